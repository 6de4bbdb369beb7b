// lsp-session.ts: a small LSP client for tests. It spawns the real `nomec --lsp` binary and
// talks to it over stdio through vscode-languageserver-protocol / vscode-jsonrpc (the same
// protocol library VS Code's client uses), records every published diagnostic, answers the
// requests a server may send to a client, and keeps the server's stderr for failure reports.
import { ChildProcess, spawn } from "node:child_process";
import * as fs from "node:fs";
import {
  createProtocolConnection,
  ProtocolConnection,
  StreamMessageReader,
  StreamMessageWriter,
  PublishDiagnosticsNotification,
  PublishDiagnosticsParams,
  Diagnostic,
  Position,
  Range,
  TextEdit,
} from "vscode-languageserver-protocol/node";

export interface Published {
  params: PublishDiagnosticsParams;
  seq: number; // order of arrival over the whole session
}

export class LspSession {
  readonly child: ChildProcess;
  readonly connection: ProtocolConnection;
  readonly published: Published[] = [];
  readonly serverRequests: string[] = [];
  readonly logMessages: string[] = [];
  stderr = "";
  exitCode: number | null = null;
  exitSignal: NodeJS.Signals | null = null;
  readonly exited: Promise<void>;
  private seq = 0;
  private waiters: Array<() => void> = [];

  constructor(nomec: string, cwd: string) {
    this.child = spawn(nomec, ["--lsp"], { cwd, stdio: ["pipe", "pipe", "pipe"] });
    this.exited = new Promise((resolve) => {
      this.child.on("exit", (code, signal) => {
        this.exitCode = code;
        this.exitSignal = signal;
        resolve();
        this.wake();
      });
    });
    this.child.on("error", (err) => {
      this.stderr += `\n[spawn error] ${String(err)}\n`;
    });
    this.child.stderr!.setEncoding("utf8");
    this.child.stderr!.on("data", (chunk: string) => {
      // Bounded: a chatty server must not make the test itself use unbounded memory.
      if (this.stderr.length < 1 << 20) this.stderr += chunk;
    });
    this.connection = createProtocolConnection(
      new StreamMessageReader(this.child.stdout!),
      new StreamMessageWriter(this.child.stdin!)
    );
    this.connection.onNotification(PublishDiagnosticsNotification.type, (params) => {
      this.published.push({ params, seq: ++this.seq });
      this.wake();
    });
    this.connection.onNotification("window/logMessage", (params: { message: string }) => {
      this.logMessages.push(params.message);
    });
    // Requests a server may make of its client (configuration, dynamic registration, progress,
    // refreshes); any other request gets the protocol's MethodNotFound error.
    const answers: Record<string, (params: unknown) => unknown> = {
      "workspace/configuration": (params) => ((params as { items?: unknown[] }).items ?? []).map(() => null),
      "workspace/workspaceFolders": () => null,
      "client/registerCapability": () => null,
      "client/unregisterCapability": () => null,
      "window/workDoneProgress/create": () => null,
      "window/showMessageRequest": () => null,
      "workspace/applyEdit": () => ({ applied: false, failureReason: "the test client applies no edits" }),
      "workspace/semanticTokens/refresh": () => null,
      "workspace/inlayHint/refresh": () => null,
      "workspace/codeLens/refresh": () => null,
      "workspace/diagnostic/refresh": () => null,
    };
    for (const [method, answer] of Object.entries(answers)) {
      this.connection.onRequest(method, (params: unknown) => {
        this.serverRequests.push(method);
        return answer(params);
      });
    }
    this.connection.onError(([err]) => {
      this.stderr += `\n[connection error] ${String(err)}\n`;
    });
    this.connection.listen();
  }

  private wake(): void {
    const waiters = this.waiters;
    this.waiters = [];
    for (const w of waiters) w();
  }

  get lastSeq(): number {
    return this.seq;
  }

  // Resolves with the first diagnostics published for `uri` after sequence number `after` that
  // satisfy `accept`; rejects after `timeoutMs`, showing what was published meanwhile.
  async waitForDiagnostics(
    uri: string,
    after: number,
    accept: (diags: Diagnostic[], params: PublishDiagnosticsParams) => boolean,
    timeoutMs = 30000
  ): Promise<PublishDiagnosticsParams> {
    const deadline = Date.now() + timeoutMs;
    for (;;) {
      const found = this.published.find(
        (p) => p.seq > after && p.params.uri === uri && accept(p.params.diagnostics, p.params)
      );
      if (found) return found.params;
      if (this.exitCode !== null || this.exitSignal !== null) {
        throw new Error(`server exited (code ${this.exitCode}, signal ${this.exitSignal}) while waiting for diagnostics`);
      }
      const left = deadline - Date.now();
      if (left <= 0) {
        const seen = this.published
          .filter((p) => p.seq > after && p.params.uri === uri)
          .map((p) => JSON.stringify(p.params));
        throw new Error(
          `no matching diagnostics for ${uri} within ${timeoutMs} ms; published since: ` +
            (seen.length ? seen.join("\n") : "(nothing)")
        );
      }
      await new Promise<void>((resolve) => {
        const timer = setTimeout(resolve, Math.min(left, 250));
        this.waiters.push(() => {
          clearTimeout(timer);
          resolve();
        });
      });
    }
  }

