// The toolbar and the tool info panel (thesis 3.1.7): face cut (with the global option), prism
// cut (Ctrl snaps to the grid), multi-cut, the symmetric three-part cut (thesis 4.4) and
// 3-point cut. A face or prism cut starts with "C"
// on a selected face: the plane follows the pointer along the face's normal (or the typed
// distance), and a right-click or Enter completes it; Escape cancels. The 3-point cut puts a
// point on the edge under the pointer (Shift: on a vertex, Ctrl: on the grid) and a right-click
// locks it; the third completes the cut. The server cuts; here the pointer is only measured.
// What a pending cut would do is drawn as the server computes it on a copy of the project
// (its sections with the sub-shapes it cuts): while a face or prism cut's plane moves, for a
// multi- or three-part cut as soon as a face is selected, and for the 3-point cut once two
// points are locked and the pointer is on a third.
import { Vector3 } from "three";
import { post } from "./api.js";

const TOOLS = [
  ["face", "Face cut", "Select a face, press C, move the plane (or type the distance), right-click or Enter. Escape cancels. Absolute: the distance in metres is kept when the rule meets shapes of other sizes."],
  ["prism", "Prism cut", "Select a base of a prism, press C, move the plane (Ctrl snaps to the grid) or type the fraction, right-click or Enter."],
  ["multi", "Multi-cut", "Set the number of cuts, select a base of a prism, press C."],
  ["symmetric", "Three-part cut", "Set the margin (a fraction of the height below 0.5), select a base of a prism, press C: two equal outer parts and the middle."],
  ["three", "3-point cut", "Point at an edge (Shift: a vertex, Ctrl: the grid) and right-click, three times. Escape cancels."],
];

export class Tools {
  constructor(bar, info, app) {
    this.app = app;
    this.info = info;
    this.tool = "face";
    this.settings = { global: false, absolute: false, grid: 0.25, cuts: 1, margin: 0.1 };
    this.cutting = null;
    this.points = [];
    this.hover = null;
    this.sections = [];
    this.asked = 0;
    bar.replaceChildren(...TOOLS.map(([id, name]) => {
      const button = document.createElement("button");
      button.id = `tool-${id}`;
      button.textContent = name;
      button.addEventListener("click", () => this.choose(id));
      return button;
    }));
    this.bar = bar;
    this.choose("face");
  }

  choose(tool) {
    this.cancel();
    this.tool = tool;
    for (const b of this.bar.children) b.classList.toggle("active", b.id === `tool-${tool}`);
    this.showInfo();
    this.selected();
  }

  /** The tool info panel for the current tool. */
  showInfo() {
    const [, name, help] = TOOLS.find(([id]) => id === this.tool);
    const title = document.createElement("h3");
    title.textContent = name;
    const text = document.createElement("p");
    text.className = "help";
    text.textContent = help;
    const rows = [title, text];
    const field = (label, id, value, step, change) => {
      const row = document.createElement("label");
      row.className = "setting";
      const input = document.createElement("input");
      input.type = "number";
      input.id = id;
      input.step = step;
      input.value = value;
      input.addEventListener("input", () => change(Number(input.value), input));
      row.append(label, input);
      rows.push(row);
      return input;
    };
    if (this.tool === "face") {
      const row = document.createElement("label");
      row.className = "setting";
      const box = document.createElement("input");
      box.type = "checkbox";
      box.id = "global";
      box.checked = this.settings.global;
      box.addEventListener("change", () => (this.settings.global = box.checked));
      row.append(box, " global: cut every sub-shape the plane passes through");
      rows.push(row);
      const fixed = document.createElement("label");
      fixed.className = "setting";
      const absolute = document.createElement("input");
      absolute.type = "checkbox";
      absolute.id = "absolute";
      absolute.checked = this.settings.absolute;
      absolute.addEventListener("change", () => (this.settings.absolute = absolute.checked));
      fixed.append(absolute, " absolute: the distance stays in metres from the face on shapes of other sizes");
      rows.push(fixed);
      this.amount = field("distance", "cut-amount", this.cutting ? round(this.cutting.amount) : "", "any", (v) => this.typed(v));
    } else if (this.tool === "prism") {
      field("grid", "grid", this.settings.grid, "any", (v) => (this.settings.grid = v));
      this.amount = field("fraction", "cut-amount", this.cutting ? round(this.cutting.amount) : "", "any", (v) => this.typed(v));
    } else if (this.tool === "multi") {
      field("cuts", "cuts", this.settings.cuts, "1", (v) => {
        this.settings.cuts = v;
        this.selected();
      });
      this.amount = null;
    } else if (this.tool === "symmetric") {
      field("margin", "margin", this.settings.margin, "any", (v) => {
        this.settings.margin = v;
        this.selected();
      });
      this.amount = null;
    } else {
      field("grid", "grid", this.settings.grid, "any", (v) => (this.settings.grid = v));
      const placed = document.createElement("p");
      placed.id = "points-placed";
      placed.textContent = `${this.points.length} of 3 points placed`;
      rows.push(placed);
      this.amount = null;
    }
    if (this.amount) {
      this.amount.addEventListener("keydown", (event) => {
        event.stopPropagation();
        if (event.key === "Enter") this.complete();
        if (event.key === "Escape") this.cancel();
      });
    }
    this.info.replaceChildren(...rows);
  }

