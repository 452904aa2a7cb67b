// The split grammar editor in a real browser (Debian's Chromium, headless, WebGL through
// SwiftShader, driven by playwright-core) against a `shapegram studio` child given a blank
// project file: tasks 1 to 8 of the Shape Grammar Editor's user test (thesis 4.1), done
// with pointer and keyboard events only, each ending in an exact check of the saved project and
// printing how many user actions (clicks, drags, key presses) it took. Run by .ci/run:
//
//   SHAPEGRAM_BIN=target/release/shapegram STUDIO_OUTPUT=target/studio node studio/tests/topo.mjs
//
// The tasks build the Mayan pyramid of the thesis's Figure 48: a `Pyramid` symbol whose rule
// `tier` keeps a stone slab (its bottom quarter) and, above it, a centre part with 10 % margins
// removed all round, which becomes the next, smaller `Pyramid` (tasks 1-5); a `Stairs` ramp cut
// by three points (6); `Steps` cut into four slabs (7) and all of them cut again at once (8);
// then the prism cut's grid snapping and the symmetric three-part cut of thesis 4.4. Task 9
// builds the whole pyramid of examples/topo_pyramid.sgproj.json in a fresh project, and its
// compiled grammar must give the example's GLBs byte for byte for seeds 0 to 9.
import { chromium } from "playwright-core";
import { execFileSync, spawn } from "node:child_process";
import { mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, join, resolve } from "node:path";
import { createInterface } from "node:readline";
import { fileURLToPath } from "node:url";
import assert from "node:assert/strict";

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, "../..");
const binary = resolve(process.env.SHAPEGRAM_BIN || join(root, "target/release/shapegram"));
const output = resolve(process.env.STUDIO_OUTPUT || mkdtempSync(join(tmpdir(), "topo-shots-")));
const browserPath = process.env.CHROMIUM || "/usr/bin/chromium";
mkdirSync(output, { recursive: true });

const folder = mkdtempSync(join(tmpdir(), "topo-test-"));
const projectFile = join(folder, "pyramid.sgproj.json");
writeFileSync(projectFile, "");

function startStudio(files) {
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

/** The user's hands: every click, drag and key press goes through here and is counted. */
class User {
  constructor(page) {
    this.page = page;
    this.actions = 0;
  }

  async settle() {
    await this.page.waitForFunction(() => window.__topo.requests.pending === 0, null, { timeout: 20000 });
  }

  async click(selector) {
    this.actions += 1;
    await this.page.locator(selector).click();
    await this.settle();
  }

  async clickAt({ x, y }) {
    this.actions += 1;
    await this.page.mouse.click(x, y);
    await this.settle();
  }

  async rightClickAt({ x, y }) {
    this.actions += 1;
    await this.page.mouse.click(x, y, { button: "right" });
    await this.settle();
  }

  async drag(from, to) {
    this.actions += 1;
    await this.page.mouse.move(from.x, from.y);
    await this.page.mouse.down();
    await this.page.mouse.move(to.x, to.y, { steps: 8 });
    await this.page.mouse.up();
    await this.settle();
  }

  /** A key or a shortcut such as Control+s: one press. */
  async press(key) {
    this.actions += 1;
    await this.page.keyboard.press(key);
    await this.settle();
  }

  /** Typing: one press per character. */
  async type(text) {
    this.actions += text.length;
    await this.page.keyboard.type(text);
    await this.settle();
  }

  /** Moves the pointer (not an action: nothing is pressed). */
  async point({ x, y }) {
    await this.page.mouse.move(x, y, { steps: 4 });
  }

  /** Clicks the centre of face `face` of sub-shape `node` in the edit view. */
  async clickFace(node, face) {
    await this.clickAt(await this.page.evaluate(([n, f]) => window.__topo.faceScreen(n, f), [node, face]));
  }

  /** Selects sub-shape `node` as the user does: its top face twice (face, then shape). */
  async selectShape(node) {
    const top = await faceTowards(this.page, node, [0, 1, 0]);
    await this.clickFace(node, top);
    await this.clickFace(node, top);
  }

  /** A face cut as the thesis's users made it: select the face, C, the distance, Enter;
   * `pending` checks the page before Enter. */
  async faceCut(node, direction, distance, pending = async () => {}) {
    const face = await faceTowards(this.page, node, direction);
    await this.clickFace(node, face);
    await this.press("c");
    // The plane follows the pointer; the distance is then typed exactly into the tool info,
    // whose field has the focus and its value selected.
    const to = await this.page.evaluate(([n, f]) => window.__topo.faceScreen(n, f), [node, face]);
    await this.point({ x: to.x - 30, y: to.y + 10 });
    await this.type(String(distance));
    await pending();
    await this.press("Enter");
  }
}

/** The sections of the pending cut the edit view draws (the server's), each polygon's corners
 * rounded and sorted, the polygons sorted. */
async function pendingSections(page) {
  const sections = await page.evaluate(() => window.__topo.tools.sections);
  const round = (p) => p.map((v) => Math.round(v * 1e9) / 1e9 + 0);
  const key = (p) => JSON.stringify(p);
  return sections
    .map((polygon) => polygon.map(round).sort((a, b) => key(a).localeCompare(key(b))))
    .sort((a, b) => key(a).localeCompare(key(b)));
}

/** A rectangle's corners sorted as `pendingSections` sorts them. */
function sortedCorners(corners) {
  const key = (p) => JSON.stringify(p);
  return corners.map((p) => p.map((v) => v + 0)).sort((a, b) => key(a).localeCompare(key(b)));
}

/** The face of sub-shape `node` whose normal points along `direction` (read from the page). */
async function faceTowards(page, node, direction) {
  return page.evaluate(([n, d]) => {
    const normals = window.__topo.part(n).normals;
    const score = (v) => v[0] * d[0] + v[1] * d[1] + v[2] * d[2];
    return normals.reduce((best, v, i) => (score(v) > score(normals[best]) ? i : best), 0);
  }, [node, direction]);
}

/** The saved project, its numbers rounded to 1e-9 (1 − 0.9 is 0.09999999999999998), −0 as 0. */
function saved() {
  const text = readFileSync(projectFile, "utf8");
  return JSON.parse(text, (_, v) => (typeof v === "number" ? Math.round(v * 1e9) / 1e9 + 0 : v));
}

const UNIT_CUBE = {
  name: "Pyramid",
  vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]],
  faces: [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]],
  anchor: [3, 0],
};

