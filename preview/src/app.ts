// app.ts: the preview's controller. It asks nomec for the scene (`nome/preview`) when the
// host names a document or says it changed, moves sliders with `nome/setParameter` (one
// request in flight, the newest value waiting), keeps the last good picture while the text
// has errors, and drives the panel: sliders, pipeline, topology, diagnostics, saving.
// `window.nomePreview` exposes what the tests read (vertex hash, timings, state).
import { Viewer } from "./scene";
import {
  LspDiagnostic, Pipeline, PreviewReply, RpcError, SetParameterReply, Slider, Summary, Transport,
  VsCodeTransport, WebSocketTransport,
} from "./protocol";

declare function acquireVsCodeApi(): { postMessage(m: unknown): void };

const $ = <T extends HTMLElement>(id: string) => document.getElementById(id) as T;

interface Timing {
  parameter: string;
  roundTripMs: number;  // request sent -> reply received
  frameMs: number;      // slider input -> the new frame drawn
  applyMs: number;      // reply received -> geometry rebuilt (decoding, normals)
  drawMs: number;       // geometry rebuilt -> the frame drawn by the GPU
  serverMs: number;     // evaluation time reported by nomec
  bytes: number;        // size of the reply's text
  bufferWidth: number;  // the drawing buffer's width for this frame (smaller while dragging)
}

class App {
  private uri = "";
  private sliders: Slider[] = [];
  private inputs = new Map<string, HTMLInputElement[]>();  // slider id -> its range and number
  private moved: Record<string, number> = {};   // values the user moved, kept across reloads
  private summaries: Summary[] = [];
  private inFlight = false;
  private pending: { id: string; value: number; t0: number } | null = null;
  private previewQueued = false;
  private previewing = false;
  private fittedOnce = false;
  readonly timings: Timing[] = [];
  state = { ready: false, ok: false, version: -1, previews: 0, error: "" };
  /// Where the last full preview's time went (ms): request, slider panel, geometry, frame.
  lastPreview = { requestMs: 0, panelMs: 0, geometryMs: 0, frameMs: 0 };

  constructor(private transport: Transport, private viewer: Viewer) {
    transport.onNotification = (method, params) => {
      if (method === "nome/open") this.open(String(params.uri), params.title ? String(params.title) : undefined);
      else if (method === "nome/changed" && params.uri === this.uri) void this.preview();
      else if (method === "window/showMessage" && typeof params?.message === "string") {
        this.status(params.message, params.type === 1 || params.type === 2);
      }
    };
    transport.onClose = (reason) =>
      this.status(reason !== "" ? `Disconnected: ${reason}.` : "Disconnected from nomec view (it stopped or the file is gone).", true);
    if (transport.writeIntoFile !== undefined) $("write-values").hidden = false;
    this.wirePanel();
  }

