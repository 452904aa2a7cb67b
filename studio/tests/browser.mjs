// The studio in a real browser: Debian's Chromium, headless, WebGL through SwiftShader, driven
// by playwright-core, against a `shapegram studio` child serving a copy of examples/house.cga
// in a temporary folder. Run by .ci/run (not by `cargo test`):
//
//   SHAPEGRAM_BIN=target/release/shapegram STUDIO_OUTPUT=target/studio node studio/tests/browser.mjs
//
// SHAPEGRAM_BIN: the binary (default ../target/release/shapegram from studio/); STUDIO_OUTPUT:
// where screenshots go (default a temporary folder); CHROMIUM: the browser (/usr/bin/chromium).
import { chromium } from "playwright-core";
import { spawn } from "node:child_process";
import { copyFileSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, join, resolve } from "node:path";
import { createInterface } from "node:readline";
import { fileURLToPath } from "node:url";
import assert from "node:assert/strict";

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, "../..");
const binary = resolve(process.env.SHAPEGRAM_BIN || join(root, "target/release/shapegram"));
const output = resolve(process.env.STUDIO_OUTPUT || mkdtempSync(join(tmpdir(), "studio-shots-")));
const browserPath = process.env.CHROMIUM || "/usr/bin/chromium";
mkdirSync(output, { recursive: true });

const folder = mkdtempSync(join(tmpdir(), "studio-test-"));
const grammar = join(folder, "house.cga");
copyFileSync(join(root, "examples/house.cga"), grammar);
// Not given, but in the folder: listed, opened from the list.
copyFileSync(join(root, "examples/office.cga"), join(folder, "office.cga"));

/** Starts `shapegram studio` on a free port; resolves with the child and the page's URL. */
function startStudio(files = [grammar]) {
  const child = spawn(binary, ["studio", ...files, "--listen", "127.0.0.1:0"], {
    stdio: ["ignore", "pipe", "inherit"],
  });
  return new Promise((resolvePromise, reject) => {
    child.on("error", reject);
    child.on("exit", (code) => reject(new Error(`shapegram studio exited with ${code}`)));
    createInterface({ input: child.stdout }).once("line", (line) => {
      const match = /^shapegram studio: (http:\/\/127\.0\.0\.1:\d+\/)$/.exec(line);
      if (!match) reject(new Error(`unexpected first line: ${line}`));
      else resolvePromise({ child, url: match[1] });
    });
  });
}

/** What the canvas shows: pixels unlike the empty background, and a 32×32 grey thumbnail. */
async function canvasPixels(page) {
  return page.evaluate(() => {
    const source = document.getElementById("canvas");
    const copy = document.createElement("canvas");
    copy.width = source.width;
    copy.height = source.height;
    const context = copy.getContext("2d");
    context.drawImage(source, 0, 0);
    const { data, width, height } = context.getImageData(0, 0, copy.width, copy.height);
    const background = [0xdf, 0xe6, 0xec];
    let model = 0;
    const thumbnail = new Array(32 * 32).fill(0);
    for (let y = 0; y < height; y++) {
      for (let x = 0; x < width; x++) {
        const i = (y * width + x) * 4;
        const far = Math.abs(data[i] - background[0]) + Math.abs(data[i + 1] - background[1])
          + Math.abs(data[i + 2] - background[2]);
        // The grid's lines are close to the background; the model's walls and roof are not.
        if (far > 60) model += 1;
        thumbnail[Math.floor((y * 32) / height) * 32 + Math.floor((x * 32) / width)] += data[i] + data[i + 1] + data[i + 2];
      }
    }
    const cell = (width / 32) * (height / 32) * 3;
    return { model, total: width * height, thumbnail: thumbnail.map((v) => v / cell) };
  });
}

function thumbnailDifference(a, b) {
  return a.thumbnail.reduce((sum, v, i) => sum + Math.abs(v - b.thumbnail[i]), 0) / a.thumbnail.length;
}

/** Edit-to-new-preview latencies: each edit replaces `from` with `to` (a pair of texts in the
 * editor), typed; from the last keystroke to the model drawn (the 40 ms debounce included). */
async function measure(page, edits) {
  const latencies = [];
  for (const [from, to] of edits) {
    await select(page, from);
    await page.keyboard.type(to);
    counts(await settled(page));
    latencies.push(await page.evaluate(() => {
      const t = window.__studio.timings[window.__studio.rendered];
      return { total: t.rendered - t.changed, server: t.answered - t.sent, draw: t.rendered - t.answered };
    }));
  }
  const median = (key) => latencies.map((l) => l[key]).sort((a, b) => a - b)[Math.floor(latencies.length / 2)];
  return `median ${median("total").toFixed(0)} ms (40 ms debounce, request and derivation `
    + `${median("server").toFixed(0)} ms, GLB load and draw ${median("draw").toFixed(0)} ms), `
    + `max ${Math.max(...latencies.map((l) => l.total)).toFixed(0)} ms over ${latencies.length} edits`;
}

