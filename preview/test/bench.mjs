// bench.mjs: the preview's speed, in headless Chromium against `nomec view`
//   node test/bench.mjs PATH/TO/nomec [--moves N] [--drag-scale S] [--app-dir DIR]...
// With several --app-dir (built apps, e.g. before and after a change), every case runs for
// each app in turn, twice, interleaved (A B A B), and each app's figures are printed: a
// ratio measured in one run on one machine state.
// 1. slider move -> new frame drawn (p50/p90) on examples/funnel_cube.nome (fp.z);
// 2. the same on examples/klein_bottle_zipped.nome with merge + subdivision 3 + offset
//    (tp1.h), the seed's heaviest interactive case, with and without the wireframe
//    (frames during a drag are drawn without it anyway, so the two differ little now);
// 3. the first picture of a generated 0.5 MB scene (the scene of
//    bench/common/generated_scene.h): from navigation to the first frame with the scene
//    drawn (the page's `nome-first-picture` mark; drawn as while dragging), to the first
//    frame drawn at rest (`nome-first-full-picture`), and from goto to one more frame.
// Frames are timed in the page, from the slider value set to the frame after the reply
// was drawn (`nomePreview.timings`); bytes are the reply's JSON text. While a slider is
// dragged the app draws with `dragScale` of the resolution per axis (adapted to the frame
// time; --drag-scale fixes it) and no wireframe
// (--drag-scale 1 draws every frame as at rest, for comparison). Software rendering
// (SwiftShader) on a shared machine: the numbers are upper bounds of a desktop's.
import { mkdtempSync, writeFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join, dirname } from "node:path";
import { fileURLToPath } from "node:url";
import { launchBrowser, startView, stopView, waitFor, percentile } from "./harness.mjs";

const nomec = process.argv[2];
if (!nomec) {
  console.error("usage: node test/bench.mjs PATH/TO/nomec [--moves N] [--drag-scale S]");
  process.exit(2);
}
const movesAt = process.argv.indexOf("--moves");
const moves = movesAt > 0 ? Number(process.argv[movesAt + 1]) : 40;
const scaleAt = process.argv.indexOf("--drag-scale");
const dragScale = scaleAt > 0 ? Number(process.argv[scaleAt + 1]) : undefined;
const appDirs = process.argv.flatMap((a, i) => (a === "--app-dir" ? [process.argv[i + 1]] : []));
const apps = appDirs.length > 0 ? appDirs : [undefined];
let appDir;  // the app of the case being run
const examples = join(dirname(fileURLToPath(import.meta.url)), "../../examples");

function generatedScene(minBytes) {
  let out = "# Generated like bench/common/generated_scene.h.\n";
  for (let k = 0; out.length < minBytes; ++k) {
    out += `# module ${k}\nbank b${k}\n  set n ${4 + (k % 8)} 3 20 1\n  set r 1.${k % 10} 0.1 5 0.1\n  set h 0.5 0.1 2 0.1\nendbank\n`;
    for (let i = 0; i < 4; ++i) {
      out += `point q${k}_${i} ({expr $b${k}_r * cos(${i} * pi / 2)} {expr $b${k}_r * sin(${i} * pi / 2)} {expr $b${k}_h * ${i} - 0.5}) endpoint\n`;
    }
    out += `mesh m${k}\n`;
    for (let i = 0; i < 8; ++i) out += `  point v${i} (${i % 2} ${Math.floor(i / 2) % 2} {expr $b${k}_h * ${Math.floor(i / 4)}}) endpoint\n`;
    out += "  face f0 (v0 v1 v3 v2) endface\n  face f1 (v4 v6 v7 v5) endface\n  face f2 (v0 v4 v5 v1) endface\n" +
      "  face f3 (v2 v3 v7 v6) endface\n  face f4 (v0 v2 v6 v4) endface\n  face f5 (v1 v5 v7 v3) endface\nendmesh\n";
    out += `face t${k} (q${k}_0 q${k}_1 q${k}_2 q${k}_3) endface\nfunnel fun${k} ($b${k}_n $b${k}_r 0.5 $b${k}_h) endfunnel\n` +
      `group g${k}\n  instance box m${k} translate (0 0 {expr -$b${k}_h}) endinstance\n` +
      `  instance fa fun${k} rotate (0 0 1) (90) translate (0 0 1) endinstance\nendgroup\n` +
      `instance gi${k} g${k} translate ({expr $b${k}_r * 3} ${k % 7} 0) endinstance\n` +
      `instance fb${k} fun${k} scale (1 1 -1) endinstance\n` +
      `face j${k} (fb${k}_hc0 fb${k}_hc1 fb${k}_bc1 fb${k}_bc0) endface\n\n`;
  }
  return out;
}