  // A request that fails the test instead of hanging when the server never answers.
  async request<R>(method: string, params: unknown, timeoutMs = 30000): Promise<R> {
    let timer: NodeJS.Timeout | undefined;
    const timeout = new Promise<never>((_, reject) => {
      timer = setTimeout(
        () => reject(new Error(`${method}: no answer within ${timeoutMs} ms`)),
        timeoutMs
      );
    });
    try {
      return await Promise.race([this.connection.sendRequest<R>(method, params), timeout]);
    } finally {
      clearTimeout(timer);
    }
  }

  // The process ids of the server and every process below it, from /proc (Linux).
  descendants(): number[] {
    const root = this.child.pid;
    if (root === undefined || !fs.existsSync("/proc")) return [];
    const parentOf = new Map<number, number>();
    for (const entry of fs.readdirSync("/proc")) {
      if (!/^\d+$/.test(entry)) continue;
      try {
        const stat = fs.readFileSync(`/proc/${entry}/stat`, "utf8");
        // Field 4 (ppid) follows the parenthesised command name, which may contain spaces.
        const rest = stat.slice(stat.lastIndexOf(")") + 2).split(" ");
        parentOf.set(Number(entry), Number(rest[1]));
      } catch {
        // The process ended while we looked.
      }
    }
    const found = [root];
    for (let i = 0; i < found.length; i++) {
      for (const [pid, ppid] of parentOf) if (ppid === found[i]) found.push(pid);
    }
    return found;
  }

  dispose(): void {
    this.connection.dispose();
    if (this.exitCode === null && this.exitSignal === null) this.child.kill("SIGKILL");
  }
}

// ---- Text helpers (LSP positions are UTF-16 code units, which JS strings index natively) ----

export function lineOf(text: string, line: number): string {
  return text.split("\n")[line] ?? "";
}

// The range of the `occurrence`-th (0-based) `token` on the first line containing `lineNeedle`.
export function locate(text: string, lineNeedle: string, token: string, occurrence = 0): Range {
  const lines = text.split("\n");
  const line = lines.findIndex((l) => l.includes(lineNeedle));
  if (line < 0) throw new Error(`test setup: no line contains ${JSON.stringify(lineNeedle)}`);
  let character = -1;
  for (let i = 0; i <= occurrence; i++) {
    character = lines[line].indexOf(token, character + 1);
    if (character < 0) throw new Error(`test setup: ${JSON.stringify(token)} #${occurrence} not on line ${line}`);
  }
  return Range.create(line, character, line, character + token.length);
}

// Every range of `token` as a whole word (not part of a longer name) in `text`, outside
// `#` comments (enough for the scenes these tests use, which have no `#` in strings).
export function allRanges(text: string, token: string): Range[] {
  const out: Range[] = [];
  text.split("\n").forEach((full, line) => {
    const hash = full.indexOf("#");
    const l = hash < 0 ? full : full.slice(0, hash);
    let at = l.indexOf(token);
    while (at >= 0) {
      const before = at > 0 ? l[at - 1] : " ";
      const after = l[at + token.length] ?? " ";
      if (!/[A-Za-z0-9_.$]/.test(before) && !/[A-Za-z0-9_.]/.test(after)) {
        out.push(Range.create(line, at, line, at + token.length));
      }
      at = l.indexOf(token, at + 1);
    }
  });
  return out;
}

export function offsetAt(text: string, pos: Position): number {
  const lines = text.split("\n");
  let offset = 0;
  for (let i = 0; i < pos.line; i++) offset += lines[i].length + 1;
  return offset + pos.character;
}

// Applies LSP text edits (non-overlapping, all relative to the original text) to `text`.
export function applyEdits(text: string, edits: TextEdit[]): string {
  const sorted = edits
    .map((e) => ({ start: offsetAt(text, e.range.start), end: offsetAt(text, e.range.end), newText: e.newText }))
    .sort((a, b) => b.start - a.start || b.end - a.end);
  let out = text;
  let limit = Infinity;
  for (const e of sorted) {
    if (e.end > limit) throw new Error("overlapping text edits from the server");
    out = out.slice(0, e.start) + e.newText + out.slice(e.end);
    limit = e.start;
  }
  return out;
}

export function rangeKey(r: Range): string {
  return `${r.start.line}:${r.start.character}-${r.end.line}:${r.end.character}`;
}