/** Waits until the newest revision is derived and drawn; returns the status line. */
async function settled(page) {
  await page.waitForFunction(() => window.__studio.rendered === window.__studio.rev, null, { timeout: 20000 });
  return page.locator("#status").textContent();
}

/** Collects the page's errors into `problems`. A derivation the server answers 409 was
 * superseded by a newer edit (docs/studio.md): Chromium logs that answer as an error, but it is
 * the page working as meant. */
function watchProblems(page, problems) {
  page.on("pageerror", (e) => problems.push(e.message));
  page.on("console", (m) => {
    const superseded = /status of 409/.test(m.text()) && m.location().url.endsWith("/api/derive");
    if (m.type() === "error" && !superseded) problems.push(m.text());
  });
}

/** Accepts the first completion offered with Enter. CodeMirror ignores Enter for 75 ms after
 * the list opens (its `interactionDelay`), counted from before the test can see the list, so
 * waiting 100 ms after seeing it is always enough, however slow the page. */
async function acceptCompletion(page) {
  await page.waitForTimeout(100);
  await page.keyboard.press("Enter");
}

/** Opens `file` from the list and waits for its own model: the editor holding the file's text,
 * then that revision drawn. (Waiting on `settled` alone can read the previous file's status,
 * since the page counts the new revision only once the file has arrived.) */
async function choose(page, file) {
  const text = readFileSync(file, "utf8");
  await page.selectOption("#file", file);
  await page.waitForFunction((text) => window.__studio.view.state.doc.toString() === text, text);
  return settled(page);
}

/** Selects `text` (its `occurrence`-th match) in the editor, so that typing replaces it. */
async function select(page, text, after = false) {
  await page.evaluate(([text, after]) => {
    const view = window.__studio.view;
    const at = view.state.doc.toString().indexOf(text);
    if (at < 0) throw new Error(`no ${text} in the editor`);
    const end = at + text.length;
    view.dispatch({ selection: after ? { anchor: end } : { anchor: at, head: end } });
    view.focus();
  }, [text, after]);
}

function counts(status) {
  const match = /derived in ([\d.]+) ms · (\d+) shapes · (\d+) leaves/.exec(status);
  assert.ok(match, `status line: ${status}`);
  return { ms: Number(match[1]), shapes: Number(match[2]), leaves: Number(match[3]) };
}

/** Every kind of grammar, and completion, on a studio of its own over a folder of examples:
 * a 2D L-system shows its SVG, a topological grammar and a cave show a model, a rule just
 * written is offered by completion, and an operation is completed from the server's table. */