function viewArgs() {
  return appDir === undefined ? [] : ["--app-dir", appDir];
}

async function sliderBench(browser, file, param, values, pipeline, wireframe = true) {
  const view = await startView(nomec, file, viewArgs());
  try {
    const page = await browser.newPage({ viewport: { width: 1000, height: 640 } });
    await page.goto(view.url);
    await waitFor(page, () => window.nomePreview?.state.ready && window.nomePreview.state.ok, undefined, 60000);
    if (pipeline) {
      const n = await page.evaluate(() => window.nomePreview.state.previews);
      await page.locator("#merge").check();
      await page.locator("#subdivide").fill(String(pipeline.subdivide));
      await page.locator("#offset").fill(String(pipeline.offset));
      await page.locator("#offset").dispatchEvent("change");
      await waitFor(page, (k) => window.nomePreview.state.previews >= k + 2 && window.nomePreview.state.ok, n, 120000);
    }
    if (!wireframe) await page.locator("#wire").click();
    if (dragScale !== undefined) {
      await page.evaluate((s) => { const v = window.nomePreview.viewer; v.dragScale = s; v.adaptiveDrag = false; }, dragScale);
    }
    const summary = await page.locator("#topology").innerText();
    for (let i = 0; i < moves; ++i) {
      const before = await page.evaluate(() => window.nomePreview.timings.length);
      await page.evaluate(([p, v]) => window.nomePreview.move(p, v), [param, values[i % values.length]]);
      await waitFor(page, (n) => window.nomePreview.timings.length > n, before, 60000);
    }
    const t = (await page.evaluate(() => window.nomePreview.timings)).slice(-moves);
    const frame = t.map((x) => x.frameMs);
    const server = t.map((x) => x.serverMs);
    const rt = t.map((x) => x.roundTripMs);
    const apply = t.map((x) => x.applyMs);
    const draw = t.map((x) => x.drawMs);
    const bytes = t.map((x) => x.bytes);
    await page.close();
    return {
      timings: t,
      p50: percentile(frame, 50), p90: percentile(frame, 90), server50: percentile(server, 50),
      rt50: percentile(rt, 50), apply50: percentile(apply, 50), draw50: percentile(draw, 50),
      bytes50: percentile(bytes, 50), n: t.length, summary: summary.split("\n").slice(0, 4).join(" "),
    };
  } finally {
    await stopView(view);
  }
}

async function firstPicture(browser, file) {
  const view = await startView(nomec, file, viewArgs());
  try {
    const page = await browser.newPage({ viewport: { width: 1000, height: 640 } });
    const t0 = performance.now();
    await page.goto(view.url);
    await waitFor(page, () => window.nomePreview?.state.ready && window.nomePreview.state.ok, undefined, 120000);
    await page.evaluate(() => window.nomePreview.viewer.nextFrame());
    const ms = performance.now() - t0;
    // The page's own clock: navigation start -> the first frame with the scene drawn.
    const firstMs = await page.evaluate(() => performance.getEntriesByName("nome-first-picture")[0].startTime);
    // ... and to the first one drawn at rest (full resolution and lighting, every overlay).
    // (An app older than that mark draws the first picture at rest: the same time.)
    const fullMs = await waitFor(page, () => performance.getEntriesByName("nome-first-full-picture").length > 0, undefined, 10000)
      .then(() => page.evaluate(() => performance.getEntriesByName("nome-first-full-picture")[0].startTime), () => firstMs);
    const outputs = await page.evaluate(() => window.nomePreview.app.summaries.length);
    const parts = await page.evaluate(() => window.nomePreview.lastPreview());
    await page.close();
    return { ms, firstMs, fullMs, outputs, parts };
  } finally {
    await stopView(view);
  }
}

