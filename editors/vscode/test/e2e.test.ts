// e2e.test.ts: end-to-end test of the real `nomec --lsp` binary, driven the way VS Code drives
// it (vscode-languageserver-protocol over the child's stdio). One session: initialize, open a
// copy of examples/funnel_cube.nome with two deliberate errors, check the diagnostics'
// ranges, codes and messages, hover on a parameter, edit (fix, break, fix again) with
// incremental changes, go to definition, find references, format, shut down and exit —
// and check that the server exits with status 0 and leaves no process behind.
//
// Usage: node out/test/e2e.test.js /path/to/nomec     (or NOMEC=/path/to/nomec)
// Every feature is its own subtest, so the report names each one that fails.
import { test } from "node:test";
import * as assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import * as fs from "node:fs";
import * as os from "node:os";
import * as path from "node:path";
import { pathToFileURL } from "node:url";
import {
  Diagnostic,
  DiagnosticSeverity,
  Hover,
  InitializeResult,
  Location,
  LocationLink,
  MarkupContent,
  Range,
  TextDocumentSyncKind,
  TextEdit,
} from "vscode-languageserver-protocol/node";
import { LspSession, allRanges, applyEdits, locate, rangeKey } from "./lsp-session";

const nomec = process.env.NOMEC ?? process.argv[2];
const repoRoot = path.resolve(__dirname, "..", "..", "..", "..");
const example = path.join(repoRoot, "examples", "funnel_cube.nome");

function replaceOnce(text: string, from: string, to: string): string {
  const at = text.indexOf(from);
  assert.ok(at >= 0 && text.indexOf(from, at + 1) < 0, `test setup: ${JSON.stringify(from)} must occur exactly once`);
  return text.slice(0, at) + to + text.slice(at + from.length);
}

function hoverText(hover: Hover): { kind: string; value: string } {
  const c = hover.contents as MarkupContent | string | Array<string | { language: string; value: string }>;
  if (typeof c === "string") return { kind: "plaintext", value: c };
  if (Array.isArray(c)) return { kind: "marked", value: c.map((m) => (typeof m === "string" ? m : m.value)).join("\n") };
  if ("kind" in c) return { kind: c.kind, value: c.value };
  return { kind: "marked", value: (c as { value: string }).value };
}

function asLocations(result: Location | Location[] | LocationLink[] | null): Location[] {
  if (result === null) return [];
  const list = Array.isArray(result) ? result : [result];
  return list.map((l) =>
    "targetUri" in l ? { uri: l.targetUri, range: l.targetSelectionRange } : (l as Location)
  );
}

function contains(outer: Range, inner: Range): boolean {
  const before = (a: { line: number; character: number }, b: { line: number; character: number }) =>
    a.line < b.line || (a.line === b.line && a.character <= b.character);
  return before(outer.start, inner.start) && before(inner.end, outer.end);
}

function summary(diags: Diagnostic[]): string {
  return JSON.stringify(diags.map((d) => ({ range: rangeKey(d.range), code: d.code, message: d.message })));
}