const cut = (step, point, normal, below, above) => ({ cut: { step, point, normal, below, above } });

/** Task 1, rule creation. Target: a symbol `Pyramid` (the default shape, a unit cube) with a
 * rule `tier` that does nothing yet (one uncut terminal sub-shape). */
async function ruleCreation(user) {
  await user.click("#new-symbol");
  await user.type("Pyramid");
  await user.press("Enter");
  await user.click("#new-rule");
  await user.click("#rename");
  await user.type("tier");
  await user.press("Enter");
  await user.press("Control+s");
  assert.deepEqual(saved(), {
    format: "shapegram-topo-project",
    version: 2,
    symbols: [UNIT_CUBE],
    rules: [{ name: "tier", symbol: "Pyramid", weight: 1, tree: "terminal" }],
  });
}

/** Task 2, the face cut. Target: in `tier`, the stone slab: a face cut 0.75 below the top face
 * leaves the bottom quarter (y ≤ 0.25) as one sub-shape and the rest above it. */
async function faceCut(user) {
  await user.faceCut(0, [0, 1, 0], 0.75);
  await user.press("Control+s");
  assert.deepEqual(saved().rules[0].tree, cut(0, [0.5, 0.25, 0.5], [0, 1, 0], "terminal", "terminal"));
}

/** Task 3, testing. Target: the tester, seed 7 and one generation, shows what `tier` makes of
 * the pyramid: the slab and the rest, two terminal boxes of 12 triangles each; the project is
 * unchanged. */
async function testing(user, before) {
  await user.click("#test-seed");
  await user.press("Control+a");
  await user.type("7");
  await user.click("#test");
  assert.equal(await user.page.locator("#test-result").textContent(),
    "generation 1 · 2 terminals · 0 non-terminals · 24 triangles");
  const drawn = await user.page.evaluate(() => {
    const source = document.getElementById("test-canvas");
    const copy = document.createElement("canvas");
    copy.width = source.width;
    copy.height = source.height;
    const context = copy.getContext("2d");
    context.drawImage(source, 0, 0);
    const { data } = context.getImageData(0, 0, copy.width, copy.height);
    let model = 0;
    for (let i = 0; i < data.length; i += 4) {
      if (Math.abs(data[i] - 0xee) + Math.abs(data[i + 1] - 0xf1) + Math.abs(data[i + 2] - 0xf4) > 60) model += 1;
    }
    return model / (data.length / 4);
  });
  assert.ok(drawn > 0.05, `the tester drew ${drawn} of its pixels`);
  assert.deepEqual(saved(), before);
}

/** Task 4, multiple cuts and volume removal. Target: the part above the slab gets 10 % margins
 * cut off on all four sides (four face cuts from the right and front faces) and the margins
 * removed, leaving its centre for the next tier; the tester then shows the slab and the centre. */
async function multipleCuts(user) {
  await user.faceCut(2, [1, 0, 0], 0.9); // left margin (3) | the rest (4)
  await user.faceCut(4, [1, 0, 0], 0.1); // middle (5) | right margin (6)
  await user.faceCut(5, [0, 0, 1], 0.9); // back margin (7) | the rest (8)
  await user.faceCut(8, [0, 0, 1], 0.1); // centre (9) | front margin (10)
  for (const margin of [3, 6, 7, 10]) {
    await user.selectShape(margin);
    await user.press("Delete");
  }
  await user.press("Control+s");
  assert.deepEqual(saved().rules[0].tree,
    cut(0, [0.5, 0.25, 0.5], [0, 1, 0], "terminal",
      cut(1, [0.1, 0.625, 0.5], [1, 0, 0], "epsilon",
        cut(2, [0.9, 0.625, 0.5], [1, 0, 0],
          cut(3, [0.5, 0.625, 0.1], [0, 0, 1], "epsilon",
            cut(4, [0.5, 0.625, 0.9], [0, 0, 1], "terminal", "epsilon")),
          "epsilon"))));
  await user.click("#test");
  assert.equal(await user.page.locator("#test-result").textContent(),
    "generation 1 · 2 terminals · 0 non-terminals · 24 triangles");
}

/** The RGBA pixels of canvas `id` as drawn now. */
async function canvasPixels(page, id) {
  return page.evaluate((id) => {
    const source = document.getElementById(id);
    const copy = document.createElement("canvas");
    copy.width = source.width;
    copy.height = source.height;
    const context = copy.getContext("2d");
    context.drawImage(source, 0, 0);
    return Array.from(context.getImageData(0, 0, copy.width, copy.height).data);
  }, id);
}

/** How many pixels of two same-sized captures differ by more than a little. */
function differing(a, b) {
  let count = 0;
  for (let i = 0; i < a.length; i += 4) {
    if (Math.abs(a[i] - b[i]) + Math.abs(a[i + 1] - b[i + 1]) + Math.abs(a[i + 2] - b[i + 2]) > 30) count += 1;
  }
  return count;
}

