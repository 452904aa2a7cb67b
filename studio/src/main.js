// Shapegram Studio's page: a CodeMirror editor on the left, a three.js preview on the right.
// Every change is sent to the server (debounced) as text to derive; the answer brings the GLB
// and the parser's diagnostics. The server derives; this page only draws.
import { EditorState } from "@codemirror/state";
import { EditorView, keymap, lineNumbers, highlightActiveLine, drawSelection } from "@codemirror/view";
import { defaultKeymap, history, historyKeymap, indentWithTab } from "@codemirror/commands";
import { bracketMatching, indentOnInput } from "@codemirror/language";
import { setDiagnostics, lintGutter } from "@codemirror/lint";
import { languageFor } from "./languages/index.js";
import { completionFor, loadVocabulary } from "./complete.js";
import { Drawing } from "./drawing.js";
import { Preview } from "./preview.js";
import { Debugger } from "./debug.js";
import { AttrsPanel } from "./attrs.js";
import { LotEditor } from "./lot.js";
import * as exports from "./exports.js";

/** How long typing must pause before the text is derived. */
const DEBOUNCE_MS = 40;

const $ = (id) => document.getElementById(id);
const statusLine = $("status");
const fileSelect = $("file");
const diagnosticsList = $("diagnostics");

/** What the browser test watches: revisions sent, the one drawn, timings per revision, the editor. */
const studio = {
  rev: 0,
  rendered: -1,
  answered: -1,
  diagnostics: [],
  shapes: 0,
  leaves: 0,
  timings: {},
  saved: 0,
  svg: null,
  /** The shown model's textured materials (`Preview.textures`). */
  textures: [],
};
window.__studio = studio;

let path = null;
let savedText = "";
let lastGlb = null;
let timer = null;
let drawnRev = -1;
/** The request whose model is shown: what the exports derive. */
let shownRequest = null;

const preview = new Preview($("canvas"));
const drawing = new Drawing($("drawing"));
const debug = new Debugger(preview, {
  tree: $("tree"),
  info: $("node-info"),
  generation: $("generation"),
  generationValue: $("generation-value"),
  joints: $("joints"),
}, {
  rederive: () => {
    studio.rev += 1;
    studio.timings[studio.rev] = { changed: performance.now() };
    derive();
  },
  jump: (place) => {
    const doc = view.state.doc;
    const from = position(doc, place.line, place.column);
    const to = position(doc, place.end_line, place.end_column);
    // Scrolled to the rule's start: a long rule would otherwise scroll the editor sideways.
    view.dispatch({ selection: { anchor: from, head: to }, effects: EditorView.scrollIntoView(from, { y: "center", x: "start" }) });
    view.focus();
  },
});
studio.debug = debug;
const attrs = new AttrsPanel($("side"), changed);
const lot = new LotEditor($("side"), preview, changed);
studio.attrs = attrs;
studio.lot = lot;

const view = new EditorView({
  parent: $("editor"),
  state: EditorState.create({ doc: "", extensions: editorExtensions() }),
});
studio.view = view;

function editorExtensions() {
  return [
    lineNumbers(),
    history(),
    drawSelection(),
    highlightActiveLine(),
    indentOnInput(),
    bracketMatching(),
    lintGutter(),
    languageFor(path),
    completionFor(path),
    keymap.of([
      { key: "Mod-s", preventDefault: true, run: () => (save(), true) },
      indentWithTab,
      ...defaultKeymap,
      ...historyKeymap,
    ]),
    EditorView.updateListener.of((update) => {
      if (update.docChanged) changed();
    }),
  ];
}

function setStatus(text, error = false) {
  statusLine.textContent = text;
  statusLine.classList.toggle("error", error);
  statusLine.classList.toggle("dirty", path !== null && view.state.doc.toString() !== savedText);
}