async function kinds(context) {
  const kindsFolder = mkdtempSync(join(tmpdir(), "studio-kinds-"));
  for (const name of ["koch-island.lsys", "grotto.cave", "topo_house.grammar", "topo_brick_house.grammar",
    "textures/brick.png", "textures/tiles.png"]) {
    mkdirSync(dirname(join(kindsFolder, name)), { recursive: true });
    copyFileSync(join(root, "examples", name), join(kindsFolder, name));
  }
  const tower = join(kindsFolder, "tower.cga");
  writeFileSync(tower, 'Lot --> extrude(10) Mass\nMass --> comp(f) { top : Roof | side : Wall }\nWall --> color("#c8b8a0")\n');
  const studio = await startStudio([join(kindsFolder, "koch-island.lsys")]);
  const page = await context.newPage();
  const problems = [];
  watchProblems(page, problems);
  try {
    // The 2D L-system: the SVG of its 4 · 8³ segments, drawn as an image.
    await page.goto(studio.url);
    const status = await settled(page);
    assert.match(status, /3 steps, 3803 modules, 2048 segments, 0 polygons/);
    const svg = await page.evaluate(() => window.__studio.svg);
    assert.ok(svg && svg.polylines > 0 && svg.bytes > 10000, `the SVG: ${JSON.stringify(svg)}`);
    const shown = await page.locator("#drawing").boundingBox();
    assert.ok(await page.locator("#drawing").isVisible() && shown.width > 300, "the drawing is not shown");
    const natural = await page.evaluate(() => document.getElementById("drawing").naturalWidth);
    assert.equal(natural, 800, "the SVG did not decode");
    await page.screenshot({ path: join(output, "studio-kinds-lsystem.png") });
    console.log(`koch-island.lsys: ${svg.polylines} polylines, ${svg.bytes} bytes of SVG`);
    // Its downloads are the model `shapegram lsystem` writes for it: tubes along the strokes.
    const drawnGlb = (await downloads(page, "#download", 1))["koch-island.glb"];
    const drawnStl = (await downloads(page, "#download-stl", 1))["koch-island.stl"];
    writeFileSync(join(output, "studio-download-koch-island.glb"), drawnGlb);
    const tubes = glbCounts(drawnGlb).triangles;
    assert.ok(tubes >= 2048 * 8, `the drawing's GLB has ${tubes} triangles`);
    assert.equal(stlCounts(drawnStl).triangles, tubes, "the drawing's STL and GLB triangles");
    console.log(`koch-island.lsys downloads: ${tubes} triangles in its GLB and STL`);

    // Topological grammars and a cave: models on the canvas, the drawing hidden; the brick
    // house's brick and roof tiles drawn from the images beside it (embedded in its GLB),
    // repeating across its faces.
    const textured = {
      "topo_house.grammar": [],
      "topo_brick_house.grammar": [
        { material: "Brick", width: 128, height: 64, repeats: true },
        { material: "RoofTiles", width: 64, height: 64, repeats: true },
      ],
      "grotto.cave": [],
    };
    for (const [name, textures] of Object.entries(textured)) {
      const made = await choose(page, join(kindsFolder, name));
      assert.equal(await page.evaluate(() => window.__studio.svg), null, `${name}: a drawing is shown`);
      assert.match(made, /^derived in [\d.]+ ms · /, `${name}: ${made}`);
      assert.equal(await page.locator("#drawing").isVisible(), false);
      const pixels = await canvasPixels(page);
      assert.ok(pixels.model > pixels.total * 0.02, `${name}: ${pixels.model} of ${pixels.total} model pixels`);
      const loaded = await page.evaluate(() => window.__studio.textures);
      assert.deepEqual(loaded.sort((a, b) => a.material.localeCompare(b.material)), textures, `${name}: textures`);
      const shot = name === "topo_brick_house.grammar" ? "brick" : name.split(".").pop();
      await page.screenshot({ path: join(output, `studio-kinds-${shot}.png`) });
      console.log(`${name}: ${made.replace(/^derived in [\d.]+ ms · /, "")}, ${pixels.model} model pixels, `
        + `${loaded.length} textures`);
    }

    // Completion: a rule just written is offered and taken; an operation is offered with the
    // signature the server gives, and taken.
    await choose(page, tower);
    await page.evaluate(() => {
      const view = window.__studio.view;
      view.dispatch({ changes: { from: view.state.doc.length, insert: 'Balcony --> color("#3a6ea5")\n' } });
    });
    await select(page, 'color("#c8b8a0")', true);
    await page.keyboard.type(" Balc");
    const offered = page.locator(".cm-tooltip-autocomplete li");
    await offered.first().waitFor();
    assert.equal(await offered.first().textContent(), "Balconyrule");
    await acceptCompletion(page);
    await page.evaluate(() => {
      const view = window.__studio.view;
      view.dispatch({ changes: { from: view.state.doc.length, insert: "Roof --> " }, selection: { anchor: view.state.doc.length + 9 } });
      view.focus();
    });
    await page.keyboard.type("roofG");
    await offered.first().waitFor();
    // First, with the signature the engine's table gives (fuzzy matches such as roofRidge follow).
    assert.equal(await offered.first().textContent(), "roofGableroofGable([byAngle | byHeight,] value [, overhangX [, overhangY [, even [, edgeIndex]]]])");
    await page.screenshot({ path: join(output, "studio-kinds-completion.png") });
    await acceptCompletion(page);
    await page.keyboard.type("(30)");
    const text = await page.evaluate(() => window.__studio.view.state.doc.toString());
    assert.equal(text, 'Lot --> extrude(10) Mass\nMass --> comp(f) { top : Roof | side : Wall }\n'
      + 'Wall --> color("#c8b8a0") Balcony\nBalcony --> color("#3a6ea5")\nRoof --> roofGable(30)');
    const completed = counts(await settled(page));
    assert.ok(completed.shapes > 5, `the completed grammar derives: ${JSON.stringify(completed)}`);
    console.log(`completion: Balcony and roofGable taken, ${completed.shapes} shapes`);
    assert.deepEqual(problems, [], "errors in the page's console");
  } finally {
    await page.close();
    studio.child.kill();
    rmSync(kindsFolder, { recursive: true, force: true });
  }
}

/** Pixels of the highlight's colour (debug.js's HIGHLIGHT, #ff22cc) on the canvas, and where
 * the middle one is (page coordinates). */