/** The anchor of sub-shape `node` as the page shows it: the edge it names, rounded. */
async function anchorOf(page, node) {
  const anchor = await page.evaluate((n) => window.__topo.part(n).anchor, node);
  const round = (p) => p.map((v) => Math.round(v * 1e9) / 1e9);
  return { face: anchor.face, corner: anchor.corner, from: round(anchor.from), to: round(anchor.to) };
}

/** Task 5, recursive rules and anchor placement. Target: the centre left by task 4 becomes a
 * `Pyramid` again (the recursion that stacks the tiers of Figure 48), anchored as the symbol's
 * own anchor stands: on the top face, along +z from the corner at the smallest x and z; the
 * anchor is turned a corner and back with the keys, previewed, and three generations give
 * three slabs under a last pyramid. */
async function recursion(user) {
  await user.selectShape(9);
  await user.click("button.assign-symbol[data-symbol='0']");
  const placed = await anchorOf(user.page, 9);
  assert.deepEqual([placed.from, placed.to], [[0.1, 1, 0.1], [0.1, 1, 0.9]]);
  await user.press(".");
  const turned = await anchorOf(user.page, 9);
  assert.equal(turned.face, placed.face, "the anchor turns round its face");
  assert.notDeepEqual(turned.from, placed.from);
  await user.press(",");
  assert.deepEqual(await anchorOf(user.page, 9), placed);
  // "A" on another face of it (the front) moves the anchor there; Ctrl+Z puts it back.
  const front = await faceTowards(user.page, 9, [0, 0, 1]);
  const moveStart = user.actions;
  await user.clickFace(9, front);
  await user.press("a");
  assert.deepEqual((await anchorOf(user.page, 9)).face, front);
  assert.equal(user.actions - moveStart, 2, "moving an anchor to another face takes two actions");
  await user.press("Control+z");
  assert.deepEqual(await anchorOf(user.page, 9), placed);
  await user.selectShape(9);
  // The preview: one generation of Pyramid's rule on the centre: a slab and a smaller centre.
  const without = await canvasPixels(user.page, "canvas");
  await user.click("#preview-anchor");
  const previewed = await user.page.evaluate(() => window.__topo.previewMesh.reduce((n, p) => n + p.positions.length / 9, 0));
  assert.equal(previewed, 24);
  // The preview is drawn over the centre: the edit view's pixels change.
  const changed = differing(without, await canvasPixels(user.page, "canvas"));
  assert.ok(changed > 200, `the preview changed ${changed} pixels of the edit view`);
  // Dragging the anchor's arrow onto the front face, near its top left corner, moves the anchor
  // there in one action (the corner nearest the drop); the preview follows it.
  const previewOf = () => user.page.evaluate(() => window.__topo.previewMesh.map((p) => p.positions));
  const previewBefore = await previewOf();
  const grip = await user.page.evaluate(() => {
    const { from, to } = window.__topo.part(9).anchor;
    return window.__topo.pointScreen(from.map((v, i) => (v + to[i]) / 2));
  });
  const corner = [0.1, 1, 0.9];
  const drop = await nearCorner(user.page, 9, front, corner);
  const dragStart = user.actions;
  await user.drag(grip, drop);
  assert.equal(user.actions - dragStart, 1, "moving an anchor by dragging takes one action");
  const dragged = await anchorOf(user.page, 9);
  assert.deepEqual([dragged.face, dragged.from], [front, corner]);
  const previewAfter = await previewOf();
  assert.equal(previewAfter.reduce((n, p) => n + p.length / 9, 0), 24);
  assert.notDeepEqual(previewAfter, previewBefore, "the preview follows the dragged anchor");
  await user.press("Control+z");
  assert.deepEqual(await anchorOf(user.page, 9), placed);
  assert.deepEqual(await previewOf(), previewBefore);
  await user.press("Control+s");
  const tree = saved().rules[0].tree;
  assert.deepEqual(tree.cut.above.cut.above.cut.below.cut.above.cut.below,
    { symbol: { name: "Pyramid", anchor: [placed.face, placed.corner] } });
  await user.click("#test-generations");
  await user.press("Control+a");
  await user.type("3");
  await user.click("#test");
  assert.equal(await user.page.locator("#test-result").textContent(),
    "generation 3 · 3 terminals · 1 non-terminals · 48 triangles");
}

/** Client coordinates of a point on face `face` of sub-shape `node` near its corner `vertex`
 * (most of the way there from the face's centre), where a pointer aims at a vertex. */
async function nearCorner(page, node, face, vertex) {
  return page.evaluate(([n, f, v]) => {
    const corners = window.__topo.part(n).faces[f];
    const centre = corners.reduce((a, p) => a.map((x, i) => x + p[i] / corners.length), [0, 0, 0]);
    return window.__topo.pointScreen(centre.map((x, i) => x + 0.85 * (v[i] - x)));
  }, [node, face, vertex]);
}

/** A new symbol (the unit cube) with a new rule, chosen for editing. */
async function newSymbolWithRule(user, name) {
  await user.click("#new-symbol");
  await user.type(name);
  await user.press("Enter");
  await user.click("#new-rule");
}

/** Task 6, the 3-point cut. Target: the pyramid's stair ramp (Figure 48): a symbol `Stairs`
 * whose rule cuts the box by the plane through its top back edge and its bottom front-left
 * corner, points put on the vertices with Shift, and removes the air above the ramp. */
