// The studio's editor of topological split grammars (the Shape Grammar Editor, thesis 3.1):
// a `.sgproj.json` project opened in a session on the server, which does every cut, undo and
// generation; this page shows the symbol explorer, the edit view, the toolbar and tool info,
// the rule tree and the tester, and turns pointer and keys into authoring steps.
import { post, requests } from "./api.js";
import { EditView } from "./view3d.js";
import { Explorer } from "./explorer.js";
import { Tools } from "./tools.js";
import { TreeView } from "./tree.js";
import { Tester } from "./tester.js";

const $ = (id) => document.getElementById(id);
/** Pointer travel (pixels) below which a press and release is a click, not a drag. */
const CLICK_SLOP = 5;
/** An anchor being dragged to another face: its sub-shape and the face under the pointer. */
let anchorDrag = null;

const app = {
  path: new URLSearchParams(location.search).get("path"),
  state: null,
  view: {},
  selection: null,
  previewing: null,
  requests,

  status(text, error = false) {
    $("status").textContent = text;
    $("status").classList.toggle("error", error);
  },

  /** POSTs to the project's endpoint `name`; shows an error and resolves null on failure. */
  async request(name, body) {
    const { status, json } = await post(name, { path: app.path, ...body });
    if (status !== 200) {
      app.status(json.error, true);
      return null;
    }
    return json;
  },

  /** Runs an authoring step; `next(made)` may choose another view (a new symbol or rule). */
  async act(action, next) {
    const answer = await app.request("action", { action, view: app.view });
    if (!answer) return;
    if (next) {
      app.view = next(answer.made);
      await app.refresh();
    } else {
      app.show(answer.state);
    }
    await app.followPreview();
    app.status(`${action.kind.replaceAll("_", " ")} done`);
  },

  async refresh() {
    const state = await app.request("state", { view: app.view });
    if (state) app.show(state);
  },

  choose(view) {
    app.view = view;
    app.selection = null;
    app.previewing = null;
    tools.cancel();
    app.refresh();
  },

  show(state) {
    app.state = state;
    if (app.selection && !state.edit.parts.some((p) => p.node === app.selection.node)) app.selection = null;
    explorer.show(state, app.view);
    const key = state.edit.rule != null ? `rule ${state.edit.rule}` : `symbol ${state.edit.symbol}`;
    edit.show(state.edit.parts, key, state.materials, app.textureUrl);
    tree.show(state, app.view, app.selection);
    tools.selected();
    $("undo").disabled = state.undo === 0;
    $("redo").disabled = state.redo === 0;
    $("save").classList.toggle("dirty", state.dirty);
    $("toolbar").hidden = app.view.rule == null;
    const rule = app.view.rule != null ? state.rules[app.view.rule] : null;
    $("editing").textContent = rule
      ? `rule ${rule.name} of ${state.symbols[rule.symbol].name}`
      : app.view.symbol != null ? `symbol ${state.symbols[app.view.symbol].name}` : "nothing chosen";
    app.decorate();
  },

  /** Where the server serves the image of a material's texture (a path beside the project). */
  textureUrl(texture) {
    return `/api/topo/texture?path=${encodeURIComponent(app.path)}&texture=${encodeURIComponent(texture)}`;
  },

  part(node) {
    return app.state?.edit.parts.find((p) => p.node === node);
  },

  /** The symbol the tester starts from: the edited rule's, or the chosen symbol. */
  editedSymbol() {
    if (app.view.rule != null) return app.state.rules[app.view.rule]?.symbol;
    return app.view.symbol;
  },

  select(selection) {
    app.selection = selection;
    if (app.previewing !== selection?.node) app.previewing = null;
    tree.show(app.state, app.view, selection);
    tools.selected();
    app.decorate();
  },

  /** The anchor of the selected sub-shape when it is drawn (a symbol's, not hidden). */
  selectedAnchor() {
    const part = app.selection && app.part(app.selection.node);
    return part?.anchor && !part.hidden ? part : null;
  },

  async setVisible(node, visible) {
    const state = await app.request("visibility", { rule: app.view.rule, node, visible, view: app.view });
    if (state) app.show(state);
  },

  async preview(node) {
    app.previewing = node;
    app.previewMesh = null;
    if (node != null) {
      const answer = await app.request("preview", { rule: app.view.rule, node });
      app.previewMesh = answer?.parts || null;
    }
    app.decorate();
  },

  decorate() {
    const anchors = (app.state?.edit.parts || [])
      .filter((p) => p.anchor && !p.hidden && (app.selection?.node === p.node))
      .map((p) => p.anchor);
    edit.decorate({ selection: app.selection, anchors, preview: app.previewing != null ? app.previewMesh : null, target: anchorDrag?.target, ...tools.overlays() });
  },

  /** The face cycle of Fig. 15: a face, then its shape, then nothing. */
  clickFace(hit) {
    const s = app.selection;
    if (!hit) return app.select(null);
    if (s && s.node === hit.node && s.face === hit.face) {
      return app.select(s.mode === "face" ? { ...s, mode: "shape" } : null);
    }
    app.select({ node: hit.node, face: hit.face, mode: "face" });
  },

  /** The preview shows what the sub-shape turns into: after a step (a moved or turned anchor,
   * an undo) it is generated again, or dropped when the sub-shape has no symbol any more. */
  async followPreview() {
    if (app.previewing == null) return;
    if (app.part(app.previewing)?.kind === "symbol") await app.preview(app.previewing);
    else await app.preview(null);
  },

  async undo() {
    const state = await app.request("undo", { view: app.view });
    if (state) app.show(state);
    await app.followPreview();
  },

  async redo() {
    const state = await app.request("redo", { view: app.view });
    if (state) app.show(state);
    await app.followPreview();
  },

  async save() {
    const answer = await app.request("save", {});
    if (!answer) return;
    app.saved += 1;
    await app.refresh();
    app.status(`saved ${answer.bytes} bytes`);
  },

  async compile() {
    const answer = await app.request("compile", {});
    if (answer) app.status(`compiled to ${answer.path}`);
  },
  saved: 0,
};
window.__topo = app;