async function highlightPixels(page) {
  return page.evaluate(() => {
    const source = document.getElementById("canvas");
    const copy = document.createElement("canvas");
    copy.width = source.width;
    copy.height = source.height;
    const context = copy.getContext("2d");
    context.drawImage(source, 0, 0);
    const { data, width, height } = context.getImageData(0, 0, copy.width, copy.height);
    const found = [];
    for (let i = 0; i < width * height; i++) {
      const [r, g, b] = [data[i * 4], data[i * 4 + 1], data[i * 4 + 2]];
      if (Math.abs(r - 0xff) + Math.abs(g - 0x22) + Math.abs(b - 0xcc) < 24) found.push(i);
    }
    const rect = source.getBoundingClientRect();
    const middle = found[Math.floor(found.length / 2)] ?? 0;
    return {
      count: found.length,
      total: width * height,
      x: rect.left + ((middle % width) + 0.5) * (rect.width / width),
      y: rect.top + (Math.floor(middle / width) + 0.5) * (rect.height / height),
    };
  });
}

/** The derivation tree, picking, the generation slider and the joints (docs/studio.md), on a
 * studio of their own over fresh copies of house.cga and the excavator. */
async function visualDebugging(context) {
  const folder = mkdtempSync(join(tmpdir(), "studio-debug-"));
  const house = join(folder, "house.cga");
  const excavator = join(folder, "excavator.cga");
  copyFileSync(join(root, "examples/house.cga"), house);
  copyFileSync(join(root, "examples/excavator.cga"), excavator);
  const { child, url } = await startStudio([house, excavator]);
  const page = await context.newPage();
  const problems = [];
  watchProblems(page, problems);
  try {
    await page.goto(url);
    const full = counts(await settled(page));
    const debug = () => window.__studio.debug;

    // The tree: one initial shape, closed, with its count of children; opening it makes the
    // rows of its children only.
    assert.deepEqual(await page.locator("#tree li").allTextContents(), ["Lot (1)"]);
    await page.click("#tree li .toggle");
    assert.deepEqual(await page.locator("#tree li").count(), 2);
    assert.equal(await page.locator("#tree li li .label").textContent(), "Walls (6)");
    assert.equal(await highlightPixels(page).then((h) => h.count), 0);

    // Clicking a node highlights the leaves under it (every wall, window and roof under
    // Walls) and draws its scope box; the info panel shows its rule.
    await page.click("#tree li li .label");
    const walls = await highlightPixels(page);
    assert.ok(walls.count > walls.total * 0.02, `highlight of Walls: ${walls.count} of ${walls.total} pixels`);
    assert.equal(await page.evaluate(() => window.__studio.debug.scopeBox.visible), true);
    assert.match(await page.locator("#node-info .rule").textContent(), /^shape 1 · 6 children · rule Walls --> … \(line 21\)$/);
    await page.screenshot({ path: join(output, "studio-debug-tree.png") });
    // The rule's link selects the rule in the editor.
    await page.click("#node-info .rule a");
    const selected = await page.evaluate(() => {
      const { state } = window.__studio.view;
      const { from, to } = state.selection.main;
      return state.doc.sliceString(from, to);
    });
    assert.equal(selected, "Walls --> comp(f) { front : Front | side : Side | top : RoofBase | bottom : NIL }");
    console.log(`tree: Walls highlighted on ${walls.count} pixels`);

    // Clicking a shape in the preview selects its leaf's node: the tree opens down to it and
    // marks it, the info panel names it, and only it is highlighted now.
    await page.mouse.click(walls.x, walls.y);
    const picked = await page.evaluate(() => {
      const d = window.__studio.debug;
      return { node: d.selected, name: d.index.name(d.selected), leaf: d.index.childrenOf(d.selected).length === 0 };
    });
    assert.ok(picked.node > 1 && picked.leaf, `picked ${JSON.stringify(picked)}`);
    assert.equal(await page.locator("#tree li.selected > .label").textContent(), picked.name);
    assert.match(await page.locator("#node-info .rule").textContent(), new RegExp(`^shape ${picked.node} · leaf · `));
    const leaf = await highlightPixels(page);
    assert.ok(leaf.count > 0 && leaf.count < walls.count, `highlight of the leaf: ${leaf.count} pixels`);
    await page.screenshot({ path: join(output, "studio-debug-pick.png") });
    console.log(`picked: shape ${picked.node} (${picked.name}), ${leaf.count} pixels`);

    // The generation slider: after 2 generations only the walls' faces are there.
    const before = await canvasPixels(page);
    await page.fill("#generation", "2");
    const early = counts(await settled(page));
    assert.ok(early.shapes < full.shapes && early.leaves < full.leaves, `generation 2: ${JSON.stringify(early)}`);
    assert.equal(await page.locator("#generation-value").textContent(), `2 of ${await page.getAttribute("#generation", "max")}`);
    assert.ok(thumbnailDifference(before, await canvasPixels(page)) > 1, "the canvas did not change at generation 2");
    await page.screenshot({ path: join(output, "studio-debug-generation.png") });
    await page.fill("#generation", await page.getAttribute("#generation", "max"));
    const again = counts(await settled(page));
    assert.deepEqual([again.shapes, again.leaves], [full.shapes, full.leaves]);
    console.log(`generation 2: ${early.shapes} shapes, ${early.leaves} leaves (all: ${full.shapes}, ${full.leaves})`);

    // Joints: the excavator's are drawn and have sliders within their limits; moving the
    // boom's poses the model on the page as the engine poses it.
    await choose(page, excavator);
    const boom = page.locator('#joints input[data-section^="Boom"][data-kind="rotation"][data-axis="2"]');
    assert.equal(await boom.count(), 1);
    assert.deepEqual([await boom.getAttribute("min"), await boom.getAttribute("max")], ["-40", "60"]);
    const rest = await canvasPixels(page);
    await boom.fill("45");
    const posed = await canvasPixels(page);
    assert.ok(thumbnailDifference(rest, posed) > 0.5, "the canvas did not change with the boom at 45°");
    await page.screenshot({ path: join(output, "studio-debug-joints.png") });
    const section = await boom.getAttribute("data-section");
    const difference = await page.evaluate(async (section) => {
      const d = window.__studio.debug;
      const { bone } = d.bones.find((b) => b.joint.section === section);
      const text = window.__studio.view.state.doc.toString();
      const path = document.getElementById("file").value;
      const pose = { [section]: { rotation: [0, 0, 45] } };
      const response = await fetch("/api/derive", {
        method: "POST",
        headers: { "content-type": "application/json" },
        body: JSON.stringify({ path, text, pose }),
      });
      const answer = await response.json();
      const glb = Uint8Array.from(atob(answer.glb), (c) => c.charCodeAt(0));
      const length = new DataView(glb.buffer).getUint32(12, true);
      const gltf = JSON.parse(new TextDecoder().decode(glb.subarray(20, 20 + length)));
      const node = gltf.nodes.find((n) => n.extras?.shapegram?.joint?.section === section);
      const t = node.translation || [0, 0, 0];
      const r = node.rotation || [0, 0, 0, 1];
      const client = [...bone.position.toArray(), ...bone.quaternion.toArray()];
      return Math.max(...[...t, ...r].map((v, i) => Math.abs(v - client[i])));
    }, section);
    assert.ok(difference < 1e-6, `the page's boom pose differs from the engine's by ${difference}`);
    console.log(`joints: ${await page.locator("#joints input").count()} sliders; boom at 45° as the engine poses it (within ${difference.toExponential(1)})`);
    assert.deepEqual(problems, [], "errors in the page's console (visual debugging)");
  } finally {
    await page.close();
    child.kill();
    rmSync(folder, { recursive: true, force: true });
  }
}