async function threePointCut(user) {
  await newSymbolWithRule(user, "Stairs");
  await user.click("#tool-three");
  const top = await faceTowards(user.page, 0, [0, 1, 0]);
  const front = await faceTowards(user.page, 0, [0, 0, 1]);
  await user.page.keyboard.down("Shift");
  user.actions += 1;
  for (const [face, vertex] of [[top, [0, 1, 0]], [top, [1, 1, 0]], [front, [0, 0, 1]]]) {
    await user.point(await nearCorner(user.page, 0, face, vertex));
    await user.settle();
    if (vertex[2] === 1) {
      // Two points locked, the third under the pointer: the section the cut would make.
      assert.deepEqual(await pendingSections(user.page), [sortedCorners([[0, 1, 0], [1, 1, 0], [1, 0, 1], [0, 0, 1]])]);
    }
    await user.rightClickAt(await nearCorner(user.page, 0, face, vertex));
  }
  await user.page.keyboard.up("Shift");
  assert.deepEqual(await pendingSections(user.page), [], "nothing pending after the cut");
  // The plane's normal by the right-hand rule over the points: (0, −1, −1)/√2, so the ramp
  // (y + z < 1) is the part above the plane (node 2) and the air the part below (node 1).
  await user.selectShape(1);
  await user.press("Delete");
  await user.press("Control+s");
  const rule = saved().rules[1];
  assert.equal(rule.name, "Stairs rule 1");
  assert.equal(rule.symbol, "Stairs");
  assert.deepEqual(rule.tree, cut(0, [0, 1, 0], [0, -0.707106781, -0.707106781], "epsilon", "terminal"));
}

/** Task 7, the multi-cut. Target: the pyramid's steps: a symbol `Steps` whose rule cuts it,
 * from its top face, into four equal slabs (three cuts set in the tool info). */
async function multiCut(user) {
  await newSymbolWithRule(user, "Steps");
  await user.click("#tool-multi");
  await user.click("#cuts");
  await user.press("Control+a");
  await user.type("3");
  await user.clickFace(0, await faceTowards(user.page, 0, [0, 1, 0]));
  // The selected face shows where "C" will cut: three squares across the cube.
  const square = (y) => sortedCorners([[0, y, 0], [1, y, 0], [1, y, 1], [0, y, 1]]);
  assert.deepEqual(await pendingSections(user.page), [square(0.25), square(0.5), square(0.75)]);
  await user.press("c");
  await user.press("Control+s");
  assert.deepEqual(saved().rules[2].tree,
    cut(0, [0.5, 0.75, 0.5], [0, 1, 0],
      cut(1, [0.5, 0.5, 0.5], [0, 1, 0],
        cut(2, [0.5, 0.25, 0.5], [0, 1, 0], "terminal", "terminal"),
        "terminal"),
      "terminal"));
}

/** Task 8, the face cut's global option. Target: one face cut from the top slab's front face,
 * half way in, cuts all four slabs of `Steps` at once; the front half of the top slab is then
 * removed, setting the top step back. */
async function globalCut(user) {
  await user.click("#tool-face");
  await user.click("#global");
  // While the plane is pending it is drawn where it cuts: across all four slabs, not only the
  // face it started from.
  const across = (y0, y1) => sortedCorners([[0, y0, 0.5], [1, y0, 0.5], [1, y1, 0.5], [0, y1, 0.5]]);
  await user.faceCut(2, [0, 0, 1], 0.5, async () => {
    assert.deepEqual(await pendingSections(user.page),
      [across(0, 0.25), across(0.25, 0.5), across(0.5, 0.75), across(0.75, 1)]);
  });
  await user.selectShape(14);
  await user.press("Delete");
  await user.press("Control+s");
  const half = (step, front) => cut(step, [0.5, 0.875, 0.5], [0, 0, 1], "terminal", front);
  // Leaves are cut in depth-first order: the bottom slab (5), then 6, 4 and the top slab (2).
  assert.deepEqual(saved().rules[2].tree,
    cut(0, [0.5, 0.75, 0.5], [0, 1, 0],
      cut(1, [0.5, 0.5, 0.5], [0, 1, 0],
        cut(2, [0.5, 0.25, 0.5], [0, 1, 0], half(3, "terminal"), half(4, "terminal")),
        half(5, "terminal")),
      half(6, "epsilon")));
}

/** The prism cut with grid snapping (§3.1.7.2). Target: a second rule of `Steps` cut across
 * by a plane dragged between the cube's bases: the pointer at 0.45 of the height from the top
 * shows 0.45, with Ctrl held it snaps to the grid (0.25) at 0.5, and a right-click cuts there;
 * the upper half then becomes a new symbol of its own shape (the tree view's "new symbol"). */
