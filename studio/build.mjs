// Bundles the studio into dist/: studio.js (CodeMirror, three.js and src/), studio.css and
// index.html; and the split grammar editor's topo.js, topo.css and topo.html (src/topo/). The output is deterministic for the locked dependencies, so CI can rebuild it
// and compare with what is checked in (the binary embeds dist/).
import { build } from "esbuild";
import { copyFileSync, mkdirSync } from "node:fs";

mkdirSync("dist", { recursive: true });
await build({
  entryPoints: { studio: "src/main.js", topo: "src/topo/main.js" },
  bundle: true,
  minify: true,
  format: "esm",
  target: "es2022",
  outdir: "dist",
  legalComments: "eof",
  logLevel: "warning",
});
await build({
  entryPoints: { studio: "src/style.css", topo: "src/topo/style.css" },
  bundle: true,
  minify: true,
  outdir: "dist",
  logLevel: "warning",
});
copyFileSync("src/index.html", "dist/index.html");
copyFileSync("src/topo/index.html", "dist/topo.html");