function changed() {
  studio.rev += 1;
  studio.timings[studio.rev] = { changed: performance.now() };
  clearTimeout(timer);
  timer = setTimeout(derive, DEBOUNCE_MS);
  setStatus(statusLine.textContent.replace(/^● /, ""));
}

async function api(method, url, body) {
  const response = await fetch(url, {
    method,
    headers: body ? { "content-type": "application/json" } : {},
    body: body ? JSON.stringify(body) : undefined,
  });
  const json = await response.json();
  return { status: response.status, json };
}

async function loadFiles() {
  const { status, json } = await api("GET", "/api/files");
  if (status !== 200) return setStatus(json.error, true);
  fileSelect.replaceChildren(
    ...json.files.map((f) => {
      const option = document.createElement("option");
      option.value = f.path;
      option.textContent = f.given ? f.name : `${f.name} (folder)`;
      return option;
    }),
  );
  if (json.files.length > 0) await open(json.files[0].path);
  else setStatus("no grammar files here", true);
}

/** Topological split grammar projects open in their own editor page. */
const PROJECT_SUFFIX = ".sgproj.json";

async function open(file) {
  if (file.endsWith(PROJECT_SUFFIX)) {
    if (path !== null && view.state.doc.toString() !== savedText
        && !confirm("Discard the unsaved changes?")) {
      fileSelect.value = path;
      return;
    }
    // Discarded (or clean): leaving must not ask again.
    path = null;
    location.assign(`/topo?path=${encodeURIComponent(file)}`);
    return;
  }
  if (path !== null && view.state.doc.toString() !== savedText
      && !confirm("Discard the unsaved changes?")) {
    fileSelect.value = path;
    return;
  }
  const { status, json } = await api("GET", `/api/file?path=${encodeURIComponent(file)}`);
  if (status !== 200) return setStatus(json.error, true);
  path = file;
  fileSelect.value = file;
  preview.reset();
  debug.reset();
  attrs.reset();
  view.setState(EditorState.create({ doc: json.text, extensions: editorExtensions() }));
  savedText = view.state.doc.toString();
  studio.rev += 1;
  studio.timings[studio.rev] = { changed: performance.now() };
  derive();
}

async function derive() {
  clearTimeout(timer);
  const rev = studio.rev;
  const text = view.state.doc.toString();
  const timing = studio.timings[rev] || (studio.timings[rev] = {});
  timing.sent = performance.now();
  const generations = debug.generations();
  const request = { path, text, tree: true, generations, ...attrs.settings() };
  if (lot.request()) request.lot = lot.request();
  let answer;
  try {
    answer = await api("POST", "/api/derive", request);
  } catch (e) {
    return setStatus(`cannot reach the studio: ${e.message}`, true);
  }
  // An answer to an older revision, or one the server dropped for a newer request.
  if (rev < drawnRev || rev !== studio.rev || answer.status === 409) return;
  const { status, json } = answer;
  timing.answered = performance.now();
  studio.answered = rev;
  if (status !== 200) return setStatus(json.error, true);
  drawnRev = rev;
  showDiagnostics(json.diagnostics);
  attrs.show(json.attrs, json.dropped);
  $("notes").replaceChildren(...json.notes.map((note) => {
    const item = document.createElement("li");
    item.textContent = note;
    return item;
  }));
  const errors = json.diagnostics.filter((d) => d.severity === "error" && !d.file).length;
  if (json.ok) {
    if (json.svg) {
      // A drawing's downloads are its model, which the server makes (see download()).
      lastGlb = null;
      studio.svg = await drawing.show(json.svg);
      studio.textures = [];
      debug.load(null, null, generations);
    } else {
      drawing.hide();
      studio.svg = null;
      lastGlb = Uint8Array.from(atob(json.glb), (c) => c.charCodeAt(0));
      await preview.show(lastGlb.buffer, (gltf) => debug.load(json.tree, gltf, generations));
      studio.textures = preview.textures();
    }
    shownRequest = request;
    studio.shapes = json.shapes;
    studio.leaves = json.leaves;
    const warnings = json.diagnostics.length ? ` · ${json.diagnostics.length} warnings` : "";
    const lots = json.lots > 1 ? ` · ${json.lots} lots` : "";
    const made = json.summary || `${json.shapes} shapes · ${json.leaves} leaves${lots}`;
    setStatus(`derived in ${json.derive_ms.toFixed(1)} ms · ${made}${warnings}`);
  } else if (json.error) {
    setStatus(json.error, true);
  } else {
    setStatus(`${errors} ${errors === 1 ? "error" : "errors"}: the preview shows the last model`, true);
  }
  timing.rendered = performance.now();
  studio.rendered = rev;
}