async function prismCut(user) {
  await user.click("#new-rule");
  await user.click("#tool-prism");
  await user.clickFace(0, await faceTowards(user.page, 0, [0, 1, 0]));
  await user.press("c");
  // A point on the line the plane moves along (x = z = 0.5), at y = 0.55.
  const aim = await user.page.evaluate(() => window.__topo.pointScreen([0.5, 0.55, 0.5]));
  await user.point({ x: aim.x + 3, y: aim.y });
  await user.point(aim);
  assert.equal(Number(await user.page.locator("#cut-amount").inputValue()), 0.45);
  await user.page.keyboard.down("Control");
  user.actions += 1;
  await user.point({ x: aim.x + 3, y: aim.y });
  await user.point(aim);
  assert.equal(Number(await user.page.locator("#cut-amount").inputValue()), 0.5);
  await user.rightClickAt(aim);
  await user.page.keyboard.up("Control");
  await user.press("Control+s");
  const rule = saved().rules[3];
  assert.equal(rule.name, "Steps rule 2");
  assert.deepEqual(rule.tree, cut(0, [0.5, 0.5, 0.5], [0, 1, 0], "terminal", "terminal"));
  // The upper half becomes a symbol of its own: a box of half the height, assigned to it.
  await user.selectShape(2);
  await user.click("#symbol-from-leaf");
  await user.press("Control+s");
  const made = saved();
  assert.deepEqual(made.symbols.map((s) => s.name), ["Pyramid", "Stairs", "Steps", "Symbol4"]);
  const half = made.symbols[3];
  assert.deepEqual([half.vertices.length, half.faces.length], [8, 6]);
  assert.deepEqual([Math.min(...half.vertices.map((v) => v[1])), Math.max(...half.vertices.map((v) => v[1]))], [0.5, 1]);
  assert.deepEqual(made.rules[3].tree.cut.above, { symbol: { name: "Symbol4", anchor: [0, 0] } });
}

/** The symmetric three-part cut (thesis 4.4). Target: a third rule of `Steps` cutting it from
 * its top face into a top and a bottom part of 0.2 of its height each and the middle between;
 * undone and redone with the keys. */
async function symmetricCut(user) {
  await user.click("#new-rule");
  await user.click("#tool-symmetric");
  await user.click("#margin");
  await user.press("Control+a");
  await user.type("0.2");
  await user.clickFace(0, await faceTowards(user.page, 0, [0, 1, 0]));
  await user.press("c");
  await user.press("Control+s");
  const rule = saved().rules[4];
  assert.equal(rule.name, "Steps rule 3");
  assert.deepEqual(rule.tree,
    cut(0, [0.5, 0.8, 0.5], [0, 1, 0],
      cut(1, [0.5, 0.2, 0.5], [0, 1, 0], "terminal", "terminal"),
      "terminal"));
  const leaves = () => user.page.evaluate(() => window.__topo.state.edit.parts.length);
  assert.equal(await leaves(), 3);
  await user.press("Control+z");
  assert.equal(await leaves(), 1);
  await user.press("Control+y");
  assert.equal(await leaves(), 3);
}

/** The colour drawn at client point `at` of the edit view. */
async function pixelAt(page, at) {
  return page.evaluate(({ x, y }) => {
    const source = document.getElementById("canvas");
    const r = source.getBoundingClientRect();
    const copy = document.createElement("canvas");
    copy.width = source.width;
    copy.height = source.height;
    const context = copy.getContext("2d");
    context.drawImage(source, 0, 0);
    const scale = source.width / r.width;
    return Array.from(context.getImageData(Math.round((x - r.left) * scale), Math.round((y - r.top) * scale), 1, 1).data.slice(0, 3));
  }, at);
}

/** The new features of the editor model (docs/topo.md): a face cut at an absolute distance and
 * a per-face material. Target: in the three-part rule, the top part (node 2) loses a 0.1 m
 * strip along its front face by an offset cut, and the strip's front face gets a blue material
 * `lapis`, drawn in its colour in the edit view. */
async function materialAndAbsoluteCut(user) {
  await user.click("#tool-face");
  assert.equal(await user.page.locator("#global").isChecked(), true, "task 8 left the global option on");
  await user.click("#global");
  await user.click("#absolute");
  await user.faceCut(2, [0, 0, 1], 0.1);
  const front = await faceTowards(user.page, 6, [0, 0, 1]);
  const centre = await user.page.evaluate(([n, f]) => window.__topo.faceScreen(n, f), [6, front]);
  const before = await pixelAt(user.page, centre);
  await user.clickFace(6, front);
  await user.click("#material-name");
  await user.press("Control+a");
  await user.type("lapis");
  await user.click("#material-color");
  await user.press("Control+a");
  await user.type("#3050d0");
  await user.click("#apply-material");
  await user.press("Escape");
  const after = await pixelAt(user.page, centre);
  assert.ok(after[2] > after[0] + 40 && before[2] < before[0], `the face was drawn ${before}, then ${after}`);
  await user.press("Control+s");
  const project = saved();
  assert.deepEqual(project.materials, [{ name: "lapis", color: "#3050d0", tile: [1, 1] }]);
  const rule = project.rules[4];
  const strip = rule.tree.cut.above.cut;
  assert.deepEqual([strip.step, strip.point, strip.normal, strip.offset.distance, strip.below, strip.above],
    [2, [0.5, 0.9, 0.9], [0, 0, 1], 0.1, "terminal", "terminal"]);
  assert.deepEqual(rule.face_materials, [{ node: 6, face: front, material: "lapis" }]);
}

/** The 3-point cut's grid snapping (§3.1.7.4). Target: a fourth rule of `Steps` cut by the
 * plane x = 0.25: the pointer at x = 0.3 on three edges (the top face's back and front edges,
 * the front face's bottom edge) puts the points at 0.3 without Ctrl and, with Ctrl held, on
 * the grid (0.25). */
async function threePointGrid(user) {
  await user.click("#new-rule");
  await user.click("#tool-three");
  const hoverX = () => user.page.evaluate(() => window.__topo.tools.hover?.at[0]);
  const aims = [[0.3, 1, 0.03], [0.3, 1, 0.97], [0.3, 0.03, 1]];
  const screen = (p) => user.page.evaluate((q) => window.__topo.pointScreen(q), p);
  await user.point(await screen(aims[0]));
  assert.ok(Math.abs((await hoverX()) - 0.3) < 0.02, `without Ctrl the point follows the pointer: ${await hoverX()}`);
  await user.page.keyboard.down("Control");
  user.actions += 1;
  for (const aim of aims) {
    const at = await screen(aim);
    await user.point({ x: at.x + 2, y: at.y });
    await user.point(at);
    assert.equal(Math.round((await hoverX()) * 1e9) / 1e9, 0.25);
    await user.rightClickAt(at);
  }
  await user.page.keyboard.up("Control");
  await user.press("Control+s");
  const rule = saved().rules[5];
  assert.equal(rule.name, "Steps rule 4");
  assert.deepEqual(rule.tree, cut(0, [0.25, 1, 0], [1, 0, 0], "terminal", "terminal"));
}

