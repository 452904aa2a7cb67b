// `shapegram derive --tiles` end to end: a city of WGS84 lots is tiled by the binary, checked by
// 3d-tiles-tools (check.mjs), and streamed by CesiumJS from npm in Debian's Chromium, headless
// with WebGL through SwiftShader. Cesium and the tileset are served from loopback; no Ion
// token, no imagery: the globe is a plain colour and every request elsewhere is refused.
// Far away only the masses (far/) load; close to the city the full models (near/) replace them.
// The city is written with --metadata: a building picked on screen is a Cesium3DTileFeature
// whose properties are its row in the tile's property table (EXT_structural_metadata). It is
// written twice, with float vertices and with --meshopt (quantised and compressed, which
// CesiumJS decodes): both stream alike, draw the same triangles and pick the same rows.
// Run by .ci/run:
//
//   SHAPEGRAM_BIN=target/release/shapegram TILES_OUTPUT=target/ci-tiles node tests/tiles-browser/browser.mjs
//
// SHAPEGRAM_BIN: the binary (default ../../target/release/shapegram from here); TILES_OUTPUT:
// where the tileset and screenshots go (default a temporary folder); CHROMIUM: the browser.
import { chromium } from "playwright-core";
import { execFileSync } from "node:child_process";
import { createServer } from "node:http";
import { mkdirSync, mkdtempSync, readFileSync, rmSync, statSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, extname, join, normalize, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import assert from "node:assert/strict";
import { checkTileset } from "./check.mjs";

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, "../..");
const binary = resolve(process.env.SHAPEGRAM_BIN || join(root, "target/release/shapegram"));
const output = resolve(process.env.TILES_OUTPUT || mkdtempSync(join(tmpdir(), "tiles-test-")));
const browserPath = process.env.CHROMIUM || "/usr/bin/chromium";
mkdirSync(output, { recursive: true });

// 10 × 10 lots of 20 × 30 m, 28 m apart east and 40 m north, in Berlin (degrees per metre at
// 52.52° N, near enough).
const [lon0, lat0] = [13.405, 52.52];
const [perEast, perNorth] = [1 / 67_800, 1 / 111_270];
const features = [];
for (let i = 0; i < 10; i++) {
  for (let j = 0; j < 10; j++) {
    const ring = [[0, 0], [20, 0], [20, 30], [0, 30], [0, 0]].map(([dx, dy]) => [
      lon0 + (i * 28 + dx) * perEast,
      lat0 + (j * 40 + dy) * perNorth,
    ]);
    features.push({ type: "Feature", properties: { lot: i * 10 + j }, geometry: { type: "Polygon", coordinates: [ring] } });
  }
}
const lots = join(output, "city.geojson");
writeFileSync(lots, JSON.stringify({ type: "FeatureCollection", features }));
// The tilesets, by the path they are served under: floats, and meshopt-compressed.
const tilesets = { tiles: [], "tiles-meshopt": ["--meshopt"] };
for (const [name, flags] of Object.entries(tilesets)) {
  const dir = join(output, name);
  rmSync(dir, { recursive: true, force: true });
  execFileSync(binary, ["derive", "-q", join(root, "examples/house.cga"), "--lots", lots, "--crs", "wgs84",
    "--tiles", dir, "--tile-size", "100", "--metadata", ...flags], { stdio: "inherit" });
}

/** The property table rows of a GLB as Node reads it: by property id, a value per row. The
 * table's views are never compressed (EXT_meshopt_compression compresses vertices and indices),
 * so this reads meshopt tiles too. */
function propertyTable(file) {
  const bytes = readFileSync(file);
  const jsonLength = bytes.readUInt32LE(12);
  const json = JSON.parse(bytes.subarray(20, 20 + jsonLength).toString("utf8"));
  const bin = bytes.subarray(20 + jsonLength + 8);
  const metadata = json.extensions.EXT_structural_metadata;
  const table = metadata.propertyTables[0];
  const view = (i) => {
    const v = json.bufferViews[i];
    return bin.subarray(v.byteOffset || 0, (v.byteOffset || 0) + v.byteLength);
  };
  const rows = {};
  for (const [id, columns] of Object.entries(table.properties)) {
    const property = metadata.schema.classes[table.class].properties[id];
    const values = view(columns.values);
    const column = [];
    for (let row = 0; row < table.count; row++) {
      if (property.type === "STRING") {
        const offsets = view(columns.stringOffsets);
        const [start, end] = [offsets.readUInt32LE(4 * row), offsets.readUInt32LE(4 * row + 4)];
        column.push(values.subarray(start, end).toString("utf8"));
      } else if (property.componentType === "FLOAT64") {
        column.push(values.readDoubleLE(8 * row));
      } else if (property.componentType === "UINT32") {
        column.push(values.readUInt32LE(4 * row));
      }
    }
    rows[id] = column;
  }
  return rows;
}


