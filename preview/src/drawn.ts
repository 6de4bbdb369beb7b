// drawn.ts: which vertices the GPU draws for an output's triangles, with no three.js in it
// (test/drawn.test.mjs runs it in node).
//
// A triangle corner is drawn by a vertex shared with every other corner that has the same
// mesh vertex, the same fan component, the same side and the same face colour:
// - the fan of a mesh vertex is the set of triangles around it; it is oriented by walking
//   from triangle to triangle across the edges they share at the vertex, giving each corner
//   a side (+1/-1) so that neighbouring triangles agree. On an orientable, consistently
//   wound surface every side is +1; across a Möbius edge (Möbius bands, Klein bottles) the
//   two triangles sit on opposite sides. A fan that falls apart into pieces (a pinched
//   vertex) gets one component per piece.
// - the smooth normal of a fan component is the sum of its triangles' area-weighted normals,
//   each taken with its side; a drawn vertex on side s uses s times it, so it agrees with
//   the winding of the triangles it draws (what two-sided lighting needs).
// So a closed quad mesh of one colour draws one vertex per mesh vertex instead of six per
// quad, and positions-only updates rewrite positions and normals of those vertices in place.

export interface Drawn {
  /// Mesh vertex of each drawn vertex.
  source: Uint32Array;
  /// Fan component of each drawn vertex, and its side (+1/-1).
  fan: Uint32Array;
  side: Int8Array;
  /// Fan component and side of each triangle corner (3 per triangle).
  cornerFan: Uint32Array;
  cornerSide: Int8Array;
  /// Three drawn vertices per triangle.
  index: Uint32Array;
  /// Number of fan components.
  fans: number;
  /// RGB in [0, 1] per drawn vertex.
  colors: Float32Array;
}

const kDefaultColor = [0.72, 0.76, 0.82];

/// Drawn vertices of `triangles` (3 mesh vertex indices each) over `vertexCount` vertices;
/// `triangleFaces` gives each triangle's polygon, `faceColors` each polygon's RGB bytes.
export function buildDrawn(vertexCount: number, triangles: Uint32Array, triangleFaces: Uint32Array,
                           faceColors: Uint8Array | null): Drawn {
  const corners = triangles.length;
  // Corners around each vertex (compressed rows).
  const start = new Uint32Array(vertexCount + 1);
  for (let c = 0; c < corners; ++c) start[triangles[c] + 1]++;
  for (let v = 0; v < vertexCount; ++v) start[v + 1] += start[v];
  const around = new Uint32Array(corners);
  const fill = start.slice(0, vertexCount);
  for (let c = 0; c < corners; ++c) around[fill[triangles[c]]++] = c;

  const cornerFan = new Uint32Array(corners);
  const cornerSide = new Int8Array(corners);
  const index = new Uint32Array(corners);
  const source: number[] = [];
  const fanOf: number[] = [];
  const sideOf: number[] = [];
  const colorOf: number[] = [];
  let fans = 0;
  const stack: number[] = [];
  const next = (c: number) => triangles[c - (c % 3) + ((c % 3) + 1) % 3];
  const prev = (c: number) => triangles[c - (c % 3) + ((c % 3) + 2) % 3];
  const colorKey = (c: number): number => {
    if (faceColors === null) return -1;
    const f = triangleFaces[(c / 3) | 0];
    return 3 * f + 2 < faceColors.length ? (faceColors[3 * f] << 16) | (faceColors[3 * f + 1] << 8) | faceColors[3 * f + 2] : -1;
  };
  for (let v = 0; v < vertexCount; ++v) {
    const lo = start[v], hi = start[v + 1];
    for (let i = lo; i < hi; ++i) cornerSide[around[i]] = 0;  // 0: not reached yet
    // Orient each connected piece of the fan from its first corner.
    for (let i = lo; i < hi; ++i) {
      const first = around[i];
      if (cornerSide[first] !== 0) continue;
      const fan = fans++;
      cornerSide[first] = 1;
      cornerFan[first] = fan;
      stack.push(first);
      while (stack.length > 0) {
        const a = stack.pop()!;
        const an = next(a), ap = prev(a), as = cornerSide[a];
        for (let j = lo; j < hi; ++j) {
          const b = around[j];
          if (cornerSide[b] !== 0) continue;
          const bn = next(b), bp = prev(b);
          // Across a shared edge (v, w): opposite directions agree, equal ones disagree.
          let side = 0;
          if (an === bp || ap === bn) side = as;
          else if (an === bn || ap === bp) side = -as;
          if (side === 0) continue;
          cornerSide[b] = side;
          cornerFan[b] = fan;
          stack.push(b);
        }
      }
    }
    // One drawn vertex per (fan piece, side, colour) among the corners of v.
    const first = source.length;
    for (let i = lo; i < hi; ++i) {
      const c = around[i];
      const key = colorKey(c);
      let d = first;
      while (d < source.length && !(fanOf[d] === cornerFan[c] && sideOf[d] === cornerSide[c] && colorOf[d] === key)) ++d;
      if (d === source.length) {
        source.push(v);
        fanOf.push(cornerFan[c]);
        sideOf.push(cornerSide[c]);
        colorOf.push(key);
      }
      index[c] = d;
    }
  }
  const colors = new Float32Array(3 * source.length);
  for (let d = 0; d < source.length; ++d) {
    const k = colorOf[d];
    const rgb = k < 0 ? kDefaultColor : [((k >> 16) & 255) / 255, ((k >> 8) & 255) / 255, (k & 255) / 255];
    colors.set(rgb, 3 * d);
  }
  return {
    source: Uint32Array.from(source), fan: Uint32Array.from(fanOf), side: Int8Array.from(sideOf),
    cornerFan, cornerSide, index, fans, colors,
  };
}

/// Writes the drawn vertices' positions and smooth normals (unit length; zero where the fan
/// has no area) for the mesh `positions` into `outPositions`/`outNormals` (3 floats each).
export function placeDrawn(d: Drawn, triangles: Uint32Array, positions: Float32Array,
                           outPositions: Float32Array, outNormals: Float32Array): void {
  const sum = new Float64Array(3 * d.fans);
  for (let t = 0; t < triangles.length; t += 3) {
    const a = 3 * triangles[t], b = 3 * triangles[t + 1], c = 3 * triangles[t + 2];
    const ux = positions[b] - positions[a], uy = positions[b + 1] - positions[a + 1], uz = positions[b + 2] - positions[a + 2];
    const vx = positions[c] - positions[a], vy = positions[c + 1] - positions[a + 1], vz = positions[c + 2] - positions[a + 2];
    const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;  // area-weighted
    for (let k = 0; k < 3; ++k) {
      const f = 3 * d.cornerFan[t + k], s = d.cornerSide[t + k];
      sum[f] += s * nx;
      sum[f + 1] += s * ny;
      sum[f + 2] += s * nz;
    }
  }
  for (let i = 0; i < d.source.length; ++i) {
    const v = 3 * d.source[i], f = 3 * d.fan[i], o = 3 * i;
    outPositions[o] = positions[v];
    outPositions[o + 1] = positions[v + 1];
    outPositions[o + 2] = positions[v + 2];
    const len = Math.hypot(sum[f], sum[f + 1], sum[f + 2]);
    const s = len > 0 ? d.side[i] / len : 0;
    outNormals[o] = s * sum[f];
    outNormals[o + 1] = s * sum[f + 1];
    outNormals[o + 2] = s * sum[f + 2];
  }
}
