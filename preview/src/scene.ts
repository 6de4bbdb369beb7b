// scene.ts: the three.js side of the preview. Each output mesh gives a shaded surface, a
// wireframe of the polygon edges (not the triangle diagonals), its border edges and its
// Möbius edges. The surface is drawn indexed: one drawn vertex per mesh vertex, side of its
// fan and face colour (see `Topology`), so the GPU shades each vertex once instead of once
// per triangle corner; smooth normals are averaged over each vertex's fan with the signs
// that orient the fan consistently, so Möbius and Klein surfaces shade smoothly too, and
// flat shading takes the face normal in the fragment shader. An update recomputes only the
// outputs it names; all outputs are then drawn as five objects (surfaces, wireframe,
// borders, Möbius edges, curves), so a scene of hundreds of outputs costs five draw calls,
// not hundreds. Orbit, pan and zoom by mouse or keyboard; "fit view" frames everything. A
// scene that sets up viewing (a SLIDE `render`: camera, lights, window background) is first
// shown through its camera (perspective or parallel), lit by its lights on its background;
// "fit view" then looks along that camera, and the Scene view toggle goes back to the
// preview's own lights and theme background.
import * as THREE from "three";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
import { LineSegments2 } from "three/examples/jsm/lines/LineSegments2.js";
import { LineSegmentsGeometry } from "three/examples/jsm/lines/LineSegmentsGeometry.js";
import { LineMaterial } from "three/examples/jsm/lines/LineMaterial.js";
import { SceneView, WireOutput, float32s, uint32s, uint8s } from "./protocol";
import { Drawn, buildDrawn, placeDrawn } from "./drawn";

interface Part {
  name: string;
  positions: Float32Array;
  triangles: Uint32Array;
  triangleFaces: Uint32Array;
  faceColors: Uint8Array | null;
  edges: Uint32Array;
  borderEdges: Uint32Array;
  mobiusEdges: Uint32Array;
  curvePoints: Float32Array;    // the output's polylines and curves
  curveSegments: Uint32Array;   // point index pairs
  // What the surface draws: shared vertices (see drawn.ts) with positions and normals.
  drawn: Drawn;
  drawPositions: Float32Array;
  drawNormals: Float32Array;
}

// Line segments drawn fat (LineSegments2, a few pixels wide) at rest and one pixel wide
// while a slider is dragged: a fat line is a quad per segment with its own shaders, which a
// software renderer pays dearly for when a scene has thousands of border edges.
class Overlay {
  readonly fat: LineSegments2;
  readonly thin: THREE.LineSegments;
  /// Whether there is anything to draw.
  present = false;

  constructor(readonly material: LineMaterial, order: number) {
    this.fat = new LineSegments2(new LineSegmentsGeometry(), material);
    this.thin = new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: material.color }));
    this.fat.renderOrder = order;
    this.thin.renderOrder = order;
    this.fat.visible = this.thin.visible = false;
  }

  /// Segment end points, two per segment.
  set(ends: Float32Array): void {
    this.fat.geometry.dispose();
    const g = new LineSegmentsGeometry();
    if (ends.length > 0) g.setPositions(ends);
    this.fat.geometry = g;
    this.thin.geometry.dispose();
    const t = new THREE.BufferGeometry();
    t.setAttribute("position", new THREE.BufferAttribute(ends, 3));
    this.thin.geometry = t;
    this.present = ends.length > 0;
  }

  show(dragging: boolean): void {
    this.fat.visible = this.present && !dragging;
    this.thin.visible = this.present && dragging;
  }
}