  /** "C": starts a face or prism cut on the selected face, or runs the multi- or three-part cut. */
  start() {
    const { selection, view } = this.app;
    if (view.rule == null) return this.app.status("cuts are made in a rule: choose or create one", true);
    if (!selection) return this.app.status("select a face first (click it)", true);
    const part = this.app.part(selection.node);
    if (!part) return;
    if (this.tool === "multi" || this.tool === "symmetric") {
      this.show([]);
      return this.app.act(this.faceAction());
    }
    if (this.tool === "three") return;
    const normal = new Vector3(...part.normals[selection.face]);
    const corners = part.faces[selection.face].map((p) => new Vector3(...p));
    const center = corners.reduce((a, p) => a.add(p), new Vector3()).multiplyScalar(1 / corners.length);
    const depths = part.faces.flat().map((p) => normal.dot(new Vector3(...p)));
    const height = Math.max(...depths) - Math.min(...depths);
    this.cutting = { node: part.node, face: selection.face, normal, center, height, amount: this.tool === "prism" ? 0.5 : height / 2 };
    this.showInfo();
    this.amount.focus();
    this.amount.select();
    this.ask(this.pendingAction());
  }

  typed(value) {
    if (!this.cutting || !Number.isFinite(value)) return;
    this.cutting.amount = value;
    this.ask(this.pendingAction());
  }

  /** The multi- or three-part cut of the selected face, as "C" would make it. */
  faceAction() {
    const { selection, view } = this.app;
    const cut = { rule: view.rule, node: selection.node, face: selection.face };
    return this.tool === "multi"
      ? { kind: "multi_cut", ...cut, cuts: Math.round(this.settings.cuts) }
      : { kind: "symmetric_cut", ...cut, margin: this.settings.margin };
  }

  /** The face or prism cut in progress, as completing it would send it. */
  pendingAction() {
    const c = this.cutting;
    const rule = this.app.view.rule;
    return this.tool === "prism"
      ? { kind: "prism_cut", rule, node: c.node, face: c.face, fraction: c.amount }
      : { kind: "face_cut", rule, node: c.node, face: c.face, distance: c.amount, global: this.settings.global, absolute: this.settings.absolute };
  }

  /** The selection changed: a multi- or three-part cut shows where "C" would cut. */
  selected() {
    const { selection, view } = this.app;
    if ((this.tool === "multi" || this.tool === "symmetric") && selection?.mode === "face" && view.rule != null && !this.cutting) {
      this.ask(this.faceAction());
    } else if (!this.cutting && this.points.length < 2 && this.sections.length) {
      this.show([]);
    }
  }

  /** Asks the server for the sections `action` would make; only the latest answer is drawn,
   * and a cut the server would refuse has none. */
  async ask(action) {
    this.asked += 1;
    const asked = this.asked;
    const { status, json } = await post("sections", { path: this.app.path, action });
    if (asked !== this.asked) return;
    this.show(status === 200 ? json.sections : []);
  }

  /** Draws `sections` (dropping any answer still on its way). */
  show(sections) {
    this.asked += 1;
    this.sections = sections;
    this.decorate();
  }