/** A grammar with annotated attributes and a random colour per brick, for the panel's steps. */
const TOWER = `@Group("Mass", 1) @Order(2) @Range(min=5, max=40, stepsize=1)
@Description("Height in metres")
attr height = 12
@Group("Mass", 1) @Order(1) @Enum("flat", "hip")
attr roof = "flat"
@Color
attr wall = "#c0b090"
@Hidden
attr secret = 1
attr lit = true

@StartRule
Lot --> extrude(height) Mass
Mass --> comp(f) { top : Top | bottom : NIL | side : Wall }
Top --> case roof == "hip" : roofHip(30) color("#8b3a2f") Roof. else : color(wall) Roof.
Wall --> split(y) { ~2 : Course }*
Course --> split(x) { ~2 : Brick }*
Brick --> 50% : color("#b03020") X. else : color("#2040b0") X.
`;

/** Triangles and vertices of a GLB (indexed triangle primitives), an OBJ (faces fanned) and
 * a binary STL. */
function glbCounts(glb) {
  const length = glb.readUInt32LE(12);
  const json = JSON.parse(glb.subarray(20, 20 + length).toString("utf8"));
  let triangles = 0;
  let vertices = 0;
  for (const mesh of json.meshes) {
    for (const primitive of mesh.primitives) {
      if ((primitive.mode ?? 4) !== 4) continue;
      triangles += json.accessors[primitive.indices].count / 3;
      vertices += json.accessors[primitive.attributes.POSITION].count;
    }
  }
  return { triangles, vertices };
}

function objCounts(text) {
  let triangles = 0;
  let vertices = 0;
  for (const line of text.split("\n")) {
    if (line.startsWith("v ")) vertices += 1;
    if (line.startsWith("f ")) triangles += line.trim().split(/\s+/).length - 3;
  }
  return { triangles, vertices };
}

function stlCounts(stl) {
  const triangles = stl.readUInt32LE(80);
  assert.equal(stl.length, 84 + 50 * triangles, "the STL's length matches its triangle count");
  return { triangles, vertices: 3 * triangles };
}