export class Viewer {
  readonly renderer: THREE.WebGLRenderer;
  readonly scene = new THREE.Scene();
  readonly perspective = new THREE.PerspectiveCamera(40, 1, 0.01, 1000);
  readonly ortho = new THREE.OrthographicCamera(-1, 1, 1, -1, 0.01, 1000);
  /// The camera drawn through: `perspective`, or `ortho` for a scene's parallel camera.
  camera: THREE.PerspectiveCamera | THREE.OrthographicCamera = this.perspective;
  /// Half the height the orthographic camera shows at zoom 1.
  private orthoHalfHeight = 1;
  controls: OrbitControls;
  private aspect = 1;
  // The preview's own lights (a sky light and a key light that follows the camera), and the
  // scene's when it has any (`setView`).
  private key = new THREE.DirectionalLight(0xffffff, 1.6);
  private defaultLights: THREE.Object3D[] = [];
  private sceneLights = new THREE.Group();
  /// The scene's viewing set-up, if it has one.
  view: SceneView | undefined;
  /// Whether the scene's camera, lights and background are used (the Scene view toggle).
  useSceneView = true;
  private themeBackground = "#e9edf2";
  private parts = new Map<string, Part>();
  private surface: THREE.Mesh;
  private wire: THREE.LineSegments;
  private border: Overlay;
  private mobius: Overlay;
  private curves: Overlay;
  private surfaceMaterial = new THREE.MeshStandardMaterial({
    vertexColors: true,
    side: THREE.DoubleSide,
    roughness: 0.55,
    metalness: 0.05,
    polygonOffset: true,
    polygonOffsetFactor: 1,
    polygonOffsetUnits: 1,
  });
  // While a slider is dragged: diffuse lighting only, a fraction of the standard material's
  // cost per pixel on a software renderer.
  private dragMaterial = new THREE.MeshLambertMaterial({
    vertexColors: true,
    side: THREE.DoubleSide,
    polygonOffset: true,
    polygonOffsetFactor: 1,
    polygonOffsetUnits: 1,
  });
  private wireMaterial = new THREE.LineBasicMaterial({ color: 0x1d2330, transparent: true, opacity: 0.55 });
  // Borders and Möbius edges are drawn 3 pixels wide so they read at a glance.
  private borderMaterial = new LineMaterial({ color: 0xff7a00, linewidth: 3 });
  private mobiusMaterial = new LineMaterial({ color: 0xd0208f, linewidth: 3.5 });
  private curveMaterial = new LineMaterial({ color: 0x1f6feb, linewidth: 2.5 });
  smooth = true;
  wireframe = true;
  private frameWaiters: (() => void)[] = [];
  private probe = new Uint8Array(4);
  private needsRender = true;
  // While a slider is dragged (and for the first frame of a new scene) the frame is drawn
  // with fewer pixels, diffuse lighting, one-pixel borders and no wireframe (a software
  // renderer's cost is mostly per pixel and per fat line); the frame after the drag settles
  // is drawn at full resolution with every overlay, as at rest.
  private interacting = false;
  private settleTimer: ReturnType<typeof setTimeout> | undefined;
  /// Share of the full resolution (per axis) used while dragging: a step of `dragSteps`,
  /// half on a software renderer to start with, full on a GPU; with `adaptiveDrag` each
  /// synchronised drag frame that takes longer than `dragBudgetMs` to draw steps it down,
  /// one that takes less than half of it steps it up (a slow machine trades pixels for
  /// smoothness, a fast one draws every pixel).
  dragScale = Viewer.softwareGl() ? 0.5 : 1;
  adaptiveDrag = true;
  dragBudgetMs = 12;
  static readonly dragSteps = [0.25, 0.35, 0.5, 0.7, 1];
  /// Quiet time after the last slider move before the full-resolution frame.
  settleMs = 200;
  private fullPixelRatio = 1;

