// build.mjs: bundles the preview (TypeScript + three.js) with esbuild into dist/: app.js,
// style.css, index.html (the page `nomec view` serves) and body.html (the markup the VS
// Code extension embeds in its own page). Nothing is fetched at run time.
import { build } from "esbuild";
import { mkdirSync, readFileSync, writeFileSync, copyFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const root = join(dirname(fileURLToPath(import.meta.url)), "..");
const out = process.argv[2] ?? join(root, "dist");
mkdirSync(out, { recursive: true });
await build({
  entryPoints: [join(root, "src/app.ts")],
  bundle: true,
  minify: true,
  format: "iife",
  target: "es2020",
  outfile: join(out, "app.js"),
  logLevel: "warning",
});
const body = readFileSync(join(root, "src/body.html"), "utf8");
const page = readFileSync(join(root, "src/index.html"), "utf8").replace("<!--NOME-PREVIEW-BODY-->", body);
writeFileSync(join(out, "index.html"), page);
writeFileSync(join(out, "body.html"), body);
copyFileSync(join(root, "src/style.css"), join(out, "style.css"));
console.log(`preview: built ${out}`);