const work = mkdtempSync(join(tmpdir(), "nome-bench-"));
const browser = await launchBrowser();
try {
  const line = (name, r) => console.log(`${name}: slider -> frame p50 ${r.p50.toFixed(1)} ms, p90 ${r.p90.toFixed(1)} ms ` +
    `(p50 parts: round trip ${r.rt50.toFixed(1)} ms of which nomec ${r.server50.toFixed(1)} ms, rebuild ${r.apply50.toFixed(1)} ms, ` +
    `draw ${r.draw50.toFixed(1)} ms; reply ${r.bytes50} bytes; ${r.n} moves)`);
  // Runs `run` for each app (twice each, interleaved when there are several apps) and
  // prints each app's figures with `show`.
  const each = async (show, run) => {
    const results = new Map(apps.map((a) => [a, []]));
    for (let round = 0; round < (apps.length > 1 ? 2 : 1); ++round) {
      for (const a of apps) {
        appDir = a;
        results.get(a).push(await run());
      }
    }
    for (const a of apps) show(a === undefined ? "" : `[${a}] `, results.get(a));
  };
  const merged = (rs) => {
    const t = rs.flatMap((r) => r.timings);
    const pick = (k) => t.map((x) => x[k]);
    return {
      p50: percentile(pick("frameMs"), 50), p90: percentile(pick("frameMs"), 90), server50: percentile(pick("serverMs"), 50),
      rt50: percentile(pick("roundTripMs"), 50), apply50: percentile(pick("applyMs"), 50), draw50: percentile(pick("drawMs"), 50),
      bytes50: percentile(pick("bytes"), 50), n: t.length,
    };
  };
  const slider = (name, ...args) => each((tag, rs) => line(tag + name, merged(rs)), () => sliderBench(browser, ...args));
  const zs = [-0.5, -0.45, -0.4, -0.35, -0.3, -0.35, -0.4, -0.45];
  await slider("funnel_cube fp.z", join(examples, "funnel_cube.nome"), "fp.z", zs);
  const hs = [1.5, 1.4, 1.3, 1.2, 1.1, 1.2, 1.3, 1.4];
  await slider("klein_bottle_zipped tp1.h, merge + subdivide 3 + offset 0.05",
    join(examples, "klein_bottle_zipped.nome"), "tp1.h", hs, { subdivide: 3, offset: 0.05 });
  await slider("the same without the wireframe overlay",
    join(examples, "klein_bottle_zipped.nome"), "tp1.h", hs, { subdivide: 3, offset: 0.05 }, false);
  const big = join(work, "generated.nome");
  const text = generatedScene(512 * 1024);
  writeFileSync(big, text);
  await each((tag, fs) => {
    for (const f of fs) {
      const p = Object.entries(f.parts).map(([k, v]) => `${k} ${v.toFixed(0)}`).join(", ");
      console.log(`${tag}first picture of a ${(text.length / 1024).toFixed(0)} KB scene (${f.outputs} outputs): ${f.firstMs.toFixed(0)} ms ` +
        `from navigation to the first frame drawn (${p}), ${f.fullMs.toFixed(0)} ms to the first drawn at rest; ` +
        `${f.ms.toFixed(0)} ms from goto to one more frame drawn`);
    }
  }, () => firstPicture(browser, big));
} finally {
  await browser.close();
  rmSync(work, { recursive: true, force: true });
}
