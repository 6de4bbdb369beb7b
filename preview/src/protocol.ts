// protocol.ts: the JSON-RPC messages the preview exchanges with nomec (see lsp/README.md,
// "Live preview"), the decoding of their base64 typed arrays, and the transports: a
// WebSocket to `nomec view`, or the VS Code webview's message channel to the extension,
// which relays requests to the running language server.

export interface Summary {
  name: string;
  vertices: number;
  edges: number;
  faces: number;
  euler: number;
  orientable: boolean;
  border_loops: number;
  genus: number;
  components: number;
  closed: boolean;
  curves: number;
  bounding_box: { min: number[]; max: number[] } | null;
  position_hash: string;
}

export interface WireGeometry {
  positions: string;
  triangles?: string;
  triangleFaces?: string;
  faceColors?: string | null;
  edges?: string;
  borderEdges?: string;
  mobiusEdges?: string;
  curvePoints?: string;
  curveSegments?: string;
}

export interface WireOutput {
  name: string;
  summary: Summary;
  positionsOnly: boolean;
  geometry: WireGeometry;
}

export interface Slider {
  id: string;
  bank: string;
  name: string;
  value: number;
  min: number;
  max: number;
  step: number;
  listed: boolean;
}

export interface Pipeline {
  merge: boolean;
  subdivide: number;
  rule: "catmull-clark" | "derose";
  offset: number;
}

export interface LspDiagnostic {
  range: { start: { line: number; character: number }; end: { line: number; character: number } };
  severity?: number;
  code?: string;
  message: string;
}

/// The scene's viewing set-up (SLIDE `render` camera and lights, window background; see
/// lsp/README.md): positions and directions in world coordinates, colours in [0, 1].
export interface ViewCamera {
  name: string;
  position: number[];
  direction: number[];
  up: number[];
  projection: "parallel" | "perspective";
  frustum: { min: number[]; max: number[] };
}

export interface ViewLight {
  name: string;
  type: "ambient" | "directional" | "point" | "spot";
  color: number[];
  position: number[];
  direction: number[];
  on: boolean;
}

export interface SceneView {
  camera?: ViewCamera;
  lights: ViewLight[];
  background?: number[];
}

export interface PreviewReply {
  uri: string;
  version: number;
  ok: boolean;
  message?: string;
  pipeline: Pipeline;
  sliders?: Slider[];
  files?: string[];
  outputs?: WireOutput[];
  view?: SceneView;
  diagnostics: LspDiagnostic[];
}

export interface SetParameterReply {
  uri: string;
  version: number;
  parameter: string;
  value: number;
  ms: number;
  meshes: Summary[];
  outputs?: WireOutput[];
  outputNames?: string[];
  diagnostics: LspDiagnostic[];
}

function bytes(b64: string): Uint8Array {
  const bin = atob(b64);
  const out = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; ++i) out[i] = bin.charCodeAt(i);
  return out;
}

export function float32s(b64: string): Float32Array {
  const b = bytes(b64);
  return new Float32Array(b.buffer, b.byteOffset, b.byteLength / 4);
}

export function uint32s(b64: string | undefined): Uint32Array {
  if (b64 === undefined) return new Uint32Array(0);
  const b = bytes(b64);
  return new Uint32Array(b.buffer, b.byteOffset, b.byteLength / 4);
}

export function uint8s(b64: string | null | undefined): Uint8Array | null {
  return b64 === null || b64 === undefined ? null : bytes(b64);
}

export interface RpcError {
  code: number;
  message: string;
}

type Handler = (method: string, params: any) => void;

// One JSON-RPC peer over a channel that carries JSON texts or objects.
export abstract class Transport {
  private nextId = 1;
  private pending = new Map<number, { resolve: (v: any) => void; reject: (e: RpcError) => void }>();
  onNotification: Handler = () => {};
  /// The channel closed; `reason` is the host's, when it gave one (`nomec view` refusing a
  /// page past its limits).
  onClose: (reason: string) => void = () => {};
  /// The size of the last message's text, when the channel carries text (-1 otherwise).
  lastBytes = -1;

  request<T>(method: string, params: unknown): Promise<T> {
    const id = this.nextId++;
    return new Promise<T>((resolve, reject) => {
      this.pending.set(id, { resolve, reject });
      this.post({ jsonrpc: "2.0", id, method, params });
    });
  }

  protected receive(message: any): void {
    if (message === null || typeof message !== "object") return;
    if ("id" in message && !("method" in message)) {
      const p = this.pending.get(message.id);
      if (p === undefined) return;
      this.pending.delete(message.id);
      if (message.error !== undefined) p.reject(message.error as RpcError);
      else p.resolve(message.result);
    } else if (typeof message.method === "string") {
      this.onNotification(message.method, message.params);
    }
  }

  protected failAll(message: string): void {
    for (const p of this.pending.values()) p.reject({ code: -32099, message });
    this.pending.clear();
  }

  protected abstract post(message: unknown): void;
  /// Saves bytes the user asked for ("Save as STL", "Save scene").
  abstract saveFile(name: string, data: Uint8Array | string): void;
  /// Writes the saved scene into the edited file (VS Code only).
  writeIntoFile?(text: string): void;
}

export class WebSocketTransport extends Transport {
  private ws: WebSocket;
  constructor(url: string) {
    super();
    this.ws = new WebSocket(url);
    this.ws.onmessage = (e) => {
      const text = String(e.data);
      this.lastBytes = text.length;
      this.receive(JSON.parse(text));
    };
    this.ws.onclose = (e: CloseEvent) => {
      this.failAll(e.reason || "the connection to nomec view closed");
      this.onClose(e.reason);
    };
  }
  private queue: string[] = [];
  protected post(message: unknown): void {
    const text = JSON.stringify(message);
    if (this.ws.readyState === WebSocket.OPEN) this.ws.send(text);
    else {
      this.queue.push(text);
      this.ws.onopen = () => {
        for (const t of this.queue) this.ws.send(t);
        this.queue = [];
      };
    }
  }
  saveFile(name: string, data: Uint8Array | string): void {
    const blob = new Blob([data as BlobPart], { type: typeof data === "string" ? "text/plain" : "application/octet-stream" });
    const a = document.createElement("a");
    a.href = URL.createObjectURL(blob);
    a.download = name;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  }
}

interface VsCodeApi {
  postMessage(message: unknown): void;
}

export class VsCodeTransport extends Transport {
  constructor(private api: VsCodeApi) {
    super();
    window.addEventListener("message", (e: MessageEvent) => {
      const m = e.data;
      if (m && m.type === "rpc") this.receive(m.message);
    });
  }
  protected post(message: unknown): void {
    this.api.postMessage({ type: "rpc", message });
  }
  saveFile(name: string, data: Uint8Array | string): void {
    let text: string;
    if (typeof data === "string") text = data;
    else {
      let s = "";
      for (let i = 0; i < data.length; i += 0x8000) s += String.fromCharCode(...data.subarray(i, i + 0x8000));
      text = btoa(s);
    }
    this.api.postMessage({ type: "saveFile", name, base64: typeof data !== "string", data: text });
  }
  writeIntoFile(text: string): void {
    this.api.postMessage({ type: "writeIntoFile", text });
  }
}