/** Selects sub-shape `node` by its row in the rule tree (one click). */
async function chooseLeaf(user, node) {
  await user.click(`.tree-row[data-node='${node}'] .leaf`);
}

/** Removes sub-shape `node`: its row in the rule tree, then Delete. */
async function removeLeaf(user, node) {
  await chooseLeaf(user, node);
  await user.press("Delete");
}

/** Clicks the face of `node` towards `direction` and checks that the click selected it. */
async function selectFace(user, node, direction) {
  const face = await faceTowards(user.page, node, direction);
  await user.clickFace(node, face);
  const selection = await user.page.evaluate(() => window.__topo.selection);
  assert.deepEqual(selection && [selection.node, selection.face, selection.mode], [node, face, "face"],
    `a click on face ${face} of sub-shape ${node} selected ${JSON.stringify(selection)}`);
}

/** Types a colour into the explorer's colour field of the symbol shown, Enter applies it. */
async function colorSymbol(user, color) {
  await user.click("#symbol-color");
  await user.press("Control+a");
  await user.type(color);
  await user.press("Enter");
}

/** A new box symbol: name, Tab, its three sides, Enter; then its colour. */
async function newBoxSymbol(user, name, size, color) {
  await user.click("#new-symbol");
  await user.type(name);
  for (const side of size) {
    await user.press("Tab");
    await user.type(String(side));
  }
  await user.press("Enter");
  await colorSymbol(user, color);
}

/** Turns the edit view by dragging from its centre by (dx, dy) pixels. */
async function turnView(user, dx, dy) {
  const box = await user.page.locator("#canvas").boundingBox();
  const from = { x: box.x + box.width / 2, y: box.y + box.height / 2 };
  await user.drag(from, { x: from.x + dx, y: from.y + dy });
}

/** Task 9, the whole Mayan pyramid (Figure 48), in a fresh project. Target: exactly
 * examples/topo_pyramid.sgproj.json: a 16 × 8 × 16 `Pyramid` and a 16 × 2 × 16 `Stone`, each
 * in its colour; the rule `tier` cuts the pyramid's bottom quarter off as a `Stone` (prism cut
 * from the bottom face), takes 10 % margins off left and right and off back and front
 * (three-part cuts), makes the centre a `Pyramid` again, and in the middle of the front
 * margin (a 0.4 three-part cut) keeps the bottom quarter (a prism cut) cut into a ramp by a
 * 3-point cut through its top back edge and its bottom front-left corner; the ramp becomes
 * the symbol `Stairs` of its own shape. The saved project equals the example byte for byte,
 * and the compiled grammar derives the example's GLBs for seeds 0 to 9. */