/** Downloads what clicking `button` saves: by file name, the bytes. */
async function downloads(page, button, count) {
  const files = {};
  const arrived = new Promise((resolvePromise) => {
    page.on("download", async function listener(download) {
      files[download.suggestedFilename()] = readFileSync(await download.path());
      if (Object.keys(files).length === count) {
        page.off("download", listener);
        resolvePromise();
      }
    });
  });
  await page.click(button);
  await arrived;
  return files;
}

/** The attributes panel, the seed, a drawn lot and the exports, on a grammar of their own. */
async function attributesLotsAndExports(context, problems) {
  writeFileSync(join(folder, "tower.cga"), TOWER);
  const page = await context.newPage();
  watchProblems(page, problems);
  await page.goto(url);
  await settled(page);
  const plain = counts(await choose(page, join(folder, "tower.cga")));

  // The panel: a slider with its number, a select, a colour picker, a checkbox; the hidden
  // attribute left out; the group's heading.
  const slider = page.locator('#attrs-list input[type=range][data-attr="height"]');
  assert.equal(await slider.getAttribute("min"), "5");
  assert.equal(await slider.getAttribute("max"), "40");
  assert.equal(await slider.getAttribute("step"), "1");
  assert.equal(await page.locator('#attrs-list select[data-attr="roof"]').inputValue(), "0");
  assert.equal(await page.locator('#attrs-list input[type=color][data-attr="wall"]').inputValue(), "#c0b090");
  assert.equal(await page.locator('#attrs-list input[type=checkbox][data-attr="lit"]').isChecked(), true);
  assert.equal(await page.locator('#attrs-list [data-attr="secret"]').count(), 0, "a @Hidden attribute is shown");
  assert.deepEqual(await page.locator("#attrs-list h3").allTextContents(), ["Mass"]);
  // @Order: roof (1) before height (2) in the group.
  assert.deepEqual(
    await page.locator("#attrs-list [data-attr]").evaluateAll((list) => list.map((e) => e.dataset.attr)),
    ["wall", "lit", "roof", "height"],
  );
  const before = await canvasPixels(page);

  // Moving the slider derives the taller tower: another picture, the number beside it follows.
  await slider.fill("30");
  const taller = counts(await settled(page));
  assert.equal(await page.evaluate(() => window.__studio.attrs.values.height), 30);
  assert.equal(await page.locator("#attrs-list input.number").first().inputValue(), "30");
  assert.ok(taller.shapes > plain.shapes, `height 30: ${JSON.stringify(taller)} against ${JSON.stringify(plain)}`);
  const tallerPixels = await canvasPixels(page);
  assert.ok(thumbnailDifference(before, tallerPixels) > 1, "the canvas did not change with the slider");
  await page.screenshot({ path: join(output, "studio-attributes.png") });
  console.log(`attribute slider: height 12 → 30, ${plain.shapes} → ${taller.shapes} shapes`);

  // Another seed: other brick colours, the same counts.
  await page.fill("#seed", "1");
  await page.locator("#seed").dispatchEvent("change");
  const seeded = counts(await settled(page));
  assert.equal(seeded.shapes, taller.shapes);
  const seededPixels = await canvasPixels(page);
  assert.ok(thumbnailDifference(tallerPixels, seededPixels) > 0.5, "the canvas did not change with the seed");
  await page.click("#new-seed");
  await settled(page);
  const newSeed = await page.locator("#seed").inputValue();
  assert.notEqual(newSeed, "1");
  assert.equal(await page.evaluate(() => window.__studio.attrs.seed), Number(newSeed));

  // A polygon drawn on the ground: four corners, closed by clicking the first again.
  await page.selectOption("#lot-mode", "draw");
  const box = await page.locator("#canvas").boundingBox();
  // Within the preview, which shares the page with the editor and two panels.
  const corners = [[-3, -3], [9, -3], [9, 6], [-3, 6]];
  for (const corner of [...corners, corners[0]]) {
    const at = await page.evaluate((c) => window.__studio.lot.onScreen(c), corner);
    await page.mouse.click(box.x + at.x, box.y + at.y);
  }
  const drawn = counts(await settled(page));
  const lot = await page.evaluate(() => window.__studio.lot.request());
  assert.equal(lot.kind, "polygon");
  assert.equal(lot.points.length, 4);
  for (const [i, [x, z]] of lot.points.entries()) {
    assert.ok(Math.abs(x - corners[i][0]) < 0.2 && Math.abs(z - corners[i][1]) < 0.2, `corner ${i}: ${x},${z}`);
  }
  assert.notEqual(drawn.shapes, seeded.shapes, "the drawn lot gives another model");
  await page.screenshot({ path: join(output, "studio-lot.png") });
  console.log(`drawn lot ${JSON.stringify(lot.points)}: ${drawn.shapes} shapes`);

  // Downloads of what is shown: GLB, OBJ with its MTL, STL, with the same triangles.
  const glb = (await downloads(page, "#download", 1))["tower.glb"];
  const obj = await downloads(page, "#download-obj", 2);
  const stl = (await downloads(page, "#download-stl", 1))["tower.stl"];
  assert.match(obj["tower.obj"].toString("utf8"), /^mtllib tower\.mtl$/m);
  assert.match(obj["tower.mtl"].toString("utf8"), /^newmtl /m);
  writeFileSync(join(output, "studio-download-tower.glb"), glb);
  const fromGlb = glbCounts(glb);
  const fromObj = objCounts(obj["tower.obj"].toString("utf8"));
  const fromStl = stlCounts(stl);
  assert.ok(fromGlb.triangles > 0);
  assert.equal(fromObj.triangles, fromGlb.triangles, "OBJ and GLB triangles");
  assert.equal(fromStl.triangles, fromGlb.triangles, "STL and GLB triangles");
  // The GLB shares the corners its faces have in common (docs/output.md).
  assert.ok(fromGlb.vertices < 3 * fromGlb.triangles, `GLB ${fromGlb.vertices} vertices for ${fromGlb.triangles} triangles`);
  console.log(`downloads: GLB ${JSON.stringify(fromGlb)}, OBJ ${JSON.stringify(fromObj)}, STL ${JSON.stringify(fromStl)}`);

  // Lots from a file the user picks: two GeoJSON polygons; a bad file is the status's error.
  const geojson = JSON.stringify({ type: "FeatureCollection", features: [[0, 0], [30, 0]].map(([x, z]) => ({
    type: "Feature",
    geometry: { type: "Polygon", coordinates: [[[x, z], [x + 12, z], [x + 12, z + 9], [x, z + 9], [x, z]]] },
  })) });
  const pick = async (name, text) => {
    await page.setInputFiles("#lot-file", { name, mimeType: "application/json", buffer: Buffer.from(text) });
    // The page reads the file before it derives.
    await page.waitForFunction((n) => window.__studio.lot.request()?.name === n, name);
    return settled(page);
  };
  assert.match(await pick("bad.geojson", "{\"type\": \"Circle\"}"),
    /^invalid GeoJSON in bad\.geojson: the top level has the unknown type "Circle"/);
  assert.match(await pick("lots.geojson", geojson), / · 2 lots/);

  // A value that no longer fits is dropped with a note, once: renaming the attribute.
  // Each edit in one step: typed key by key, a revision in between (`extrud`) could compile
  // and drop the value before the rename is complete.
  await select(page, "attr height");
  await page.keyboard.insertText("attr tall");
  await select(page, "extrude(height)");
  await page.keyboard.insertText("extrude(tall)");
  const renamed = counts(await settled(page));
  assert.ok(renamed.shapes > 0);
  assert.deepEqual(await page.locator("#notes li").allTextContents(),
    ["`height` is no longer an attribute of the grammar: its value was dropped"]);
  assert.equal(await page.evaluate(() => "height" in window.__studio.attrs.values), false);
  await page.locator('#attrs-list input[type=range][data-attr="tall"]').fill("20");
  await settled(page);
  assert.equal(await page.locator("#notes li").count(), 0, "the note stays after the next derivation");
  await page.close();
}

