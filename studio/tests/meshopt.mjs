// A compressed GLB (`--meshopt`) in three.js: Debian's Chromium, headless, loads a plain GLB and
// the same model compressed with GLTFLoader and three's MeshoptDecoder, draws each once, and
// this script checks that both give the same meshes, vertex counts and bounding box (within
// the quantisation grid's step). Run by .ci/run (not by `cargo test`):
//
//   node studio/tests/meshopt.mjs plain.glb compressed.glb
//
// CHROMIUM: the browser (/usr/bin/chromium).
import { chromium } from "playwright-core";
import { createServer } from "node:http";
import { readFileSync } from "node:fs";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import assert from "node:assert/strict";

const here = dirname(fileURLToPath(import.meta.url));
const three = resolve(here, "../node_modules/three");
const [plainPath, compressedPath] = process.argv.slice(2);
if (!plainPath || !compressedPath) {
  console.error("usage: node studio/tests/meshopt.mjs plain.glb compressed.glb");
  process.exit(2);
}

const page = `<!doctype html><canvas id="c" width="256" height="256"></canvas>
<script type="importmap">{"imports": {"three": "/three/build/three.module.js",
  "three/addons/": "/three/examples/jsm/"}}</script>
<script type="module">
import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { MeshoptDecoder } from "three/addons/libs/meshopt_decoder.module.js";
const renderer = new THREE.WebGLRenderer({ canvas: document.getElementById("c") });
const loader = new GLTFLoader().setMeshoptDecoder(MeshoptDecoder);
window.summary = async (url) => {
  const gltf = await loader.loadAsync(url);
  let meshes = 0, vertices = 0, triangles = 0;
  gltf.scene.traverse((o) => {
    if (!o.isMesh) return;
    meshes += 1;
    vertices += o.geometry.attributes.position.count;
    triangles += o.geometry.index.count / 3;
  });
  const box = new THREE.Box3().setFromObject(gltf.scene);
  const camera = new THREE.PerspectiveCamera(45, 1, 0.1, 1000);
  camera.position.set(30, 30, 30);
  camera.lookAt(0, 0, 0);
  gltf.scene.add(new THREE.HemisphereLight(0xffffff, 0x444444, 3));
  renderer.render(gltf.scene, camera);
  return { meshes, vertices, triangles, min: box.min.toArray(), max: box.max.toArray(),
    error: renderer.getContext().getError() };
};
window.ready = true;
</script>`;

const files = { "/model.glb": plainPath, "/compressed.glb": compressedPath };
const server = createServer((request, response) => {
  try {
    if (request.url === "/") {
      response.writeHead(200, { "content-type": "text/html" }).end(page);
    } else if (files[request.url]) {
      response.writeHead(200, { "content-type": "model/gltf-binary" })
        .end(readFileSync(files[request.url]));
    } else if (request.url.startsWith("/three/")) {
      const file = join(three, request.url.slice("/three/".length));
      assert.ok(file.startsWith(three));
      response.writeHead(200, { "content-type": "text/javascript" }).end(readFileSync(file));
    } else {
      response.writeHead(404).end();
    }
  } catch {
    response.writeHead(404).end();
  }
});
await new Promise((done) => server.listen(0, "127.0.0.1", done));
const url = `http://127.0.0.1:${server.address().port}/`;

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  args: ["--headless", "--no-sandbox", "--disable-gpu", "--use-gl=swiftshader",
    "--enable-unsafe-swiftshader", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", "--no-first-run"],
});
try {
  const tab = await browser.newPage();
  const errors = [];
  tab.on("pageerror", (e) => errors.push(String(e)));
  await tab.goto(url);
  await tab.waitForFunction(() => window.ready === true, null, { timeout: 30000 });
  const plain = await tab.evaluate(() => window.summary("/model.glb"));
  const compressed = await tab.evaluate(() => window.summary("/compressed.glb"));
  assert.deepEqual(errors, []);
  console.log(`plain: ${JSON.stringify(plain)}\ncompressed: ${JSON.stringify(compressed)}`);
  assert.ok(plain.meshes > 0 && plain.vertices > 0);
  assert.equal(compressed.meshes, plain.meshes);
  assert.equal(compressed.vertices, plain.vertices);
  assert.equal(compressed.triangles, plain.triangles);
  assert.equal(compressed.error, 0);
  // Quantised positions lie within half a step of 32,767 per half extent.
  const step = Math.max(...plain.max.map((v, k) => v - plain.min[k])) / 2 / 32767;
  for (const k of [0, 1, 2]) {
    assert.ok(Math.abs(compressed.min[k] - plain.min[k]) <= step, `min ${k}`);
    assert.ok(Math.abs(compressed.max[k] - plain.max[k]) <= step, `max ${k}`);
  }
  console.log("three.js reads the compressed GLB as the plain one");
} finally {
  await browser.close();
  server.close();
}