async function wholePyramid(user, compiledExample) {
  await newBoxSymbol(user, "Pyramid", [16, 8, 16], "#c9b48a");
  await newBoxSymbol(user, "Stone", [16, 2, 16], "#b39d74");
  await user.click("button.entry.symbol[data-symbol='0']");
  await user.click("#new-rule");
  await user.click("#rename");
  await user.type("tier");
  await user.press("Enter");
  // Seen from below, behind and to the left: the bottom, left and back faces the cuts start
  // from (a drag right half round and up under the model).
  await turnView(user, 360, -120);
  // The slab: a prism cut a quarter up from the bottom face; it becomes a Stone.
  await user.click("#tool-prism");
  await selectFace(user, 0, [0, -1, 0]);
  await user.press("c");
  await user.type("0.25");
  await user.press("Enter");
  await chooseLeaf(user, 2);
  await user.click("button.assign-symbol[data-symbol='1']");
  // The margins: three-part cuts from the left face (its default margin is 0.1) ...
  await user.click("#tool-symmetric");
  assert.equal(await user.page.locator("#margin").inputValue(), "0.1");
  await selectFace(user, 1, [-1, 0, 0]);
  await user.press("c");
  await removeLeaf(user, 4);
  await removeLeaf(user, 5);
  // ... and from the back face of the middle; its centre is the next Pyramid.
  await selectFace(user, 6, [0, 0, -1]);
  await user.press("c");
  await removeLeaf(user, 8);
  await chooseLeaf(user, 10);
  await user.click("button.assign-symbol[data-symbol='0']");
  // The stairs: the middle of the front margin, from its left face with a margin of 0.4.
  await user.click("#margin");
  await user.press("Control+a");
  await user.type("0.4");
  await selectFace(user, 9, [-1, 0, 0]);
  await user.press("c");
  await removeLeaf(user, 12);
  await removeLeaf(user, 13);
  // Its bottom quarter, cut from its bottom face, which the slab hides: hide the slab.
  await user.click(".tree-row[data-node='2'] .eye");
  await user.click("#tool-prism");
  await selectFace(user, 14, [0, -1, 0]);
  await user.press("c");
  await user.type("0.25");
  await user.press("Enter");
  await removeLeaf(user, 15);
  // The ramp: back to the front view; three points on the vertices (Shift held): the top
  // face's back-left and back-right corners, then the front face's bottom-left corner.
  await turnView(user, -360, 120);
  await user.click("#tool-three");
  const bounds = await user.page.evaluate(() => {
    const corners = window.__topo.part(16).faces.flat();
    return [0, 1, 2].map((i) => [Math.min(...corners.map((p) => p[i])), Math.max(...corners.map((p) => p[i]))]);
  });
  const [[x0, x1], [y0, y1], [z0, z1]] = bounds;
  const top = await faceTowards(user.page, 16, [0, 1, 0]);
  const front = await faceTowards(user.page, 16, [0, 0, 1]);
  await user.page.keyboard.down("Shift");
  user.actions += 1;
  for (const [face, vertex] of [[top, [x0, y1, z0]], [top, [x1, y1, z0]], [front, [x0, y0, z1]]]) {
    const at = await nearCorner(user.page, 16, face, vertex);
    await user.point(at);
    assert.deepEqual(await user.page.evaluate(() => window.__topo.tools.hover?.at), vertex,
      "Shift puts the point on the vertex exactly");
    await user.rightClickAt(at);
  }
  await user.page.keyboard.up("Shift");
  await removeLeaf(user, 17);
  // The ramp becomes a symbol of its own shape, renamed Stairs and coloured.
  await chooseLeaf(user, 18);
  await user.click("#symbol-from-leaf");
  await user.click("button.entry.symbol[data-symbol='2']");
  await user.click("#rename");
  await user.type("Stairs");
  await user.press("Enter");
  await colorSymbol(user, "#8f7a55");
  await user.press("Control+s");
  await user.click("#compile");
  assert.equal(readFileSync(mayanFile, "utf8"), readFileSync(join(root, "examples/topo_pyramid.sgproj.json"), "utf8"),
    "the project built in the editor is the example, byte for byte");
  const grammar = join(folder, "mayan.grammar");
  assert.match(await user.page.locator("#status").textContent(), /^compiled to .*mayan\.grammar$/);
  for (let seed = 0; seed < 10; seed += 1) {
    const ours = join(folder, `mayan-${seed}.glb`);
    const theirs = join(folder, `example-${seed}.glb`);
    execFileSync(binary, ["topo", "-q", grammar, "--seed", String(seed), "-o", ours]);
    execFileSync(binary, ["topo", "-q", compiledExample, "--seed", String(seed), "-o", theirs]);
    const [a, b] = [readFileSync(ours), readFileSync(theirs)];
    assert.ok(a.length > 1000 && a.equals(b), `seed ${seed}: the GLBs differ (${a.length} and ${b.length} bytes)`);
  }
}

/** Textures in the edit view. Target: the top face of the strip cut off in the last task gets
 * a material `brick` with the example's brick texture (a file beside the project); the edit
 * view draws that face with the image, loaded from the studio. */
async function texturedFace(user) {
  mkdirSync(join(folder, "textures"), { recursive: true });
  writeFileSync(join(folder, "textures/brick.png"), readFileSync(join(root, "examples/textures/brick.png")));
  // The colours drawn along the middle of the strip's top face (x from 0.05 to 0.95 at
  // y = 1, z = 0.95): one plain colour before, bricks and mortar after.
  const shades = async () => {
    const seen = [];
    for (let k = 0; k < 19; k += 1) {
      const at = await user.page.evaluate((p) => window.__topo.pointScreen(p), [0.05 + k * 0.05, 1, 0.95]);
      const c = await pixelAt(user.page, at);
      if (!seen.some((s) => Math.abs(s[0] - c[0]) + Math.abs(s[1] - c[1]) + Math.abs(s[2] - c[2]) <= 30)) seen.push(c);
    }
    return seen.length;
  };
  assert.equal(await shades(), 1, "the face is drawn in one colour before it has a texture");
  await user.clickFace(6, await faceTowards(user.page, 6, [0, 1, 0]));
  await user.click("#material-name");
  await user.press("Control+a");
  await user.type("brick");
  await user.click("#material-texture");
  await user.type("textures/brick.png");
  await user.click("#apply-material");
  await user.press("Escape");
  await user.page.waitForFunction(() => {
    const mesh = window.__topo.edit.shapes.children.find((o) => o.isMesh && o.userData.part.node === 6);
    return [mesh?.material].flat().some((m) => m?.map?.image?.complete && m.map.image.naturalWidth > 0);
  }, null, { timeout: 10000 });
  const drawn = await user.page.evaluate(() => {
    const mesh = window.__topo.edit.shapes.children.find((o) => o.isMesh && o.userData.part.node === 6);
    const textured = mesh.material.findIndex((m) => m.map);
    const faces = mesh.geometry.groups.filter((g) => g.materialIndex === textured).length;
    return { faces, uvs: mesh.geometry.getAttribute("uv")?.count, corners: mesh.geometry.getAttribute("position").count, src: mesh.material[textured].map.image.src };
  });
  assert.equal(drawn.faces, 1, "one face is drawn with the texture");
  assert.equal(drawn.uvs, drawn.corners);
  assert.match(drawn.src, /\/api\/topo\/texture\?path=.*&texture=textures%2Fbrick\.png$/);
  const textured = await shades();
  assert.ok(textured >= 2, `the textured face shows ${textured} shades along its middle`);
}

const mayanFile = join(folder, "mayan.sgproj.json");

