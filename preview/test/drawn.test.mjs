// drawn.test.mjs: the preview's shared drawn vertices (src/drawn.ts) in node, no browser:
// how many vertices the GPU draws, their sides across a Möbius seam, colours, pinched
// vertices, and normals that agree with every triangle's winding.
//   node test/drawn.test.mjs
import { buildSync } from "esbuild";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";
import assert from "node:assert/strict";

const src = join(dirname(fileURLToPath(import.meta.url)), "../src/drawn.ts");
const code = buildSync({ entryPoints: [src], bundle: true, format: "esm", write: false }).outputFiles[0].text;
const { buildDrawn, placeDrawn } = await import("data:text/javascript;base64," + Buffer.from(code).toString("base64"));

function triangulate(quads) {
  const tris = [], faces = [];
  quads.forEach((q, f) => {
    for (let k = 1; k + 1 < q.length; ++k) { tris.push(q[0], q[k], q[k + 1]); faces.push(f); }
  });
  return { triangles: Uint32Array.from(tris), triangleFaces: Uint32Array.from(faces) };
}

function place(d, triangles, positions) {
  const p = new Float32Array(3 * d.source.length), n = new Float32Array(3 * d.source.length);
  placeDrawn(d, triangles, positions, p, n);
  return { p, n };
}

// Every corner's drawn normal points to the side its triangle's winding faces.
function assertNormalsAgree(d, triangles, positions, n, what) {
  for (let t = 0; t < triangles.length; t += 3) {
    const [a, b, c] = [0, 1, 2].map((k) => 3 * triangles[t + k]);
    const u = [0, 1, 2].map((k) => positions[b + k] - positions[a + k]);
    const v = [0, 1, 2].map((k) => positions[c + k] - positions[a + k]);
    const fn = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    for (let k = 0; k < 3; ++k) {
      const i = 3 * d.index[t + k];
      const dot = fn[0] * n[i] + fn[1] * n[i + 1] + fn[2] * n[i + 2];
      assert.ok(dot > 0, `${what}: triangle ${t / 3} corner ${k}: normal against the winding (${dot})`);
    }
  }
}

// A unit cube wound outwards: one drawn vertex per corner of the cube, normals outwards.
{
  const pos = new Float32Array([0,0,0, 1,0,0, 0,1,0, 1,1,0, 0,0,1, 1,0,1, 0,1,1, 1,1,1]);
  const quads = [[0,2,3,1], [4,5,7,6], [0,1,5,4], [2,6,7,3], [0,4,6,2], [1,3,7,5]];
  const { triangles, triangleFaces } = triangulate(quads);
  const d = buildDrawn(8, triangles, triangleFaces, null);
  assert.equal(d.source.length, 8, "cube: 8 drawn vertices for 36 corners");
  assert.equal(d.fans, 8);
  assert.ok(d.side.every((s) => s === 1), "cube: one side everywhere");
  const { p, n } = place(d, triangles, pos);
  for (let i = 0; i < 8; ++i) {
    const out = [0, 1, 2].map((k) => p[3 * i + k] - 0.5);
    assert.ok(out[0] * n[3 * i] + out[1] * n[3 * i + 1] + out[2] * n[3 * i + 2] > 0.8, `cube: vertex ${i} normal outwards`);
    assert.ok(Math.abs(Math.hypot(n[3 * i], n[3 * i + 1], n[3 * i + 2]) - 1) < 1e-6, "unit normals");
  }
  assertNormalsAgree(d, triangles, pos, n, "cube");
  // Two colours: the vertices on the border between colours are drawn twice.
  const colors = new Uint8Array(18).fill(200);
  colors.set([255, 0, 0], 0);  // face 0 (z = 0) red
  const c = buildDrawn(8, triangles, triangleFaces, colors);
  assert.equal(c.source.length, 12, "cube with a red bottom: its 4 corners drawn twice");
  for (let i = 0; i < c.source.length; ++i) {
    const red = c.colors[3 * i] === 1 && c.colors[3 * i + 1] === 0;
    if (red) assert.ok(pos[3 * c.source[i] + 2] === 0, "red only on the bottom");
  }
  assert.equal([...c.index.slice(0, 6)].every((i) => c.colors[3 * i] === 1 && c.colors[3 * i + 1] === 0), true,
               "the bottom's corners use red vertices");
}

// A Möbius band of n quads: one half turn, so the quads across the closing seam are wound
// against each other. Only the two seam vertices are drawn twice (one per side), and every
// normal agrees with its triangle.
{
  const n = 12;
  const pos = new Float32Array(6 * n);
  for (let i = 0; i < n; ++i) {
    const th = (2 * Math.PI * i) / n;
    for (const [j, s] of [[0, -0.5], [1, 0.5]]) {
      const r = 2 + s * Math.cos(th / 2);
      pos.set([r * Math.cos(th), r * Math.sin(th), s * Math.sin(th / 2)], 3 * (2 * i + j));
    }
  }
  const quads = [];
  for (let i = 0; i + 1 < n; ++i) quads.push([2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1]);
  quads.push([2 * n - 2, 1, 0, 2 * n - 1]);  // the half turn: bottom meets top
  const { triangles, triangleFaces } = triangulate(quads);
  const d = buildDrawn(2 * n, triangles, triangleFaces, null);
  assert.equal(d.source.length, 2 * n + 2, "Möbius band: the two seam vertices drawn on both sides");
  const twice = [...new Set([...d.source].filter((v, i, a) => a.indexOf(v) !== i))].sort((a, b) => a - b);
  assert.deepEqual(twice, [0, 1], "the doubled vertices are the seam's");
  assert.equal(d.fans, 2 * n, "one fan per vertex");
  const { n: normals } = place(d, triangles, pos);
  assertNormalsAgree(d, triangles, pos, normals, "Möbius band");
}

// A pinched vertex: two triangles meeting only at vertex 0 make two fan pieces.
{
  const pos = new Float32Array([0,0,0, 1,0,0, 0,1,0, -1,0,0, 0,-1,0.2]);
  const triangles = Uint32Array.from([0, 1, 2, 0, 3, 4]);
  const d = buildDrawn(5, triangles, Uint32Array.from([0, 1]), null);
  assert.equal(d.fans, 6, "vertex 0 has two fan pieces");
  assert.equal(d.source.length, 6);
  const { n } = place(d, triangles, pos);
  assertNormalsAgree(d, triangles, pos, n, "pinched");
}

// Positions move (a slider): placing again updates normals without rebuilding.
{
  const pos = new Float32Array([0,0,0, 1,0,0, 0,1,0, 1,1,0]);
  const triangles = Uint32Array.from([0, 1, 3, 0, 3, 2]);
  const d = buildDrawn(4, triangles, Uint32Array.from([0, 0]), null);
  assert.equal(d.source.length, 4);
  let { n } = place(d, triangles, pos);
  assert.deepEqual([...n.slice(0, 3)], [0, 0, 1]);
  pos.set([0, 0, 1], 9);  // lift vertex 3: the normals tilt
  ({ n } = place(d, triangles, pos));
  assert.ok(n[2] < 1 && n[0] < 0, "normals follow the moved vertex");
  assertNormalsAgree(d, triangles, pos, n, "moved");
}
console.log("drawn.test: ok");