// 3d-tiles-tools: two levels under the root, GLB content throughout.
for (const name of Object.keys(tilesets)) {
  const levels = await checkTileset(join(output, name));
  assert.equal(levels[0], undefined, "the root has no content");
  assert.ok(levels[1].every((uri) => uri.startsWith("far/")), levels[1].join());
  assert.ok(levels[2].every((uri) => uri.startsWith("near/")), levels[2].join());
  console.log(`3d-tiles-tools, ${name}: ${levels[1].length} far and ${levels[2].length} near tiles, all GLB`);
}

// A static server for Cesium's build and the tileset.
const cesium = join(here, "node_modules/cesium/Build/Cesium");
const types = { ".js": "text/javascript", ".json": "application/json", ".glb": "model/gltf-binary",
  ".css": "text/css", ".png": "image/png", ".jpg": "image/jpeg", ".wasm": "application/wasm",
  ".html": "text/html", ".svg": "image/svg+xml", ".xml": "application/xml" };
const page = `<!doctype html><html><head><meta charset="utf-8">
<link rel="stylesheet" href="/cesium/Widgets/widgets.css">
<style>html,body,#globe{margin:0;width:100%;height:100%;overflow:hidden}</style>
<script>window.CESIUM_BASE_URL = "/cesium/";</script><script src="/cesium/Cesium.js"></script>
</head><body><div id="globe"></div></body></html>`;
const server = createServer((request, response) => {
  const path = decodeURIComponent(new URL(request.url, "http://x").pathname);
  let file;
  if (path === "/") {
    response.writeHead(200, { "content-type": "text/html" }).end(page);
    return;
  } else if (path.startsWith("/cesium/")) file = join(cesium, normalize(path.slice(8)));
  else {
    const [, name, rest] = path.match(/^\/([^/]+)\/(.*)$/) || [];
    if (name in tilesets) file = join(output, name, normalize(rest));
  }
  try {
    if (!file || !statSync(file).isFile()) throw new Error("not a file");
    response.writeHead(200, { "content-type": types[extname(file)] || "application/octet-stream" });
    response.end(readFileSync(file));
  } catch {
    response.writeHead(404).end();
  }
});
await new Promise((ok) => server.listen(0, "127.0.0.1", ok));
const origin = `http://127.0.0.1:${server.address().port}`;

const browser = await chromium.launch({
  executablePath: browserPath,
  args: ["--headless", "--no-sandbox", "--disable-gpu", "--use-gl=swiftshader", "--enable-unsafe-swiftshader",
    "--disable-background-networking", "--disable-component-update", "--disable-sync", "--no-first-run"],
});
let failed = false;
try {
  const context = await browser.newContext({ viewport: { width: 800, height: 600 } });
  const refused = new Set();
  await context.route("**/*", (route) => {
    const url = new URL(route.request().url());
    if (url.origin === origin || url.protocol === "data:" || url.protocol === "blob:") return route.continue();
    refused.add(url.origin);
    return route.abort();
  });
  const float = await stream(context, "tiles");
  const meshopt = await stream(context, "tiles-meshopt");
  // The same tiles chosen and the same triangles drawn from each camera, and the same row picked.
  for (const view of ["far", "near"]) {
    const [a, b] = [float[view], meshopt[view]];
    // Tiles load in whatever order their requests finish.
    const loaded = (loads) => loads.map((p) => p.replace("/tiles-meshopt/", "/tiles/")).sort();
    assert.deepEqual(loaded(b.loads), loaded(a.loads), view);
    assert.equal(b.selected, a.selected, `${view}: tiles selected`);
    assert.equal(b.triangles, a.triangles, `${view}: triangles drawn`);
  }
  assert.deepEqual({ ...meshopt.picked, tile: meshopt.picked.tile.replace("/tiles-meshopt/", "/tiles/") },
    float.picked);
  console.log(`meshopt tiles: ${meshopt.near.triangles} triangles near and ${meshopt.far.triangles} far, ` +
    `as the float tiles; picked ${meshopt.picked.path} alike`);
  if (refused.size > 0) console.log(`refused requests to: ${[...refused].join(", ")}`);
  console.log(`tiles browser test passed (screenshots in ${output})`);
} catch (e) {
  failed = true;
  console.error(e);
} finally {
  await browser.close();
  server.close();
}
process.exit(failed ? 1 : 0);

/** Streams the tileset served under `/${name}/` in a new tab of `context`: the far and near
 * views' loads and draw statistics, and the building picked from above lot 55, checked
 * against its row of the tile's property table. */