const { child, url } = await startStudio([projectFile]);
const browser = await chromium.launch({
  executablePath: browserPath,
  headless: true,
  args: [
    "--no-sandbox", "--disable-gpu", "--use-gl=swiftshader", "--enable-unsafe-swiftshader",
    "--disable-background-networking", "--disable-component-update", "--disable-sync", "--no-first-run",
  ],
});
try {
  const context = await browser.newContext({ viewport: { width: 1280, height: 800 }, deviceScaleFactor: 1 });
  const page = await context.newPage();
  const problems = [];
  page.on("pageerror", (e) => problems.push(e.message));
  page.on("console", (m) => m.type() === "error" && problems.push(m.text()));
  // The studio's page, given only a project, opens it in the split grammar editor.
  await page.goto(url);
  await page.waitForURL(/\/topo\?path=/);
  await page.waitForFunction(() => window.__topo && window.__topo.state !== null && window.__topo.requests.pending === 0);

  const tasks = [
    ["Task 1, rule creation", ruleCreation],
    ["Task 2, face cut", faceCut],
    ["Task 3, testing", (user) => testing(user, saved())],
    ["Task 4, multiple cuts and volume removal", multipleCuts],
    ["Task 5, recursive rules and anchor placement", recursion],
    ["Task 6, 3-point cut", threePointCut],
    ["Task 7, multi-cut", multiCut],
    ["Task 8, global cut", globalCut],
    ["Prism cut with grid snapping, new symbol from a sub-shape", prismCut],
  ];
  for (const [name, task] of tasks) {
    const user = new User(page);
    await task(user);
    await page.screenshot({ path: join(output, `topo-${name.split(",")[0].toLowerCase().replaceAll(" ", "-")}.png`) });
    console.log(`${name}: ${user.actions} user actions`);
  }

  // Undo and redo with the keyboard walk the steps back and forth: the new symbol, then the
  // prism cut, and forward again.
  const hands = new User(page);
  const leaves = () => page.evaluate(() => window.__topo.state.edit.parts.length);
  const symbols = () => page.evaluate(() => window.__topo.state.symbols.length);
  await hands.press("Control+z");
  assert.equal(await symbols(), 3);
  await hands.press("Control+z");
  assert.equal(await leaves(), 1);
  await hands.press("Control+y");
  await hands.press("Control+y");
  assert.equal(await leaves(), 2);
  assert.equal(await symbols(), 4);
  // Dragging turns the view; the project stays as it was.
  const box = await page.locator("#canvas").boundingBox();
  const before = await page.evaluate(() => window.__topo.edit.camera.position.toArray());
  await hands.drag({ x: box.x + box.width / 2, y: box.y + box.height / 2 }, { x: box.x + box.width / 2 + 120, y: box.y + box.height / 2 });
  const after = await page.evaluate(() => window.__topo.edit.camera.position.toArray());
  assert.notDeepEqual(after, before, "dragging did not turn the view");
  // Escape cancels a cut in progress: nothing is cut.
  const undoDepth = await page.evaluate(() => window.__topo.state.undo);
  await hands.selectShape(2);
  await hands.press("Escape");
  assert.equal(await page.evaluate(() => window.__topo.selection), null, "Escape (third state) clears the selection");
  await hands.clickFace(2, await faceTowards(page, 2, [0, 1, 0]));
  await hands.press("c");
  await hands.point(await page.evaluate(() => window.__topo.faceScreen(2, 0)));
  await hands.press("Escape");
  assert.equal(await page.evaluate(() => window.__topo.tools.cutting), null);
  assert.equal(await page.evaluate(() => window.__topo.state.undo), undoDepth);

  const symmetric = new User(page);
  await symmetricCut(symmetric);
  await page.screenshot({ path: join(output, "topo-symmetric-cut.png") });
  console.log(`Symmetric three-part cut: ${symmetric.actions} user actions`);
  const materials = new User(page);
  await materialAndAbsoluteCut(materials);
  await page.screenshot({ path: join(output, "topo-material.png") });
  console.log(`Absolute-distance cut and face material: ${materials.actions} user actions`);

  const texturing = new User(page);
  await texturedFace(texturing);
  await page.screenshot({ path: join(output, "topo-texture.png") });
  console.log(`Textured face: ${texturing.actions} user actions`);

  // Export GLB writes the tester's model (Steps, seed 7, 3 generations) beside the project.
  const exporter = new User(page);
  await exporter.click("#export");
  const glb = readFileSync(join(folder, "pyramid.glb"));
  assert.equal(glb.subarray(0, 4).toString("latin1"), "glTF");
  assert.match(await page.locator("#status").textContent(), new RegExp(`^exported ${glb.length} bytes to `));

  const gridded = new User(page);
  await threePointGrid(gridded);
  await page.screenshot({ path: join(output, "topo-three-point-grid.png") });
  console.log(`3-point cut with grid snapping: ${gridded.actions} user actions`);

  // Task 9 in a fresh project, opened at its address; the example compiled by the CLI.
  writeFileSync(mayanFile, "");
  await page.goto(`${url}topo?path=${encodeURIComponent(mayanFile)}`);
  await page.waitForFunction(() => window.__topo && window.__topo.state !== null && window.__topo.requests.pending === 0);
  const compiledExample = join(folder, "example.grammar");
  execFileSync(binary, ["topo", "compile", "-q", join(root, "examples/topo_pyramid.sgproj.json"), "-o", compiledExample]);
  const builder = new User(page);
  await wholePyramid(builder, compiledExample);
  await page.screenshot({ path: join(output, "topo-task-9.png") });
  console.log(`Task 9, the whole Mayan pyramid: ${builder.actions} user actions (GLBs of seeds 0-9 equal the example's)`);

  assert.deepEqual(problems, [], "errors in the page's console");
  console.log(`split grammar editor browser test: ok (screenshots in ${output})`);
} finally {
  await browser.close();
  child.kill();
  rmSync(folder, { recursive: true, force: true });
}