const { child, url } = await startStudio();
const browser = await chromium.launch({
  executablePath: browserPath,
  headless: true,
  args: [
    "--no-sandbox", "--disable-gpu", "--use-gl=swiftshader", "--enable-unsafe-swiftshader",
    "--disable-background-networking", "--disable-component-update", "--disable-sync", "--no-first-run",
  ],
});
try {
  const context = await browser.newContext({
    viewport: { width: 1280, height: 800 },
    deviceScaleFactor: 1,
    acceptDownloads: true,
  });
  const page = await context.newPage();
  const problems = [];
  watchProblems(page, problems);

  // The page loads and draws the house.
  await page.goto(url);
  const first = counts(await settled(page));
  assert.ok(first.shapes > 100 && first.leaves > 100, `house.cga: ${JSON.stringify(first)}`);
  const loaded = await canvasPixels(page);
  assert.ok(loaded.model > loaded.total * 0.02, `the canvas shows no model: ${loaded.model} of ${loaded.total} pixels`);
  await page.screenshot({ path: join(output, "studio-loaded.png") });
  console.log(`loaded: ${first.shapes} shapes, ${first.leaves} leaves, ${loaded.model} model pixels`);

  // Typing a change derives again: a third storey, more shapes, another picture.
  await select(page, "storeys    = 2");
  await page.keyboard.type("storeys    = 3");
  const taller = counts(await settled(page));
  assert.ok(taller.shapes > first.shapes && taller.leaves > first.leaves, `3 storeys: ${JSON.stringify(taller)}`);
  const tallerPixels = await canvasPixels(page);
  assert.ok(thumbnailDifference(loaded, tallerPixels) > 1, "the canvas did not change with a third storey");
  await page.screenshot({ path: join(output, "studio-edited.png") });
  console.log(`edited: ${taller.shapes} shapes, ${taller.leaves} leaves`);

  // Edit-to-new-preview latency over roof angles typed one after another.
  const angles = ["35", "40", "45", "30", "50", "38", "42", "33", "47", "36", "35"];
  const roofEdits = angles.slice(1).map((to, i) => [`roofAngle  = ${angles[i]}`, `roofAngle  = ${to}`]);
  console.log(`house.cga edit-to-new-preview latency: ${await measure(page, roofEdits)}`);

  // An error shows at its line, in the editor and in the list, and goes when fixed.
  await select(page, "extrude(storeys * storeyH", true);
  await page.keyboard.type(" Foo");
  await page.waitForFunction(() => window.__studio.rendered === window.__studio.rev
    && window.__studio.diagnostics.some((d) => d.severity === "error"));
  const marked = await page.evaluate(() => {
    const view = window.__studio.view;
    return [...document.querySelectorAll(".cm-lintRange-error")]
      .map((e) => view.state.doc.lineAt(view.posAtDOM(e)).number);
  });
  assert.deepEqual(marked, [19], "the error is underlined on line 19");
  const listed = await page.locator("#diagnostics li.error").first().textContent();
  assert.match(listed, /^19:35 error: expected `,` or `\)`/);
  assert.match(await page.locator("#status").textContent(), /1 error/);
  await page.screenshot({ path: join(output, "studio-error.png") });
  console.log(`error shown: ${listed.split("\n")[0]}`);
  for (let i = 0; i < 4; i++) await page.keyboard.press("Backspace");
  await settled(page);
  assert.equal(await page.locator(".cm-lintRange-error").count(), 0, "the error mark stays after the fix");
  assert.equal(await page.locator("#diagnostics li").count(), 0);
  assert.deepEqual(counts(await page.locator("#status").textContent()).shapes, taller.shapes);

  // Save writes the file (read back from disk); Ctrl-S does the same.
  await page.click("#save");
  await page.waitForFunction(() => window.__studio.saved === 1);
  const text = await page.evaluate(() => window.__studio.view.state.doc.toString());
  assert.equal(readFileSync(grammar, "utf8"), text);
  assert.match(readFileSync(grammar, "utf8"), /attr storeys    = 3\n/);
  await select(page, "storeys    = 3");
  await page.keyboard.type("storeys    = 4");
  await settled(page);
  await page.keyboard.press("Control+s");
  await page.waitForFunction(() => window.__studio.saved === 2);
  assert.match(readFileSync(grammar, "utf8"), /attr storeys    = 4\n/);
  await page.screenshot({ path: join(output, "studio-saved.png") });

  // Download GLB gives the model shown.
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#download")]);
  assert.equal(download.suggestedFilename(), "house.glb");
  const glb = readFileSync(await download.path());
  assert.equal(glb.subarray(0, 4).toString("latin1"), "glTF");
  assert.equal(glb.readUInt32LE(4), 2);
  assert.equal(glb.readUInt32LE(8), glb.length);
  // .ci/run validates it with the Khronos validator.
  writeFileSync(join(output, "studio-download-house.glb"), glb);
  console.log(`downloaded house.glb: ${glb.length} bytes`);

  // Another grammar of the folder, from the list: office.cga with 12 floors, then other floor
  // heights, timed the same way.
  const office = join(folder, "office.cga");
  assert.deepEqual(await page.locator("#file option").allTextContents(), ["house.cga", "office.cga (folder)"]);
  const eight = counts(await choose(page, office));
  const heights = ["3.4", "3.5", "3.3", "3.6", "3.4"];
  const officeEdits = [["floors       = 8", "floors       = 12"],
    ...heights.slice(1).map((to, i) => [`floorHeight  = ${heights[i]}`, `floorHeight  = ${to}`])];
  const officeLatency = await measure(page, officeEdits);
  const twelve = counts(await page.locator("#status").textContent());
  assert.ok(twelve.shapes > eight.shapes, `12 floors: ${JSON.stringify(twelve)} against ${JSON.stringify(eight)}`);
  console.log(`office.cga (12 floors, ${twelve.shapes} shapes) edit-to-new-preview latency: ${officeLatency}`);
  await page.screenshot({ path: join(output, "studio-office.png") });

  await kinds(context);
  await visualDebugging(context);
  await attributesLotsAndExports(context, problems);

  assert.deepEqual(problems, [], "errors in the page's console");
  console.log(`studio browser test: ok (screenshots in ${output})`);
} finally {
  await browser.close();
  child.kill();
  rmSync(folder, { recursive: true, force: true });
}