const edit = new EditView($("canvas"));
app.edit = edit;
const explorer = new Explorer($("explorer"), app);
const tools = new Tools($("toolbar"), $("tool-info"), app);
app.tools = tools;
const tree = new TreeView($("rule-tree"), $("shape-panel"), app);
const tester = new Tester($("tester"), app);
app.tester = tester;

/** Client coordinates of face `face` of sub-shape `node`'s centre (for the browser tests). */
app.faceScreen = (node, face) => {
  const corners = app.part(node).faces[face];
  const centre = corners.reduce((a, p) => a.map((v, i) => v + p[i] / corners.length), [0, 0, 0]);
  return edit.screenOf(centre);
};
app.pointScreen = (point) => edit.screenOf(point);

const canvas = $("canvas");
let pressed = null;
// A press on the selected sub-shape's anchor arrow starts dragging the anchor instead of
// turning the view; the listener runs before the orbit controls' (capture, on the parent).
canvas.parentElement.addEventListener("pointerdown", (event) => {
  const part = app.selectedAnchor();
  if (event.target !== canvas || event.button !== 0 || tools.cutting || !part) return;
  if (!edit.onAnchor(event.clientX, event.clientY, part.anchor)) return;
  anchorDrag = { node: part.node, target: null };
  edit.controls.enabled = false;
}, true);
canvas.addEventListener("pointerdown", (event) => {
  if (event.button === 0 && !anchorDrag) pressed = { x: event.clientX, y: event.clientY };
});
canvas.addEventListener("pointerup", (event) => {
  if (anchorDrag) return dropAnchor(event);
  if (event.button !== 0 || !pressed) return;
  const moved = Math.hypot(event.clientX - pressed.x, event.clientY - pressed.y);
  pressed = null;
  if (moved < CLICK_SLOP && !tools.cutting) app.clickFace(edit.pick(event.clientX, event.clientY));
});
canvas.addEventListener("pointermove", (event) => {
  if (anchorDrag) {
    const hit = edit.pick(event.clientX, event.clientY);
    anchorDrag.target = hit?.node === anchorDrag.node ? { node: hit.node, face: hit.face } : null;
    return app.decorate();
  }
  if (event.buttons === 0) tools.move(event.clientX, event.clientY, { ctrl: event.ctrlKey, shift: event.shiftKey });
});