async function stream(context, name) {
  const tab = await context.newPage();
  const errors = [];
  tab.on("pageerror", (e) => errors.push(String(e)));
  await tab.goto(origin + "/");
  await tab.evaluate(async (name) => {
    const viewer = new Cesium.Viewer("globe", {
      baseLayer: false, baseLayerPicker: false, geocoder: false, timeline: false, animation: false,
      homeButton: false, sceneModePicker: false, navigationHelpButton: false, fullscreenButton: false,
      infoBox: false, selectionIndicator: false, skyBox: false, skyAtmosphere: false,
      terrainProvider: new Cesium.EllipsoidTerrainProvider(),
    });
    viewer.scene.globe.baseColor = Cesium.Color.fromCssColorString("#6b8e5a");
    viewer.scene.backgroundColor = Cesium.Color.fromCssColorString("#dfe6ec");
    const tileset = await Cesium.Cesium3DTileset.fromUrl(`/${name}/tileset.json`);
    viewer.scene.primitives.add(tileset);
    window.loads = [];
    tileset.tileLoad.addEventListener((tile) => window.loads.push(new URL(tile.content.url, location.href).pathname));
    window.viewer = viewer;
    window.tileset = tileset;
    window.view = (range) => viewer.camera.viewBoundingSphere(tileset.boundingSphere,
      new Cesium.HeadingPitchRange(0.3, -0.5, range));
    // Straight down onto a point `range` metres below, so the centre of the screen is on it.
    window.above = ([lon, lat, height], range) => {
      const target = Cesium.Cartesian3.fromDegrees(lon, lat, height);
      viewer.camera.lookAt(target, new Cesium.HeadingPitchRange(0, -Cesium.Math.PI_OVER_TWO, range));
      viewer.camera.lookAtTransform(Cesium.Matrix4.IDENTITY);
    };
  }, name);

  /** Moves the camera by `aim` (in the page) and waits for its tiles. */
  async function look(aim, view) {
    const shot = name === "tiles" ? view : `${view}-${name}`;
    await tab.evaluate((aim) => {
      if (typeof aim === "number") window.view(aim);
      else window.above(aim.point, aim.range);
      window.settled = false;
      // tilesLoaded turns true once every tile the view needs is loaded and drawn.
      window.tileset.allTilesLoaded.addEventListener(function once() {
        window.settled = true;
        window.tileset.allTilesLoaded.removeEventListener(once);
      });
      // A view whose tiles are all loaded already raises no event: give it a few frames.
      setTimeout(() => { window.settled = true; }, 2000);
    }, aim);
    await tab.waitForFunction(() => window.settled && window.tileset.tilesLoaded, null, { timeout: 120_000 });
    await tab.waitForTimeout(500);
    await tab.screenshot({ path: join(output, `cesium-${shot}.png`) });
    return tab.evaluate(() => ({
      loads: [...window.loads],
      selected: window.tileset.statistics.selected,
      commands: window.tileset.statistics.numberOfCommands,
      triangles: window.tileset.statistics.numberOfTrianglesSelected,
    }));
  }

  const far = await look(3000, "far");
  console.log(`${name}, far camera: loaded ${far.loads.length} tiles, ${far.selected} selected, ${far.commands} draw commands, ${far.triangles} triangles`);
  assert.ok(far.loads.length > 0, "no tile was loaded from afar");
  assert.ok(far.loads.every((p) => p.startsWith(`/${name}/far/`)), `near tiles from afar: ${far.loads}`);
  assert.ok(far.selected > 0 && far.commands > 0, "nothing drawn from afar");

  const near = await look(120, "near");
  const later = near.loads.slice(far.loads.length);
  console.log(`${name}, near camera: ${later.length} more tiles, ${near.selected} selected, ${near.commands} draw commands, ${near.triangles} triangles`);
  assert.ok(later.some((p) => p.startsWith(`/${name}/near/`)), `no near tile loaded: ${later}`);
  assert.ok(near.triangles > far.triangles, "the near view draws no more detail than the far one");

  // Lot 55 (i = 5, j = 5) from 80 m straight above the middle of its footprint: the centre of
  // the screen is on its roof. Its feature's properties are its row in its near tile.
  const lot = 55;
  const centre = [lon0 + (5 * 28 + 10) * perEast, lat0 + (5 * 40 + 15) * perNorth, 3];
  await look({ point: centre, range: 80 }, "picked");
  const picked = await tab.evaluate(() => {
    const feature = window.viewer.scene.pick(new Cesium.Cartesian2(400, 300));
    if (!(feature instanceof Cesium.Cesium3DTileFeature)) return { what: String(feature) };
    return {
      what: "feature",
      tile: new URL(feature.content.url, location.href).pathname,
      ids: feature.getPropertyIds(),
      path: feature.getProperty("path"),
      rule: feature.getProperty("rule"),
      wallColor: feature.getProperty("wallColor"),
      storeys: feature.getProperty("storeys"),
    };
  });
  assert.equal(picked.what, "feature", "the pick found no feature");
  assert.ok(picked.tile.startsWith(`/${name}/near/`), picked.tile);
  const rows = propertyTable(join(output, picked.tile));
  const row = rows.path.indexOf(`Lot[${lot}]`);
  assert.ok(row >= 0, `Lot[${lot}] is not in ${picked.tile}: ${rows.path}`);
  assert.equal(picked.path, rows.path[row]);
  assert.equal(picked.rule, rows.rule[row]);
  assert.equal(picked.wallColor, rows.wallColor[row]);
  assert.equal(picked.storeys, rows.storeys[row]);
  console.log(`${name}: picked ${picked.path} in ${picked.tile}: rule ${picked.rule}, wallColor ${picked.wallColor}, ` +
    `storeys ${picked.storeys}; properties ${picked.ids.join(", ")}`);
  assert.deepEqual(errors, [], "page errors");
  await tab.close();
  return { far, near, picked };
}