/** Line and column (1-based, in characters) to a document position. */
function position(doc, line, column) {
  const l = doc.line(Math.max(1, Math.min(line, doc.lines)));
  return Math.min(l.from + Math.max(0, column - 1), l.to);
}

function showDiagnostics(list) {
  const doc = view.state.doc;
  studio.diagnostics = list;
  const own = list.filter((d) => !d.file);
  const marks = own.map((d) => {
    const from = position(doc, d.line, d.column);
    let to = position(doc, d.end_line, d.end_column);
    if (to <= from) to = Math.min(from + 1, doc.length);
    const hints = d.hints.map((h) => `\nhint: ${h}`).join("");
    const label = d.label ? ` (${d.label})` : "";
    return { from, to, severity: d.severity, message: `${d.message}${label}${hints}`, source: "shapegram" };
  });
  view.dispatch(setDiagnostics(view.state, marks));
  diagnosticsList.replaceChildren(
    ...list.map((d) => {
      const item = document.createElement("li");
      item.className = d.severity;
      const where = d.file ? `${d.file}:${d.line}:${d.column}` : `${d.line}:${d.column}`;
      item.textContent = `${where} ${d.severity}: ${d.message}${d.hints.map((h) => `\n    hint: ${h}`).join("")}`;
      if (!d.file) {
        item.addEventListener("click", () => {
          const at = position(view.state.doc, d.line, d.column);
          view.dispatch({ selection: { anchor: at }, scrollIntoView: true });
          view.focus();
        });
      }
      return item;
    }),
  );
}

async function save() {
  if (path === null) return;
  const text = view.state.doc.toString();
  const { status, json } = await api("PUT", "/api/file", { path, text });
  if (status !== 200) return setStatus(`not saved: ${json.error}`, true);
  savedText = text;
  studio.saved += 1;
  setStatus(`saved ${json.bytes} bytes (${json.encoding}, ${json.line_endings})`);
}

function download() {
  if (lastGlb) return exports.save(lastGlb, `${stem()}.glb`, "model/gltf-binary");
  // A 2D L-system is shown as its SVG: its GLB is the tube model `shapegram lsystem` writes.
  downloadAs("glb");
}

/** The edited file's name without its extension. */
function stem() {
  return (path || "model").split(/[\\/]/).pop().replace(/\.[^.]*$/, "");
}

async function downloadAs(format) {
  if (!shownRequest) return setStatus("no model to download yet", true);
  try {
    // The tree is the preview's alone; the export derives the same model without it.
    const { tree: _, ...request } = shownRequest;
    await exports.download(request, format);
  } catch (e) {
    setStatus(`not exported: ${e.message}`, true);
  }
}

$("save").addEventListener("click", save);
$("download").addEventListener("click", download);
$("download-obj").addEventListener("click", () => downloadAs("obj"));
$("download-stl").addEventListener("click", () => downloadAs("stl"));
fileSelect.addEventListener("change", () => open(fileSelect.value));
window.addEventListener("beforeunload", (event) => {
  if (path !== null && view.state.doc.toString() !== savedText) event.preventDefault();
});
loadVocabulary();
loadFiles();