  /** Moves the plane to where the pointer points along the face's normal. */
  move(x, y, keys) {
    if (this.cutting) {
      const c = this.cutting;
      const ray = this.app.edit.ray(x, y);
      // The point of the line centre − t·normal closest to the pointer's ray.
      const d = c.normal.clone().negate();
      const w = c.center.clone().sub(ray.origin);
      const b = d.dot(ray.direction);
      const denominator = 1 - b * b;
      if (denominator < 1e-6) return;
      let t = (b * w.dot(ray.direction) - w.dot(d)) / denominator;
      t = Math.min(Math.max(t, 0), c.height);
      if (this.tool === "prism") {
        if (keys.ctrl && this.settings.grid > 0) t = Math.round(t / this.settings.grid) * this.settings.grid;
        c.amount = c.height > 0 ? t / c.height : 0;
      } else {
        c.amount = t;
      }
      if (this.amount) {
        this.amount.value = round(c.amount);
        // Typing then replaces what the pointer set.
        if (document.activeElement === this.amount) this.amount.select();
      }
      this.ask(this.pendingAction());
    } else if (this.tool === "three") {
      this.hover = this.edgePoint(x, y, keys);
      if (this.points.length === 2 && this.hover) this.ask(this.threePointAction([...this.points, this.hover]));
      else if (this.sections.length) this.show([]);
      else this.decorate();
    }
  }

  /** The 3-point cut through `points`. */
  threePointAction(points) {
    return {
      kind: "three_point_cut",
      rule: this.app.view.rule,
      points: points.map(({ node, face, corner, fraction }) => ({ node, face, corner, fraction })),
    };
  }

  /** The point on the nearest edge of the face under the pointer, as the server names it. */
  edgePoint(x, y, { ctrl, shift }) {
    const hit = this.app.edit.pick(x, y);
    if (!hit) return null;
    const loop = hit.part.faces[hit.face].map((p) => new Vector3(...p));
    let best = null;
    loop.forEach((a, corner) => {
      const b = loop[(corner + 1) % loop.length];
      const along = b.clone().sub(a);
      const length = along.length();
      let fraction = Math.min(Math.max(hit.point.clone().sub(a).dot(along) / (length * length), 0), 1);
      if (shift) fraction = fraction < 0.5 ? 0 : 1;
      else if (ctrl && this.settings.grid > 0) fraction = Math.min(Math.round((fraction * length) / this.settings.grid) * this.settings.grid / length, 1);
      // The far end exactly, as the server takes it (a + (b − a) can miss b by a rounding).
      const at = fraction === 1 ? b.clone() : a.clone().add(along.multiplyScalar(fraction));
      const distance = at.distanceTo(hit.point);
      if (!best || distance < best.distance) best = { node: hit.node, face: hit.face, corner, fraction, at: at.toArray(), distance };
    });
    return best;
  }

  /** Right-click: completes a cut, or locks a 3-point cut's point. */
  secondary() {
    if (this.cutting) return this.complete();
    if (this.tool !== "three" || !this.hover) return;
    this.points.push(this.hover);
    if (this.points.length < 3) {
      this.showInfo();
      return this.decorate();
    }
    const action = this.threePointAction(this.points);
    this.points = [];
    this.hover = null;
    this.showInfo();
    this.show([]);
    this.app.act(action);
  }

  complete() {
    if (!this.cutting) return;
    const action = this.pendingAction();
    this.cutting = null;
    this.showInfo();
    this.show([]);
    this.app.act(action);
  }

  /** Escape: drops a cut in progress or the points placed; `false` when there was none. */
  cancel() {
    const had = this.cutting !== null || this.points.length > 0;
    this.cutting = null;
    this.points = [];
    this.hover = null;
    if (had) {
      this.showInfo();
      this.show([]);
    }
    return had;
  }

  /** What the edit view draws for the tool: the sections of the pending cut, and the points. */
  overlays() {
    return {
      sections: this.sections,
      points: this.cutting ? [] : [...this.points, this.hover].filter(Boolean).map((p) => p.at),
    };
  }

  decorate() {
    this.app.decorate();
  }
}

function round(value) {
  return Math.round(value * 1e6) / 1e6;
}
