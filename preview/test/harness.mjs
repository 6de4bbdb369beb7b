// harness.mjs: what the browser tests and the benchmark share: start `nomec view` on a free
// port (reading the URL it prints), launch Debian's headless Chromium through
// playwright-core, and small helpers that read the page the way a person would see it.
import { spawn } from "node:child_process";
import { chromium } from "playwright-core";

export const chromiumPath = process.env.NOMEC_CHROMIUM ?? "/usr/bin/chromium";

export async function launchBrowser() {
  return chromium.launch({
    executablePath: chromiumPath,
    headless: true,
    args: ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-extensions",
      "--disable-component-update", "--disable-default-apps", "--disable-sync", "--no-first-run",
      "--use-gl=angle", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"],
  });
}

/// Starts `nomec view FILE --port 0`; resolves with {proc, url, port, stderr()} once it listens.
export function startView(nomec, file, extra = []) {
  return new Promise((resolve, reject) => {
    const proc = spawn(nomec, ["view", file, "--port", "0", ...extra], { stdio: ["ignore", "pipe", "pipe"] });
    let out = "";
    let err = "";
    const timer = setTimeout(() => reject(new Error(`nomec view did not start: ${out} ${err}`)), 20000);
    proc.stderr.on("data", (d) => { err += d; });
    proc.stdout.on("data", (d) => {
      out += d;
      const m = /at (http:\/\/127\.0\.0\.1:(\d+)\/)/.exec(out);
      if (m) {
        clearTimeout(timer);
        resolve({ proc, url: m[1], port: Number(m[2]), stdout: () => out, stderr: () => err });
      }
    });
    proc.on("exit", (code) => reject(new Error(`nomec view exited with ${code}: ${err}`)));
  });
}

/// Sends SIGINT and resolves with the exit code.
export function stopView(view) {
  return new Promise((resolve) => {
    if (view.proc.exitCode !== null) return resolve(view.proc.exitCode);
    view.proc.removeAllListeners("exit");
    view.proc.on("exit", (code) => resolve(code));
    view.proc.kill("SIGINT");
  });
}

export async function waitFor(page, predicate, arg, timeout = 30000) {
  await page.waitForFunction(predicate, arg, { timeout, polling: 20 });
}

/// Share of the canvas's pixels that differ clearly from its corner (the background).
export async function drawnShare(page) {
  return page.evaluate(() => {
    const src = document.getElementById("view");
    const c = document.createElement("canvas");
    c.width = src.width;
    c.height = src.height;
    const g = c.getContext("2d");
    g.drawImage(src, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    const bg = [d[0], d[1], d[2]];
    let n = 0;
    for (let i = 0; i < d.length; i += 4) {
      if (Math.abs(d[i] - bg[0]) + Math.abs(d[i + 1] - bg[1]) + Math.abs(d[i + 2] - bg[2]) > 30) n++;
    }
    return n / (d.length / 4);
  });
}

export function percentile(values, p) {
  const s = [...values].sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.floor((p / 100) * s.length))];
}
