// preview-e2e.mjs: the preview in a real VS Code (code-server, see preview-e2e.sh), driven
// through headless Chromium by playwright-core: open examples/funnel_cube.nome, run "NOME:
// Open Preview to the Side", check that the webview's canvas shows the sculpture (pixel
// check) and the topology readout, move the fp.z slider with the keyboard (the vertex hash
// changes, the file does not), "Write slider values into the file" (the editor's text
// changes), and save a screenshot of the window.
//   node preview-e2e.mjs CODE_SERVER_URL WORKSPACE SCREENSHOT.png
import { createRequire } from "node:module";
import { readFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";
// playwright-core comes from the preview app's node_modules.
const require = createRequire(join(dirname(fileURLToPath(import.meta.url)), "../../../preview/package.json"));
const { chromium } = require("playwright-core");

const [url, workspace, shot] = process.argv.slice(2);
const fail = (m) => { console.error(`preview-e2e: FAIL: ${m}`); process.exitCode = 1; };
const browser = await chromium.launch({
  executablePath: process.env.NOMEC_CHROMIUM ?? "/usr/bin/chromium", headless: true,
  args: ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--use-gl=angle",
    "--use-angle=swiftshader", "--enable-unsafe-swiftshader"],
});
try {
  const page = await browser.newPage({ viewport: { width: 1400, height: 860 } });
  await page.goto(`${url}/?folder=${encodeURIComponent(workspace)}`);
  await page.waitForSelector(".monaco-workbench", { timeout: 60000 });
  const row = page.locator(".explorer-folders-view .monaco-list-row", { hasText: "funnel_cube.nome" });
  await row.waitFor({ timeout: 60000 });
  await row.dblclick();
  await page.waitForSelector('[id="status.editor.mode"]:has-text("NOME")', { timeout: 60000 });
  // Room for the editor and the preview side by side.
  await page.keyboard.press("F1");
  await page.keyboard.type("View: Close Primary Side Bar");
  await page.waitForSelector(".quick-input-list .monaco-list-row", { timeout: 20000 });
  await page.keyboard.press("Enter");
  await page.keyboard.press("F1");
  await page.keyboard.type("NOME: Open Preview to the Side");
  await page.waitForSelector(".quick-input-list .monaco-list-row", { timeout: 20000 });
  await page.keyboard.press("Enter");
  // The webview's content: iframe.webview > iframe#active-frame.
  let frame;
  const t0 = Date.now();
  while (!frame && Date.now() - t0 < 60000) {
    for (const f of page.frames()) {
      if (await f.locator("#view").count().catch(() => 0)) frame = f;
    }
    if (!frame) await page.waitForTimeout(250);
  }
  if (!frame) throw new Error("no preview webview appeared");
  await frame.waitForFunction(() => window.nomePreview?.state.ready && window.nomePreview.state.ok, undefined, { timeout: 60000 });
  await frame.evaluate(() => window.nomePreview.viewer.nextFrame());
  const share = await frame.evaluate(() => {
    const src = document.getElementById("view");
    const c = document.createElement("canvas");
    c.width = src.width; c.height = src.height;
    const g = c.getContext("2d");
    g.drawImage(src, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    let n = 0;
    for (let i = 0; i < d.length; i += 4) if (Math.abs(d[i] - d[0]) + Math.abs(d[i + 1] - d[1]) + Math.abs(d[i + 2] - d[2]) > 30) n++;
    return n / (d.length / 4);
  });
  if (!(share > 0.02)) fail(`the canvas looks blank (${share})`);
  const topo = await frame.locator("#topology").innerText();
  if (!/cf/.test(topo) || !/χ = /.test(topo)) fail(`no topology readout: ${topo}`);
  const h0 = await frame.evaluate(() => window.nomePreview.vertexHash());
  await frame.locator("#s-fp_z").focus();
  for (let i = 0; i < 3; ++i) {
    const n = await frame.evaluate(() => window.nomePreview.timings.length);
    await page.keyboard.press("ArrowRight");
    await frame.waitForFunction((k) => window.nomePreview.timings.length > k, n, { timeout: 30000 });
  }
  const h1 = await frame.evaluate(() => window.nomePreview.vertexHash());
  if (h1 === h0) fail("moving fp.z did not change the mesh");
  const t = await frame.evaluate(() => window.nomePreview.timings.map((x) => x.frameMs));
  console.log(`preview-e2e: slider moves in VS Code: ${t.map((x) => x.toFixed(0)).join(", ")} ms to the new frame`);
  const onDisk = readFileSync(join(workspace, "funnel_cube.nome"), "utf8");
  if (!/set\s+z\s+-0\.8\s/.test(onDisk)) fail("a slider move edited the file");
  await frame.locator("#write-values").click();
  await page.waitForSelector('.monaco-editor .view-lines:has-text("-0.5")', { timeout: 20000 })
    .catch(() => fail("Write slider values into the file did not change the editor's text"));
  const first = await page.locator(".monaco-editor .view-lines .view-line").first().innerText();
  if (/Saved by nomec/.test(first)) fail(`the written file got the save header: ${first}`);
  await page.waitForTimeout(300);
  await page.screenshot({ path: shot });
  console.log(`preview-e2e: canvas ${(share * 100).toFixed(0)}% drawn; screenshot ${shot}`);
} finally {
  await browser.close();
}
if (!process.exitCode) console.log("preview-e2e: 1 passed, 0 failed");