// Released outside the edit view: the anchor stays where it was.
window.addEventListener("pointerup", (event) => {
  if (anchorDrag && event.target !== canvas) {
    anchorDrag = null;
    edit.controls.enabled = true;
    app.decorate();
  }
});

/** Drops a dragged anchor: on a face of its own sub-shape it moves there, its corner the one
 * nearest the pointer, so one drag both moves and turns it; anywhere else nothing changes. */
function dropAnchor(event) {
  const { node } = anchorDrag;
  anchorDrag = null;
  edit.controls.enabled = true;
  const hit = edit.pick(event.clientX, event.clientY);
  if (hit?.node !== node) return app.decorate();
  const corners = hit.part.faces[hit.face];
  const distance = (p) => Math.hypot(p[0] - hit.point.x, p[1] - hit.point.y, p[2] - hit.point.z);
  const corner = corners.reduce((best, p, k) => (distance(p) < distance(corners[best]) ? k : best), 0);
  app.act({ kind: "place_anchor", rule: app.view.rule, node, face: hit.face, corner });
}

canvas.addEventListener("contextmenu", (event) => {
  event.preventDefault();
  tools.secondary();
});

document.addEventListener("keydown", (event) => {
  const typing = event.target instanceof HTMLInputElement && event.target.type !== "checkbox";
  const mod = event.ctrlKey || event.metaKey;
  if (mod && event.key.toLowerCase() === "s") {
    event.preventDefault();
    return app.save();
  }
  if (typing) return;
  if (mod && event.key.toLowerCase() === "z" && !event.shiftKey) {
    event.preventDefault();
    return app.undo();
  }
  if (mod && (event.key.toLowerCase() === "y" || (event.key.toLowerCase() === "z" && event.shiftKey))) {
    event.preventDefault();
    return app.redo();
  }
  if (mod) return;
  const s = app.selection;
  if (event.key === "Escape") {
    if (!tools.cancel()) app.select(null);
  } else if (event.key === "c" || event.key === "C") {
    event.preventDefault();
    tools.start();
  } else if ((event.key === "Delete" || event.key === "Backspace") && s && app.view.rule != null) {
    app.act({ kind: "assign", rule: app.view.rule, node: s.node, to: "epsilon" });
  } else if ((event.key === "a" || event.key === "A") && s?.mode === "face" && app.part(s.node)?.kind === "symbol") {
    // The anchor moves to the selected face, at its first corner; "," and "." turn it from there.
    app.act({ kind: "place_anchor", rule: app.view.rule, node: s.node, face: s.face, corner: 0 });
  } else if ((event.key === "," || event.key === ".") && s && app.part(s.node)?.kind === "symbol") {
    app.act({ kind: "turn_anchor", rule: app.view.rule, node: s.node, clockwise: event.key === "." });
  }
});

$("undo").addEventListener("click", () => app.undo());
$("redo").addEventListener("click", () => app.redo());
$("save").addEventListener("click", () => app.save());
$("compile").addEventListener("click", () => app.compile());
window.addEventListener("beforeunload", (event) => {
  if (app.state?.dirty) event.preventDefault();
});

async function start() {
  if (!app.path) return app.status("no project: open a .sgproj.json file from the studio's file list", true);
  $("project").textContent = app.path.split(/[\\/]/).pop();
  const state = await app.request("open", { view: {} });
  if (!state) return;
  app.view = state.symbols.length ? (state.rules.length ? { rule: 0 } : { symbol: 0 }) : {};
  await app.refresh();
  app.status(`opened: ${state.symbols.length} symbols, ${state.rules.length} rules`);
}
start();