test("nomec --lsp end to end", { timeout: 120000 }, async (t) => {
  assert.ok(nomec, "give the nomec binary as the first argument or in $NOMEC");
  assert.ok(fs.existsSync(nomec), `no nomec binary at ${nomec}`);
  const original = fs.readFileSync(example, "utf8");

  // The document: the funnel cube with a misspelt parameter and an instance of an unknown
  // mesh. The second error follows a comment holding non-ASCII letters, so its column is
  // only right if the server counts UTF-16 code units (LSP's default), not bytes.
  const badLine = "(* größe *) instance bad nosuch endinstance";
  const opened = replaceOnce(original, "{expr $fp_ro}", "{expr $fp_rho}") + badLine + "\n";
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), "nome-e2e-"));
  const file = path.join(dir, "funnel_cube.nome");
  fs.writeFileSync(file, opened);
  const uri = pathToFileURL(file).href;

  const session = new LspSession(nomec, dir);
  let text = opened;
  let version = 1;
  let capabilities: InitializeResult["capabilities"] | undefined;
  let descendants: number[] = [];

  // Sends one didChange holding `changes` (applied in order, as LSP specifies) and returns the
  // diagnostics sequence number before it, so waits only see what came after.
  const change = (changes: Array<{ range?: Range; text: string }>): number => {
    const before = session.lastSeq;
    for (const c of changes) {
      text = c.range === undefined ? c.text : applyEdits(text, [{ range: c.range, newText: c.text }]);
    }
    version += 1;
    session.connection
      .sendNotification("textDocument/didChange", {
        textDocument: { uri, version },
        contentChanges: changes.map((c) => (c.range === undefined ? { text: c.text } : { range: c.range, text: c.text })),
      })
      .catch((err: unknown) => {
        session.stderr += `\n[didChange not sent] ${String(err)}\n`;
      });
    return before;
  };
  // The server stamps every publish with the document version it checked; waiting for this
  // version (not for a delay) makes each wait see exactly the result of the last change.
  const versionOk = (p: { version?: number }) => p.version === version;
  // Later steps need a session: without one they fail at once instead of timing out.
  const ready = () => assert.ok(capabilities, "no session: initialize failed");

  try {
    await t.test("initialize", async () => {
      const result = await session.request<InitializeResult>("initialize", {
        processId: process.pid,
        clientInfo: { name: "nomec-e2e", version: "1" },
        rootUri: pathToFileURL(dir).href,
        workspaceFolders: [{ uri: pathToFileURL(dir).href, name: "e2e" }],
        capabilities: {
          general: { positionEncodings: ["utf-16"] },
          textDocument: {
            synchronization: { dynamicRegistration: false, didSave: true },
            publishDiagnostics: { relatedInformation: true, versionSupport: true, codeDescriptionSupport: true },
            hover: { contentFormat: ["markdown", "plaintext"] },
            definition: { linkSupport: true },
            references: {},
            formatting: {},
          },
          workspace: { configuration: true, workspaceFolders: true },
          window: { workDoneProgress: false },
        },
        trace: "off",
      });
      capabilities = result.capabilities;
      assert.ok(capabilities, "initialize result has capabilities");
      const sync = capabilities.textDocumentSync;
      const kind = typeof sync === "number" ? sync : sync?.change;
      assert.equal(kind, TextDocumentSyncKind.Incremental, "incremental document sync");
      if (typeof sync === "object") assert.equal(sync.openClose, true, "open/close notifications wanted");
      const encoding = capabilities.positionEncoding;
      assert.ok(encoding === undefined || encoding === "utf-16", `position encoding ${encoding}`);
      await session.connection.sendNotification("initialized", {});
    });

    await t.test("didOpen: diagnostics at the right ranges", async () => {
      ready();
      const before = session.lastSeq;
      await session.connection.sendNotification("textDocument/didOpen", {
        textDocument: { uri, languageId: "nome", version, text },
      });
      const published = await session.waitForDiagnostics(uri, before, (d, p) => d.length > 0 && versionOk(p));
      const diags = [...published.diagnostics].sort((a, b) => a.range.start.line - b.range.start.line);
      assert.equal(diags.length, 2, `two errors expected, got ${summary(diags)}`);

      const [param, name] = diags;
      // Same place as `nomec --check`: 31:32 (1-based), i.e. line 30, character 31.
      assert.deepEqual(param.range, locate(text, "funnel fun (", "$fp_rho"));
      assert.deepEqual(param.range, Range.create(30, 31, 30, 38));
      assert.equal(param.code, "UnknownParameter");
      assert.equal(param.severity, DiagnosticSeverity.Error);
      assert.match(param.message, /unknown slider `\$fp_rho`/);
      assert.match(param.message, /did you mean `\$fp_ro`\?/);

      const nameRange = locate(text, badLine, "nosuch");
      assert.equal(nameRange.start.character, 25, "test setup: UTF-16 column of `nosuch`");
      assert.deepEqual(name.range, nameRange, "range in UTF-16 code units after `größe`");
      assert.equal(name.code, "UnknownName");
      assert.equal(name.severity, DiagnosticSeverity.Error);
      assert.match(name.message, /unknown mesh, group or generator `nosuch`/);
    });

    await t.test("hover on a parameter shows value, min and max", async () => {
      ready();
      // VS Code only sends the request when the server advertises it.
      assert.ok(capabilities!.hoverProvider, "initialize advertises hoverProvider");
      // `$fp_z` is two names: the bank `fp` and its slider `z`. Each part hovers on its own,
      // with the range of that part (what VS Code highlights), so the slider part shows the
      // slider and the bank part the bank.
      const token = locate(text, "instance fun1 fun", "$fp_z");
      const part = (from: number, to: number) =>
        Range.create(token.start.line, token.start.character + from, token.start.line, token.start.character + to);
      const slider = part(4, 5);
      const bank = part(1, 3);
      const hoverAt = (character: number) =>
        session.request<Hover | null>("textDocument/hover", {
          textDocument: { uri },
          position: { line: token.start.line, character },
        });

      const hover = await hoverAt(slider.start.character);
      assert.ok(hover, "hover result for the `z` of `$fp_z`");
      const { kind, value } = hoverText(hover);
      assert.equal(kind, "markdown", "the client asked for markdown");
      // bank fp: set z -0.8 -1.5 -0.1 0.1
      const number = (n: string) => new RegExp(`(^|[^0-9.])${n.replace(".", "\\.")}(?![0-9])`);
      assert.match(value, number("-0.8"), `value -0.8 in: ${value}`);
      assert.match(value, number("-1.5"), `min -1.5 in: ${value}`);
      assert.match(value, number("-0.1"), `max -0.1 in: ${value}`);
      assert.match(value, /\bmin/i, `the word min in: ${value}`);
      assert.match(value, /\bmax/i, `the word max in: ${value}`);
      assert.match(value, /`z`/, `the slider z in: ${value}`);
      assert.match(value, /\bfp\b/, `the bank fp in: ${value}`);
      assert.ok(hover.range, "a hover range, so VS Code highlights the hovered name");
      assert.deepEqual(hover.range, slider, `hover range ${rangeKey(hover.range)} is the slider part \`z\``);

      // The cursor just after the slider name (`$fp_z|`) still means the slider.
      const after = await hoverAt(slider.end.character);
      assert.ok(after, "hover just after `$fp_z`");
      assert.deepEqual(after.range, slider);
      assert.equal(hoverText(after).value, value);

      // The bank part: the bank, not the slider.
      const bankHover = await hoverAt(bank.start.character + 1);
      assert.ok(bankHover, "hover result for the `fp` of `$fp_z`");
      assert.ok(bankHover.range, "a hover range for the bank part");
      assert.deepEqual(bankHover.range, bank, `hover range ${rangeKey(bankHover.range)} is the bank part \`fp\``);
      assert.notEqual(hoverText(bankHover).value, value, "the bank part does not show the slider's hover");
      assert.match(hoverText(bankHover).value, /\bfp\b/, `the bank fp in: ${hoverText(bankHover).value}`);
    });

    await t.test("didChange: fixing both errors clears the diagnostics", async () => {
      ready();
      const badStart = locate(text, badLine, "(*").start;
      const before = change([
        // Two changes in one notification: the second is relative to the text after the first.
        { range: locate(text, "funnel fun (", "$fp_rho"), text: "$fp_ro" },
        { range: Range.create(badStart.line, 0, badStart.line + 1, 0), text: "" },
      ]);
      assert.equal(text, original, "test setup: the document is the example again");
      const published = await session.waitForDiagnostics(uri, before, (d, p) => d.length === 0 && versionOk(p));
      assert.deepEqual(published.diagnostics, []);
    });

    await t.test("didChange: an error typed in appears, and clears when fixed", async () => {
      ready();
      // Type `n` after `fu` in fun3's target: `fun` -> `funn`, one character at a time.
      const target = locate(text, "instance fun3 fun", "fun", 1);
      let before = change([{ range: Range.create(target.end, target.end), text: "n" }]);
      const broken = await session.waitForDiagnostics(uri, before, (d, p) => d.length > 0 && versionOk(p));
      assert.equal(broken.diagnostics.length, 1, summary(broken.diagnostics));
      const [d] = broken.diagnostics;
      assert.deepEqual(d.range, Range.create(target.start, { line: target.end.line, character: target.end.character + 1 }));
      assert.equal(d.code, "UnknownName");
      assert.match(d.message, /`funn`/);

      // Delete it again.
      before = change([{ range: Range.create(target.end, { line: target.end.line, character: target.end.character + 1 }), text: "" }]);
      assert.equal(text, original);
      const fixed = await session.waitForDiagnostics(uri, before, (dd, p) => dd.length === 0 && versionOk(p));
      assert.deepEqual(fixed.diagnostics, []);
    });

    await t.test("definition of a mesh name and of a parameter", async () => {
      ready();
      // VS Code only sends the request when the server advertises it.
      assert.ok(capabilities!.definitionProvider, "initialize advertises definitionProvider");
      const use = locate(text, "instance fun4 fun", "fun", 1);
      const defs = asLocations(
        await session.request<Location | Location[] | LocationLink[] | null>("textDocument/definition", {
          textDocument: { uri },
          position: { line: use.start.line, character: use.start.character + 1 },
        })
      );
      assert.equal(defs.length, 1, JSON.stringify(defs));
      assert.equal(defs[0].uri, uri);
      assert.deepEqual(defs[0].range, locate(text, "funnel fun (", "fun", 1), "the name in `funnel fun (`");

      const param = locate(text, "instance fun2 fun", "$fp_z");
      const pdefs = asLocations(
        await session.request<Location | Location[] | LocationLink[] | null>("textDocument/definition", {
          textDocument: { uri },
          position: { line: param.start.line, character: param.start.character + 4 },
        })
      );
      assert.equal(pdefs.length, 1, JSON.stringify(pdefs));
      assert.equal(pdefs[0].uri, uri);
      const setName = locate(text, "set     z", "z");
      assert.ok(contains(pdefs[0].range, setName), `definition ${rangeKey(pdefs[0].range)} covers \`z\` of \`set z\` at ${rangeKey(setName)}`);
      assert.equal(pdefs[0].range.start.line, pdefs[0].range.end.line, "one line: the `set` statement or its name");
    });

    await t.test("references of a mesh name and of a parameter", async () => {
      ready();
      // VS Code only sends the request when the server advertises it.
      assert.ok(capabilities!.referencesProvider, "initialize advertises referencesProvider");
      const decl = locate(text, "funnel fun (", "fun", 1);
      const uses = allRanges(text, "fun").filter((r) => r.start.line !== decl.start.line);
      assert.equal(uses.length, 6, "test setup: six instances of fun");
      const refs = async (r: Range, includeDeclaration: boolean) =>
        (await session.request<Location[] | null>("textDocument/references", {
          textDocument: { uri },
          position: r.start,
          context: { includeDeclaration },
        })) ?? [];

      const withDecl = await refs(uses[2], true);
      assert.ok(withDecl.every((l) => l.uri === uri));
      assert.deepEqual(withDecl.map((l) => rangeKey(l.range)).sort(), [decl, ...uses].map(rangeKey).sort());
      const withoutDecl = await refs(decl, false);
      assert.deepEqual(withoutDecl.map((l) => rangeKey(l.range)).sort(), uses.map(rangeKey).sort());

      // `$fp_z` is the bank `fp` and its slider `z`; references follow the part under the
      // cursor and list that part of each use (what a rename of it would edit).
      const paramUses = allRanges(text, "$fp_z");
      assert.equal(paramUses.length, 6, "test setup: six uses of $fp_z");
      const shift = (r: Range, from: number, to: number) =>
        Range.create(r.start.line, r.start.character + from, r.start.line, r.start.character + to);
      const sliderParts = paramUses.map((r) => shift(r, 4, 5));
      const setZ = locate(text, "set     z", "z");
      const sliderRefs = await refs(sliderParts[4], false);
      assert.deepEqual(sliderRefs.map((l) => rangeKey(l.range)).sort(), sliderParts.map(rangeKey).sort(), "the six `z` parts");
      const sliderRefsDecl = await refs(sliderParts[4], true);
      assert.deepEqual(
        sliderRefsDecl.map((l) => rangeKey(l.range)).sort(),
        [setZ, ...sliderParts].map(rangeKey).sort(),
        "the six `z` parts and the `z` of `set z`"
      );
      // On the `$` or on `fp`: the bank, used by every `$fp_…` in the file.
      const bankUses = ["$fp_n", "$fp_ro", "$fp_ratio", "$fp_h", "$fp_z"].flatMap((w) => allRanges(text, w)).map((r) => shift(r, 1, 3));
      assert.equal(bankUses.length, 10, "test setup: ten `$fp_…` references");
      for (const character of [paramUses[4].start.character, paramUses[4].start.character + 2]) {
        const at = Range.create(paramUses[4].start.line, character, paramUses[4].start.line, character);
        const bankRefs = await refs(at, false);
        assert.deepEqual(bankRefs.map((l) => rangeKey(l.range)).sort(), bankUses.map(rangeKey).sort(), `the bank from ${rangeKey(at)}`);
      }
    });

    await t.test("formatting: layout fixed, tokens and comments kept, idempotent", async () => {
      ready();
      // VS Code only sends the request when the server advertises it.
      assert.ok(capabilities!.documentFormattingProvider, "initialize advertises documentFormattingProvider");
      // Mess up the layout: no indentation in the bank, tabs and extra spaces in the group,
      // trailing blanks. A full-text change (allowed under incremental sync).
      const messy = text
        .replace(/^ {4}set +/gm, "set ")
        .replace(/^ {4}instance fun2 fun /m, "\t\tinstance   fun2   fun ")
        .replace(/^endbank$/m, "   endbank   ");
      assert.notEqual(messy, text, "test setup");
      let before = change([{ text: messy }]);
      await session.waitForDiagnostics(uri, before, (d, p) => d.length === 0 && versionOk(p));

      const options = { tabSize: 4, insertSpaces: true };
      const edits = (await session.request<TextEdit[] | null>("textDocument/formatting", { textDocument: { uri }, options })) ?? [];
      assert.ok(edits.length > 0, "the messy layout needs edits");
      const formatted = applyEdits(messy, edits);
      const squeeze = (s: string) => s.replace(/\s+/g, "");
      assert.equal(squeeze(formatted), squeeze(messy), "formatting changes only white space (every token and comment kept)");
      const lines = formatted.split("\n");
      assert.ok(lines.every((l) => !/[ \t]$/.test(l)), "no trailing white space");
      assert.ok(!formatted.includes("\t"), "spaces, as asked (insertSpaces)");
      for (const l of lines) {
        if (/^\s*set\b/.test(l)) assert.match(l, /^ +set /, `a set inside the bank is indented: ${JSON.stringify(l)}`);
        if (/^\s*instance fun\d/.test(l)) assert.match(l, /^ +instance fun\d fun translate/, `an instance inside the group is indented: ${JSON.stringify(l)}`);
        if (/^\s*(bank|endbank|group|endgroup|funnel)\b/.test(l)) assert.match(l, /^\S/, `top level is not indented: ${JSON.stringify(l)}`);
      }
      // One formatter for the CLI and the server: `nomec fmt` gives the same text.
      const cli = execFileSync(nomec!, ["fmt", "--indent", "4", "-"], { input: messy, encoding: "utf8" });
      assert.equal(formatted, cli, "the server formats exactly like `nomec fmt`");
      const setIndents = new Set(lines.filter((l) => /^\s*set\b/.test(l)).map((l) => l.length - l.trimStart().length));
      assert.equal(setIndents.size, 1, "every set line has the same indentation");

      // Idempotent: formatting the formatted text changes nothing.
      before = change([{ text: formatted }]);
      const clean = await session.waitForDiagnostics(uri, before, (d, p) => versionOk(p));
      assert.deepEqual(clean.diagnostics, [], "the formatted scene still checks clean");
      const again = (await session.request<TextEdit[] | null>("textDocument/formatting", { textDocument: { uri }, options })) ?? [];
      assert.equal(applyEdits(formatted, again), formatted, "formatting is idempotent");
    });

    await t.test("shutdown and exit: status 0, nothing left behind", async () => {
      ready();
      descendants = session.descendants();
      const result = await session.request<null>("shutdown", null);
      assert.equal(result, null);
      await session.connection.sendNotification("exit");
      const timeout = new Promise<"timeout">((resolve) => setTimeout(() => resolve("timeout"), 5000).unref());
      const outcome = await Promise.race([session.exited.then(() => "exited" as const), timeout]);
      assert.equal(outcome, "exited", "the server exits within 5 s of `exit`");
      assert.equal(session.exitSignal, null, `killed by a signal: ${session.exitSignal}`);
      assert.equal(session.exitCode, 0, "exit status after shutdown + exit");
      const alive = descendants.filter((pid) => fs.existsSync(`/proc/${pid}`));
      assert.deepEqual(alive, [], "no process of the server is left");
    });
  } finally {
    session.dispose();
    fs.rmSync(dir, { recursive: true, force: true });
    const failed = session.stderr.trim();
    if (failed) t.diagnostic(`server stderr:\n${failed.slice(-4000)}`);
    if (session.serverRequests.length) t.diagnostic(`server requests: ${session.serverRequests.join(", ")}`);
  }
});