  constructor(readonly canvas: HTMLCanvasElement) {
    // Multisampling is free on a GPU but quadruples the work of a software renderer
    // (SwiftShader, as in headless Chromium or a machine without a GPU).
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: !Viewer.softwareGl(), preserveDrawingBuffer: true });
    this.fullPixelRatio = Math.min(window.devicePixelRatio, 2);
    this.renderer.setPixelRatio(this.fullPixelRatio);
    this.camera.position.set(3, 2.5, 4);
    this.controls = this.makeControls();
    const sky = new THREE.HemisphereLight(0xffffff, 0x445066, 1.6);
    this.scene.add(sky);
    this.key.position.set(2, 3, 4);
    this.camera.add(this.key);
    this.defaultLights = [sky, this.key];
    this.scene.add(this.camera, this.sceneLights);
    this.surface = new THREE.Mesh(new THREE.BufferGeometry(), this.surfaceMaterial);
    this.wire = new THREE.LineSegments(new THREE.BufferGeometry(), this.wireMaterial);
    this.border = new Overlay(this.borderMaterial, 2);
    this.mobius = new Overlay(this.mobiusMaterial, 3);
    this.curves = new Overlay(this.curveMaterial, 0);
    this.scene.add(this.surface, this.wire);
    for (const o of [this.border, this.mobius, this.curves]) this.scene.add(o.fat, o.thin);
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
    const loop = () => {
      if (this.needsRender) this.draw();
      requestAnimationFrame(loop);
    };
    requestAnimationFrame(loop);
  }

  // Draws the frame now, in the dragging or the resting mode, and answers whoever waits for
  // it once the GPU has drawn it (not only when the commands were sent).
  private draw(): void {
    this.needsRender = false;
    const ratio = this.interacting ? this.fullPixelRatio * this.dragScale : this.fullPixelRatio;
    if (this.renderer.getPixelRatio() !== ratio) this.renderer.setPixelRatio(ratio);
    this.wire.visible = this.wireframe && !this.interacting;
    this.surface.material = this.interacting ? this.dragMaterial : this.surfaceMaterial;
    for (const o of [this.border, this.mobius, this.curves]) o.show(this.interacting);
    const t0 = performance.now();
    this.renderer.render(this.scene, this.camera);
    if (this.frameWaiters.length > 0) {
      const gl = this.renderer.getContext();
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, this.probe);
      if (this.interacting && this.adaptiveDrag) this.adaptDragScale(performance.now() - t0);
    }
    const waiters = this.frameWaiters;
    this.frameWaiters = [];
    for (const w of waiters) w();
    if (!this.interacting && this.parts.size > 0 && !this.fullPictureMarked) {
      this.fullPictureMarked = true;
      performance.mark("nome-first-full-picture");  // the first picture drawn at rest
    }
  }
  private fullPictureMarked = false;

  // The next drag frame's resolution from the time this one took (render and GPU sync).
  private adaptDragScale(ms: number): void {
    const steps = Viewer.dragSteps;
    let i = steps.findIndex((s) => s >= this.dragScale);
    if (i < 0) i = steps.length - 1;
    if (ms > this.dragBudgetMs && i > 0) this.dragScale = steps[i - 1];
    else if (ms < this.dragBudgetMs / 2 && i < steps.length - 1) this.dragScale = steps[i + 1];
  }

  /// Compiles every material's shaders now, while the first scene is being evaluated by
  /// nomec (another process), instead of when the first picture is drawn.
  warmUp(): void {
    if (this.parts.size > 0) return;
    const tri = new THREE.BufferGeometry();
    tri.setAttribute("position", new THREE.BufferAttribute(new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]), 3));
    tri.setAttribute("normal", new THREE.BufferAttribute(new Float32Array([0, 0, 1, 0, 0, 1, 0, 0, 1]), 3));
    tri.setAttribute("color", new THREE.BufferAttribute(new Float32Array(9).fill(0.5), 3));
    tri.setIndex([0, 1, 2]);
    const fat = new LineSegmentsGeometry();
    fat.setPositions([0, 0, 0, 1, 0, 0]);
    const probes: THREE.Object3D[] = [
      new THREE.Mesh(tri, this.surfaceMaterial), new THREE.Mesh(tri, this.dragMaterial),
      new THREE.LineSegments(tri, this.wireMaterial), new LineSegments2(fat, this.borderMaterial),
      new LineSegments2(fat, this.mobiusMaterial), new LineSegments2(fat, this.curveMaterial),
      new THREE.LineSegments(tri, this.border.thin.material),
    ];
    this.scene.add(...probes);
    this.renderer.compile(this.scene, this.camera);
    this.scene.remove(...probes);
    tri.dispose();
    fat.dispose();
  }

  static softwareGl(): boolean {
    try {
      const gl = document.createElement("canvas").getContext("webgl2");
      const info = gl?.getExtension("WEBGL_debug_renderer_info");
      const name = info ? String(gl!.getParameter(info.UNMASKED_RENDERER_WEBGL)) : "";
      return /swiftshader|llvmpipe|software/i.test(name);
    } catch {
      return false;
    }
  }

  // Orbit controls for the current camera (made anew when the camera or its up changes:
  // OrbitControls reads the up direction once).
  private makeControls(): OrbitControls {
    const c = new OrbitControls(this.camera, this.canvas);
    c.enableDamping = false;
    c.addEventListener("change", () => this.requestRender());
    return c;
  }

  /// The theme's background colour (CSS), shown unless the scene sets its own.
  setBackground(css: string): void {
    this.themeBackground = css;
    this.showBackground();
  }

  private showBackground(): void {
    const bg = this.useSceneView ? this.view?.background : undefined;
    this.scene.background = bg !== undefined
      ? new THREE.Color().setRGB(bg[0], bg[1], bg[2], THREE.SRGBColorSpace)
      : new THREE.Color(this.themeBackground);
    this.requestRender();
  }

  /// Takes the scene's viewing set-up (or none): its lights and background are used at once
  /// (while `useSceneView`); its camera by `lookThroughScene`.
  setView(view: SceneView | undefined): void {
    this.view = view;
    this.showLights();
    this.showBackground();
  }

  /// Uses the scene's camera, lights and background, or the preview's own.
  setUseSceneView(on: boolean): void {
    this.useSceneView = on;
    this.showLights();
    this.showBackground();
    if (!on || !this.lookThroughScene()) {
      this.useCamera(this.perspective, new THREE.Vector3(0, 1, 0));
      this.fitView();
    }
  }

  // The scene's lights that are on replace the preview's own; colours as written, with
  // three.js's physical intensities (π gives the colour's full brightness).
  private showLights(): void {
    for (const l of [...this.sceneLights.children]) {
      this.sceneLights.remove(l);
      (l as THREE.Light).dispose?.();
    }
    const lights = this.useSceneView ? (this.view?.lights ?? []).filter((l) => l.on) : [];
    for (const d of this.defaultLights) d.visible = lights.length === 0;
    for (const l of lights) {
      const color = new THREE.Color().setRGB(l.color[0], l.color[1], l.color[2], THREE.SRGBColorSpace);
      const [px, py, pz] = l.position;
      const [dx, dy, dz] = l.direction;
      let light: THREE.Light;
      if (l.type === "ambient") {
        light = new THREE.AmbientLight(color, Math.PI);
      } else if (l.type === "directional") {
        const d = new THREE.DirectionalLight(color, Math.PI);
        d.position.set(-dx, -dy, -dz);  // shines from here towards its target at the origin
        light = d;
      } else if (l.type === "point") {
        light = new THREE.PointLight(color, Math.PI, 0, 0);
        light.position.set(px, py, pz);
      } else {
        const spot = new THREE.SpotLight(color, Math.PI, 0, Math.PI / 6, 0.3, 0);
        spot.position.set(px, py, pz);
        spot.target.position.set(px + dx, py + dy, pz + dz);
        this.sceneLights.add(spot.target);
        light = spot;
      }
      light.name = l.name;
      this.sceneLights.add(light);
    }
    this.requestRender();
  }

  // Draws through `cam` (with `up`), keeping the key light on it.
  private useCamera(cam: THREE.PerspectiveCamera | THREE.OrthographicCamera, up: THREE.Vector3): void {
    const target = this.controls.target.clone();
    if (cam !== this.camera) {
      cam.position.copy(this.camera.position);
      this.scene.remove(this.camera);
      this.camera = cam;
      this.scene.add(cam);
      cam.add(this.key);
    }
    cam.up.copy(up);
    this.controls.dispose();
    this.controls = this.makeControls();
    this.controls.target.copy(target);
    this.resize();
  }

  /// Looks through the scene's camera: its position, direction and up, perspective with the
  /// field of view its frustum gives, or parallel showing its frustum's extent. The orbit
  /// centre is where the line of sight passes the geometry. The frustum's x and y bounds are
  /// read on the plane one unit in front of the camera (SLIDE's projection plane); the near
  /// and far planes are the preview's, so orbiting never clips. False without a camera.
  lookThroughScene(): boolean {
    const v = this.useSceneView ? this.view?.camera : undefined;
    if (v === undefined) return false;
    const pos = new THREE.Vector3(...v.position);
    const dir = new THREE.Vector3(...v.direction).normalize();
    const up = new THREE.Vector3(...v.up).normalize();
    const halfW = Math.abs(v.frustum.max[0] - v.frustum.min[0]) / 2;
    const halfH = Math.abs(v.frustum.max[1] - v.frustum.min[1]) / 2;
    // Wide enough for the frustum's width and height in this canvas.
    const half = Math.max(halfH, halfW / this.aspect) || 1;
    const sphere = this.bounds();
    const r = sphere ? sphere.radius : 1;
    let d = sphere ? sphere.center.clone().sub(pos).dot(dir) : 1;
    if (!(d > 1e-6)) d = Math.max(sphere ? sphere.center.distanceTo(pos) : 1, 1e-3);
    if (v.projection === "perspective") {
      this.useCamera(this.perspective, up);
      this.perspective.fov = THREE.MathUtils.radToDeg(2 * Math.atan(half));
      this.perspective.near = Math.max(1e-4, d / 100);
      this.perspective.far = (d + r) * 100;
    } else {
      this.orthoHalfHeight = half;
      this.useCamera(this.ortho, up);
      this.ortho.zoom = 1;
      this.ortho.near = -(d + r) * 10;
      this.ortho.far = (d + r) * 10;
    }
    this.camera.position.copy(pos);
    this.controls.target.copy(pos).addScaledVector(dir, d);
    this.camera.lookAt(this.controls.target);
    this.resize();
    this.controls.update();
    this.requestRender();
    return true;
  }

  // The bounding sphere of everything drawn, or undefined when nothing is.
  private bounds(): THREE.Sphere | undefined {
    const box = new THREE.Box3().setFromObject(this.surface);
    if (this.curves.present) {
      this.curves.thin.geometry.computeBoundingBox();
      if (this.curves.thin.geometry.boundingBox) box.union(this.curves.thin.geometry.boundingBox);
    }
    if (this.parts.size === 0 || box.isEmpty()) return undefined;
    return box.getBoundingSphere(new THREE.Sphere());
  }

  requestRender(): void {
    this.needsRender = true;
  }

  /// A slider moved: frames are drawn cheaply until `settleSoon` is followed by
  /// `settleMs` without another move.
  interact(): void {
    if (this.settleTimer !== undefined) clearTimeout(this.settleTimer);
    this.settleTimer = undefined;
    if (this.interacting || (!this.adaptiveDrag && this.dragScale >= 1)) return;
    // Nothing is drawn yet: the next frame, with the moved geometry, is the first one drawn
    // cheaply (drawing the old geometry now would only delay the new one).
    this.interacting = true;
  }

  /// The frame of the last move is drawn and no other move waits: unless a move comes
  /// within `settleMs`, draw again at full resolution with every overlay.
  settleSoon(): void {
    if (this.settleTimer !== undefined) clearTimeout(this.settleTimer);
    this.settleTimer = setTimeout(() => this.settle(), this.settleMs);
  }

  private settle(): void {
    this.settleTimer = undefined;
    if (!this.interacting) return;
    this.interacting = false;
    this.requestRender();
  }

  /// Whether frames are drawn in the cheap dragging mode now.
  get dragging(): boolean {
    return this.interacting;
  }

  /// The drawing buffer's size in pixels.
  bufferSize(): { width: number; height: number } {
    return { width: this.canvas.width, height: this.canvas.height };
  }

  /// Draws the current state now (not at the next animation frame) and resolves once the
  /// GPU has drawn it.
  nextFrame(): Promise<void> {
    const drawn = new Promise<void>((resolve) => this.frameWaiters.push(resolve));
    this.draw();
    return drawn;
  }

  private resize(): void {
    const w = Math.max(1, this.canvas.clientWidth);
    const h = Math.max(1, this.canvas.clientHeight);
    this.renderer.setSize(w, h, false);
    this.borderMaterial.resolution.set(w, h);
    this.mobiusMaterial.resolution.set(w, h);
    this.curveMaterial.resolution.set(w, h);
    this.aspect = w / h;
    this.perspective.aspect = this.aspect;
    this.perspective.updateProjectionMatrix();
    const hh = this.orthoHalfHeight;
    Object.assign(this.ortho, { left: -hh * this.aspect, right: hh * this.aspect, top: hh, bottom: -hh });
    this.ortho.updateProjectionMatrix();
    this.requestRender();
  }

  /// Replaces or updates the outputs named in `outputs`; with `keep`, drops every output
  /// whose name is not in it.
  apply(outputs: WireOutput[], keep?: string[]): void {
    // Only positions moved (the same outputs, each with its topology): the GPU buffers are
    // updated in place instead of being made anew.
    let samePlaces = outputs.every((o) => o.positionsOnly && this.parts.has(o.name));
    for (const o of outputs) {
      const old = this.parts.get(o.name);
      if (o.positionsOnly && old !== undefined) {
        old.positions = float32s(o.geometry.positions);
        Viewer.place(old);
      } else {
        this.parts.set(o.name, this.create(o));
      }
    }
    if (keep !== undefined) {
      for (const name of [...this.parts.keys()]) {
        if (!keep.includes(name)) {
          this.parts.delete(name);
          samePlaces = false;
        }
      }
    }
    if (!samePlaces || !this.updateInPlace()) this.compose();
  }

  // Copies every part's drawn vertices and positions into the current buffers when their sizes
  // still match (false when they do not: compose anew).
  private updateInPlace(): boolean {
    const sg = this.surface.geometry;
    const pos = sg.getAttribute("position") as THREE.BufferAttribute | undefined;
    const nor = sg.getAttribute("normal") as THREE.BufferAttribute | undefined;
    const wirePos = this.wire.geometry.getAttribute("position") as THREE.BufferAttribute | undefined;
    if (pos === undefined || nor === undefined || wirePos === undefined) return false;
    let drawn = 0, vertices = 0;
    for (const p of this.parts.values()) {
      drawn += p.drawPositions.length;
      vertices += p.positions.length;
    }
    if (drawn !== pos.array.length || vertices !== wirePos.array.length) return false;
    const parts = [...this.parts.values()];
    let c = 0, v = 0;
    for (const p of parts) {
      (pos.array as Float32Array).set(p.drawPositions, c);
      (nor.array as Float32Array).set(p.drawNormals, c);
      c += p.drawPositions.length;
      (wirePos.array as Float32Array).set(p.positions, v);
      v += p.positions.length;
    }
    pos.needsUpdate = true;
    nor.needsUpdate = true;
    wirePos.needsUpdate = true;
    sg.computeBoundingSphere();
    this.wire.geometry.computeBoundingSphere();
    this.border.set(Viewer.ends(parts, (p) => p.borderEdges));
    this.mobius.set(Viewer.ends(parts, (p) => p.mobiusEdges));
    this.curves.set(Viewer.ends(parts, (p) => p.curveSegments, (p) => p.curvePoints));
    this.requestRender();
    return true;
  }

  clear(): void {
    this.parts.clear();
    this.compose();
  }

  private create(o: WireOutput): Part {
    const g = o.geometry;
    const positions = float32s(g.positions);
    const triangles = uint32s(g.triangles);
    const triangleFaces = uint32s(g.triangleFaces);
    const faceColors = uint8s(g.faceColors);
    const drawn = buildDrawn(positions.length / 3, triangles, triangleFaces, faceColors);
    const part: Part = {
      name: o.name, positions, triangles, triangleFaces, faceColors,
      edges: uint32s(g.edges),
      borderEdges: uint32s(g.borderEdges),
      mobiusEdges: uint32s(g.mobiusEdges),
      curvePoints: g.curvePoints ? float32s(g.curvePoints) : new Float32Array(0),
      curveSegments: uint32s(g.curveSegments),
      drawn,
      drawPositions: new Float32Array(3 * drawn.source.length),
      drawNormals: new Float32Array(3 * drawn.source.length),
    };
    Viewer.place(part);
    return part;
  }

  // The drawn vertices' positions and normals from the part's current positions.
  private static place(p: Part): void {
    placeDrawn(p.drawn, p.triangles, p.positions, p.drawPositions, p.drawNormals);
  }

  // Segment end points of `pairs` (vertex index pairs) of every part, for a fat line.
  private static ends(parts: Part[], pick: (p: Part) => Uint32Array,
                      points: (p: Part) => Float32Array = (p) => p.positions): Float32Array {
    let n = 0;
    for (const p of parts) n += pick(p).length;
    const out = new Float32Array(n * 3);
    let o = 0;
    for (const p of parts) {
      const pairs = pick(p);
      const pos = points(p);
      for (let i = 0; i < pairs.length; ++i, o += 3) {
        const v = 3 * pairs[i];
        out[o] = pos[v];
        out[o + 1] = pos[v + 1];
        out[o + 2] = pos[v + 2];
      }
    }
    return out;
  }

  // Draws every part as one surface, one wireframe and two fat-line sets.
  private compose(): void {
    const parts = [...this.parts.values()];
    let drawn = 0, corners = 0, vertices = 0, edges = 0;
    for (const p of parts) {
      drawn += p.drawPositions.length;
      corners += p.drawn.index.length;
      vertices += p.positions.length;
      edges += p.edges.length;
    }
    const pos = new Float32Array(drawn), nor = new Float32Array(drawn), col = new Float32Array(drawn);
    const index = new Uint32Array(corners);
    const wirePos = new Float32Array(vertices);
    const wireIndex = new Uint32Array(edges);
    let c = 0, k = 0, v = 0, e = 0;
    for (const p of parts) {
      pos.set(p.drawPositions, c);
      nor.set(p.drawNormals, c);
      col.set(p.drawn.colors, c);
      const first = c / 3;
      for (let i = 0; i < p.drawn.index.length; ++i) index[k + i] = p.drawn.index[i] + first;
      k += p.drawn.index.length;
      c += p.drawPositions.length;
      wirePos.set(p.positions, v);
      const base = v / 3;
      for (let i = 0; i < p.edges.length; ++i) wireIndex[e + i] = p.edges[i] + base;
      v += p.positions.length;
      e += p.edges.length;
    }
    this.surface.geometry.dispose();
    const sg = new THREE.BufferGeometry();
    sg.setAttribute("position", new THREE.BufferAttribute(pos, 3));
    sg.setAttribute("normal", new THREE.BufferAttribute(nor, 3));
    sg.setAttribute("color", new THREE.BufferAttribute(col, 3));
    sg.setIndex(new THREE.BufferAttribute(index, 1));
    sg.computeBoundingSphere();
    this.surface.geometry = sg;
    this.wire.geometry.dispose();
    const wg = new THREE.BufferGeometry();
    wg.setAttribute("position", new THREE.BufferAttribute(wirePos, 3));
    wg.setIndex(new THREE.BufferAttribute(wireIndex, 1));
    wg.computeBoundingSphere();
    this.wire.geometry = wg;
    this.border.set(Viewer.ends(parts, (p) => p.borderEdges));
    this.mobius.set(Viewer.ends(parts, (p) => p.mobiusEdges));
    this.curves.set(Viewer.ends(parts, (p) => p.curveSegments, (p) => p.curvePoints));
    this.requestRender();
  }

  /// Smooth normals, or each triangle's own (taken in the fragment shader: the drawn
  /// vertices stay shared either way).
  setSmooth(on: boolean): void {
    this.smooth = on;
    for (const m of [this.surfaceMaterial, this.dragMaterial]) {
      m.flatShading = !on;
      m.needsUpdate = true;
    }
    this.requestRender();
  }

  setWireframe(on: boolean): void {
    this.wireframe = on;
    this.wire.visible = on && !this.interacting;
    this.requestRender();
  }

  hasGeometry(): boolean {
    return this.parts.size > 0;
  }

  /// Frames everything drawn: from the current direction, or along the scene's camera.
  fitView(): void {
    const sphere = this.bounds();
    if (sphere === undefined) return;
    const r = Math.max(sphere.radius, 1e-3);
    const sceneCamera = this.useSceneView ? this.view?.camera : undefined;
    const dir = sceneCamera !== undefined
      ? new THREE.Vector3(...sceneCamera.direction).negate().normalize()
      : this.camera.position.clone().sub(this.controls.target).normalize();
    if (dir.lengthSq() === 0) dir.set(0.5, 0.4, 0.75).normalize();
    this.controls.target.copy(sphere.center);
    if (this.camera === this.ortho) {
      const dist = 4 * r;
      this.ortho.zoom = this.orthoHalfHeight * Math.min(1, this.aspect) / (r * 1.05);
      this.ortho.near = -dist * 10;
      this.ortho.far = dist * 10;
      this.camera.position.copy(sphere.center).addScaledVector(dir, dist);
    } else {
      const dist = r / Math.sin(THREE.MathUtils.degToRad(this.perspective.fov / 2)) * 1.05;
      this.camera.position.copy(sphere.center).addScaledVector(dir, dist);
      this.perspective.near = dist / 100;
      this.perspective.far = dist * 100;
    }
    this.camera.lookAt(this.controls.target);
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.requestRender();
  }

  /// Keyboard orbit (arrows), pan (shift + arrows) and zoom (+/-).
  nudge(key: string, shift: boolean): boolean {
    const offset = this.camera.position.clone().sub(this.controls.target);
    const spherical = new THREE.Spherical().setFromVector3(offset);
    const step = Math.PI / 24;
    if (shift && key.startsWith("Arrow")) {
      const d = offset.length() * 0.05;
      const right = new THREE.Vector3().setFromMatrixColumn(this.camera.matrix, 0);
      const up = new THREE.Vector3().setFromMatrixColumn(this.camera.matrix, 1);
      const move = key === "ArrowLeft" ? right.multiplyScalar(-d) : key === "ArrowRight" ? right.multiplyScalar(d)
        : key === "ArrowUp" ? up.multiplyScalar(d) : up.multiplyScalar(-d);
      this.camera.position.add(move);
      this.controls.target.add(move);
    } else if (key === "ArrowLeft") spherical.theta -= step;
    else if (key === "ArrowRight") spherical.theta += step;
    else if (key === "ArrowUp") spherical.phi = Math.max(0.01, spherical.phi - step);
    else if (key === "ArrowDown") spherical.phi = Math.min(Math.PI - 0.01, spherical.phi + step);
    else if ((key === "+" || key === "=") && this.camera === this.ortho) this.ortho.zoom /= 0.85;
    else if ((key === "-" || key === "_") && this.camera === this.ortho) this.ortho.zoom *= 0.85;
    else if (key === "+" || key === "=") spherical.radius *= 0.85;
    else if (key === "-" || key === "_") spherical.radius /= 0.85;
    else return false;
    this.ortho.updateProjectionMatrix();
    if (!(shift && key.startsWith("Arrow"))) {
      this.camera.position.copy(this.controls.target).add(new THREE.Vector3().setFromSpherical(spherical));
    }
    this.camera.lookAt(this.controls.target);
    this.controls.update();
    this.requestRender();
    return true;
  }

  /// FNV-1a over every output's positions (the tests' "did the mesh change").
  vertexHash(): string {
    let h = 0x811c9dc5;
    for (const name of [...this.parts.keys()].sort()) {
      const b = new Uint8Array(this.parts.get(name)!.positions.slice().buffer);
      for (let i = 0; i < b.length; ++i) h = Math.imul(h ^ b[i], 0x01000193) >>> 0;
    }
    return h.toString(16).padStart(8, "0");
  }

  /// Binary STL of every output's triangles.
  stl(): Uint8Array {
    let total = 0;
    for (const p of this.parts.values()) total += p.triangles.length / 3;
    const buf = new ArrayBuffer(84 + 50 * total);
    const view = new DataView(buf);
    const header = "nomec view: binary STL";
    for (let i = 0; i < header.length; ++i) view.setUint8(i, header.charCodeAt(i));
    view.setUint32(80, total, true);
    let o = 84;
    for (const p of this.parts.values()) {
      for (let t = 0; t < p.triangles.length / 3; ++t) {
        const a = p.triangles[3 * t] * 3, b = p.triangles[3 * t + 1] * 3, c = p.triangles[3 * t + 2] * 3;
        const ux = p.positions[b] - p.positions[a], uy = p.positions[b + 1] - p.positions[a + 1], uz = p.positions[b + 2] - p.positions[a + 2];
        const vx = p.positions[c] - p.positions[a], vy = p.positions[c + 1] - p.positions[a + 1], vz = p.positions[c + 2] - p.positions[a + 2];
        const n = [uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx];
        const len = Math.hypot(n[0], n[1], n[2]) || 1;
        for (let k = 0; k < 3; ++k, o += 4) view.setFloat32(o, n[k] / len, true);
        for (const v of [a, b, c]) {
          for (let k = 0; k < 3; ++k, o += 4) view.setFloat32(o, p.positions[v + k], true);
        }
        view.setUint16(o, 0, true);
        o += 2;
      }
    }
    return new Uint8Array(buf);
  }
}