  open(uri: string, title?: string): void {
    performance.mark("nome-open");
    if (uri !== this.uri) {
      this.uri = uri;
      this.moved = {};
      this.fittedOnce = false;
      this.sliders = [];
      this.viewer.clear();
    }
    $("title").textContent = title ?? decodeURIComponent(uri.replace(/^.*\//, ""));
    void this.preview();
  }

  pipeline(): Pipeline {
    return {
      merge: $<HTMLInputElement>("merge").checked,
      subdivide: Math.max(0, Math.min(6, Math.round(Number($<HTMLInputElement>("subdivide").value) || 0))),
      rule: $<HTMLSelectElement>("rule").value as Pipeline["rule"],
      offset: Math.max(0, Number($<HTMLInputElement>("offset").value) || 0),
    };
  }

  // One preview at a time; a request made meanwhile runs once the current one is answered.
  async preview(): Promise<void> {
    if (this.uri === "") return;
    if (this.previewing) {
      this.previewQueued = true;
      return;
    }
    this.previewing = true;
    this.status("Evaluating…");
    try {
      const t0 = performance.now();
      const reply = this.transport.request<PreviewReply>("nome/preview", {
        uri: this.uri, pipeline: this.pipeline(), values: this.moved,
      });
      this.viewer.warmUp();  // nomec works meanwhile
      const r = await reply;
      const t1 = performance.now();
      this.lastPreview = { requestMs: t1 - t0, panelMs: 0, geometryMs: 0, frameMs: 0 };
      this.state.version = r.version;
      this.state.previews++;
      this.showDiagnostics(r.diagnostics);
      if (!r.ok || r.outputs === undefined) {
        this.state.ok = false;
        const n = r.diagnostics.filter((d) => d.severity === 1).length;
        this.status(r.message ?? `The scene has ${n} error${n === 1 ? "" : "s"}; showing the last good geometry.`, true);
      } else {
        this.state.ok = true;
        this.showSliders(r.sliders ?? []);
        this.summaries = r.outputs.map((o) => o.summary);
        this.showTopology();
        const t2 = performance.now();
        // The new scene is drawn first as while dragging (fewer pixels, simpler lighting),
        // so it is seen sooner; the full picture follows once nothing else changes.
        this.viewer.interact();
        this.viewer.apply(r.outputs, r.outputs.map((o) => o.name));
        this.viewer.setView(r.view);
        $("scene-view").hidden = r.view === undefined;
        if (!this.fittedOnce) {
          // A scene with a camera is first seen through it; others are framed.
          if (!this.viewer.lookThroughScene()) this.viewer.fitView();
          this.fittedOnce = true;
        }
        const t3 = performance.now();
        await this.viewer.nextFrame();
        this.viewer.settleSoon();
        if (performance.getEntriesByName("nome-first-picture").length === 0) performance.mark("nome-first-picture");
        this.lastPreview = { requestMs: t1 - t0, panelMs: t2 - t1, geometryMs: t3 - t2, frameMs: performance.now() - t3 };
        this.status(`Version ${r.version}: ${r.outputs.length} output${r.outputs.length === 1 ? "" : "s"}.`);
      }
      this.state.ready = true;
      performance.mark("nome-ready");
    } catch (e) {
      this.fail(e);
    } finally {
      this.previewing = false;
      if (this.previewQueued) {
        this.previewQueued = false;
        void this.preview();
      }
    }
  }

  private fail(e: unknown): void {
    const err = e as RpcError;
    this.state.error = err?.message ?? String(e);
    this.status(this.state.error, true);
  }

  private status(text: string, isError = false): void {
    const s = $("status");
    s.textContent = text;
    s.classList.toggle("error", isError);
  }

  // ---- sliders ----
  private showSliders(sliders: Slider[]): void {
    const same = sliders.length === this.sliders.length &&
      sliders.every((s, i) => s.id === this.sliders[i].id && s.min === this.sliders[i].min &&
        s.max === this.sliders[i].max && s.step === this.sliders[i].step);
    this.sliders = sliders;
    const box = $("sliders");
    if (same && sliders.length > 0) {
      for (const s of sliders) this.setSliderValue(s.id, s.value);
      return;
    }
    box.textContent = "";
    this.inputs.clear();
    if (sliders.length === 0) {
      box.innerHTML = '<p class="muted">No sliders in this scene.</p>';
      return;
    }
    // One collapsible group per bank; a scene with many banks opens only the first, and a
    // closed bank's rows are made when it is first opened (thousands of sliders stay cheap).
    const banks = new Map<string, Slider[]>();
    for (const s of sliders) {
      if (!banks.has(s.bank)) banks.set(s.bank, []);
      banks.get(s.bank)!.push(s);
    }
    let first = true;
    for (const [bank, list] of banks) {
      const group = document.createElement("details");
      group.className = "bank-group";
      const summary = document.createElement("summary");
      summary.className = "bank";
      summary.textContent = `bank ${bank}`;
      group.appendChild(summary);
      const fill = () => {
        if (group.dataset.filled) return;
        group.dataset.filled = "1";
        for (const s of list) group.appendChild(this.sliderRow(this.sliders.find((x) => x.id === s.id) ?? s));
      };
      group.addEventListener("toggle", () => { if (group.open) fill(); });
      if (banks.size <= 6 || first) {
        group.open = true;
        fill();
      }
      first = false;
      box.appendChild(group);
    }
  }

  private sliderRow(s: Slider): HTMLElement {
    const row = document.createElement("div");
    row.className = "slider" + (s.listed ? "" : " unlisted");
    const key = s.id.replace(/[^A-Za-z0-9_-]/g, "_");
    const label = document.createElement("label");
    label.htmlFor = `s-${key}`;
    label.textContent = s.name;
    const range = document.createElement("input");
    range.type = "range";
    range.id = `s-${key}`;
    range.dataset.param = s.id;
    range.min = String(s.min);
    range.max = String(s.max);
    range.step = s.step > 0 ? String(s.step) : "any";
    range.value = String(s.value);
    range.setAttribute("aria-valuetext", `${s.id} = ${s.value}`);
    const num = document.createElement("input");
    num.type = "number";
    num.min = range.min;
    num.max = range.max;
    num.step = range.step;
    num.value = String(s.value);
    num.setAttribute("aria-label", `${s.id} value`);
    num.dataset.param = s.id;
    const hint = document.createElement("div");
    hint.className = "range";
    hint.textContent = `${s.min} … ${s.max}, step ${s.step}`;
    range.addEventListener("input", () => {
      num.value = range.value;
      this.move(s.id, Number(range.value));
    });
    num.addEventListener("change", () => {
      const v = Math.max(s.min, Math.min(s.max, Number(num.value)));
      num.value = String(v);
      range.value = String(v);
      this.move(s.id, v);
    });
    row.append(label, range, num, hint);
    this.inputs.set(s.id, [range, num]);
    return row;
  }

  private setSliderValue(id: string, value: number): void {
    for (const el of this.inputs.get(id) ?? []) el.value = String(value);
  }

  move(id: string, value: number): void {
    this.viewer.interact();
    this.moved[id] = value;
    this.pending = { id, value, t0: performance.now() };
    if (!this.inFlight) void this.sendMove();
  }

  private async sendMove(): Promise<void> {
    while (this.pending !== null) {
      const { id, value, t0 } = this.pending;
      this.pending = null;
      this.inFlight = true;
      const sent = performance.now();
      try {
        const r = await this.transport.request<SetParameterReply>("nome/setParameter", {
          uri: this.uri, parameter: id, value, geometry: true,
        });
        const received = performance.now();
        const bytes = this.transport.lastBytes;
        this.viewer.apply(r.outputs ?? [], r.outputNames);
        this.summaries = r.meshes;
        this.showTopology();
        this.showDiagnostics(r.diagnostics, true);
        const applied = performance.now();
        await this.viewer.nextFrame();
        const drawn = performance.now();
        this.timings.push({
          parameter: id, roundTripMs: received - sent, frameMs: drawn - t0, applyMs: applied - received,
          drawMs: drawn - applied, serverMs: r.ms, bytes: bytes >= 0 ? bytes : JSON.stringify(r).length,
          bufferWidth: this.viewer.bufferSize().width,
        });
        if (this.timings.length > 1000) this.timings.shift();
        this.status(`${id} = ${value} (${r.ms.toFixed(1)} ms in nomec)`);
      } catch (e) {
        const err = e as RpcError;
        // The text changed since the last preview: ask for the scene again with the moves.
        if (err?.message?.includes("errors")) this.status(err.message, true);
        else void this.preview();
      } finally {
        this.inFlight = false;
      }
    }
    this.viewer.settleSoon();
  }

  // ---- topology and diagnostics ----
  private showTopology(): void {
    const box = $("topology");
    box.textContent = "";
    const kShown = 12;
    for (const s of this.summaries.slice(0, kShown)) {
      const t = document.createElement("table");
      t.className = "topo";
      const cap = t.createCaption();
      cap.textContent = s.name;
      const rows: [string, string][] = [
        ["V / E / F", `${s.vertices} / ${s.edges} / ${s.faces}`],
        ["Euler characteristic", `χ = ${s.euler}`],
        ["Orientable", s.orientable ? "orientable" : "non-orientable"],
        ["Borders", String(s.border_loops)],
        ["Genus", String(s.genus)],
        ["Closed", s.closed ? "closed" : "open"],
        ["Components", String(s.components)],
      ];
      if (s.curves > 0) rows.push(["Curves", String(s.curves)]);
      for (const [k, v] of rows) {
        const tr = t.insertRow();
        const th = document.createElement("th");
        th.scope = "row";
        th.textContent = k;
        const td = tr.insertCell();
        tr.insertBefore(th, td);
        td.textContent = v;
      }
      box.appendChild(t);
    }
    const rest = this.summaries.slice(kShown);
    if (rest.length > 0) {
      const sum = (f: (x: Summary) => number) => rest.reduce((a, x) => a + f(x), 0);
      const p = document.createElement("p");
      p.className = "muted";
      p.textContent = `…and ${rest.length} more outputs: ${sum((x) => x.vertices)} / ${sum((x) => x.edges)} / ` +
        `${sum((x) => x.faces)} V / E / F, ${rest.filter((x) => !x.orientable).length} non-orientable, ` +
        `${sum((x) => x.border_loops)} borders.`;
      box.appendChild(p);
    }
  }

  private showDiagnostics(diags: LspDiagnostic[], geometryOnly = false): void {
    const list = $("diagnostics");
    if (geometryOnly && diags.length === 0) return;
    list.textContent = "";
    if (diags.length === 0) {
      const li = document.createElement("li");
      li.className = "muted";
      li.textContent = "No problems.";
      list.appendChild(li);
      return;
    }
    for (const d of diags) {
      const li = document.createElement("li");
      li.className = `sev${d.severity ?? 1}`;
      const sev = document.createElement("span");
      sev.className = "sev";
      sev.textContent = d.severity === 2 ? "warning" : d.severity === 3 ? "note" : "error";
      li.append(sev, ` ${d.range.start.line + 1}:${d.range.start.character + 1} ${d.message}`);
      list.appendChild(li);
    }
  }

  // ---- panel ----
  private wirePanel(): void {
    const toggle = (id: string, on: boolean) => $(id).setAttribute("aria-pressed", String(on));
    $("fit").onclick = () => this.viewer.fitView();
    $("scene-view").onclick = () => {
      this.viewer.setUseSceneView(!this.viewer.useSceneView);
      toggle("scene-view", this.viewer.useSceneView);
    };
    $("wire").onclick = () => {
      this.viewer.setWireframe(!this.viewer.wireframe);
      toggle("wire", this.viewer.wireframe);
    };
    $("smooth").onclick = () => {
      this.viewer.setSmooth(!this.viewer.smooth);
      toggle("smooth", this.viewer.smooth);
      $("smooth").textContent = this.viewer.smooth ? "Smooth" : "Flat";
    };
    const themes = ["auto", "light", "dark"];
    $("theme").onclick = () => {
      const cur = themes.indexOf(document.documentElement.dataset.theme ?? "auto");
      const next = themes[(cur + 1) % themes.length];
      document.documentElement.dataset.theme = next;
      document.documentElement.classList.toggle("light", next === "light");
      document.documentElement.classList.toggle("dark", next === "dark");
      $("theme").textContent = `Theme: ${next}`;
      this.applyTheme();
    };
    for (const id of ["merge", "subdivide", "rule", "offset"]) $(id).addEventListener("change", () => void this.preview());
    $("save-stl").onclick = () => this.transport.saveFile(`${this.stem()}.stl`, this.viewer.stl());
    $("save-scene").onclick = async () => {
      try {
        const r = await this.transport.request<{ text: string }>("nome/saveScene", { uri: this.uri });
        this.transport.saveFile(`${this.stem()}.saved.nome`, r.text);
      } catch (e) {
        this.fail(e);
      }
    };
    $("write-values").onclick = async () => {
      try {
        const r = await this.transport.request<{ text: string }>("nome/saveScene", { uri: this.uri });
        this.transport.writeIntoFile?.(r.text);
      } catch (e) {
        this.fail(e);
      }
    };
    $("view").addEventListener("keydown", (e: KeyboardEvent) => {
      if (this.viewer.nudge(e.key, e.shiftKey)) e.preventDefault();
    });
    document.addEventListener("keydown", (e: KeyboardEvent) => {
      const target = e.target as HTMLElement;
      if (target.tagName === "INPUT" || target.tagName === "SELECT" || e.ctrlKey || e.metaKey || e.altKey) return;
      if (e.key === "f" || e.key === "F") this.viewer.fitView();
      else if (e.key === "w" || e.key === "W") $("wire").click();
      else if (e.key === "s" || e.key === "S") $("smooth").click();
      else if ((e.key === "v" || e.key === "V") && !$("scene-view").hidden) $("scene-view").click();
    });
    window.matchMedia("(prefers-color-scheme: dark)").addEventListener("change", () => this.applyTheme());
    this.applyTheme();
  }

  applyTheme(): void {
    this.viewer.setBackground(getComputedStyle(document.body).getPropertyValue("--view").trim() || "#e9edf2");
  }

  private stem(): string {
    return decodeURIComponent(this.uri.replace(/^.*\//, "").replace(/\.[^.]*$/, "")) || "scene";
  }
}

function start(): void {
  performance.mark("nome-start");
  // Connect first: nomec starts checking the scene when the page connects, meanwhile the
  // viewer sets up WebGL.
  const vscodeApi = typeof acquireVsCodeApi === "function" ? acquireVsCodeApi() : undefined;
  const transport: Transport = vscodeApi !== undefined
    ? new VsCodeTransport(vscodeApi)
    : new WebSocketTransport(`ws://${location.host}/rpc`);
  const viewer = new Viewer($<HTMLCanvasElement>("view"));
  performance.mark("nome-viewer");
  const app = new App(transport, viewer);
  (window as any).nomePreview = {
    app, viewer, timings: app.timings,
    lastPreview: () => app.lastPreview,
    state: app.state,
    vertexHash: () => viewer.vertexHash(),
    move: (id: string, value: number) => app.move(id, value),
  };
  // The VS Code host names the document once the app listens.
  vscodeApi?.postMessage({ type: "ready" });
}

start();
