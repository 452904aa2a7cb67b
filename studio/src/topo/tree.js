// The rule tree view (thesis 3.1.4, area 5): the cuts of the edited rule as a tree whose leaves
// are its sub-shapes; a leaf shows what it becomes, is chosen by a click (the shape selection of
// the edit view) and is hidden or shown with its eye. Below it, the chosen sub-shape's panel:
// make it a terminal, remove its volume, give it a symbol (or a new one of its shape), move and
// turn its anchor and preview it.
const NAMES = { terminal: "terminal", epsilon: "ε (removed)" };

export class TreeView {
  constructor(root, panel, app) {
    this.root = root;
    this.panel = panel;
    this.app = app;
  }

  show(state, view, selection) {
    const rule = view.rule != null ? state.rules[view.rule] : null;
    if (!rule) {
      this.root.replaceChildren();
      this.panel.replaceChildren();
      return;
    }
    const hidden = new Set(state.edit.parts.filter((p) => p.hidden).map((p) => p.node));
    const colors = new Map(state.edit.parts.map((p) => [p.node, p.color]));
    const list = document.createElement("ul");
    list.append(this.node(rule.tree, state, hidden, colors, selection));
    this.root.replaceChildren(list);
    this.showPanel(state, view, selection);
  }

  node(tree, state, hidden, colors, selection) {
    const item = document.createElement("li");
    const row = document.createElement("div");
    row.className = "tree-row";
    row.dataset.node = String(tree.node);
    if (tree.kind === "cut") {
      row.textContent = `cut ${tree.node}`;
      item.append(row);
      const children = document.createElement("ul");
      for (const child of tree.children) children.append(this.node(child, state, hidden, colors, selection));
      item.append(children);
      return item;
    }
    const swatch = document.createElement("span");
    swatch.className = "swatch";
    swatch.style.background = colors.get(tree.node) || "#ccc";
    const label = document.createElement("button");
    label.className = "leaf";
    label.textContent = `#${tree.node} ${tree.kind === "symbol" ? state.symbols[tree.symbol].name : NAMES[tree.kind]}`;
    if (selection?.node === tree.node && selection.mode === "shape") row.classList.add("chosen");
    label.addEventListener("click", () => this.app.select({ node: tree.node, face: 0, mode: "shape" }));
    const eye = document.createElement("button");
    eye.className = "eye";
    const visible = !hidden.has(tree.node);
    eye.textContent = visible ? "hide" : "show";
    eye.title = visible ? "Hide" : "Show";
    eye.addEventListener("click", () => this.app.setVisible(tree.node, !visible));
    row.append(swatch, label, eye);
    item.append(row);
    return item;
  }

  /** The chosen sub-shape's assignment buttons and, for a symbol, its anchor's. */
  showPanel(state, view, selection) {
    const part = selection && state.edit.parts.find((p) => p.node === selection.node);
    if (!part) {
      this.panel.replaceChildren();
      return;
    }
    const title = document.createElement("h3");
    title.textContent = `Sub-shape #${part.node}`;
    const button = (text, action, id) => {
      const b = document.createElement("button");
      b.textContent = text;
      if (id) b.id = id;
      b.addEventListener("click", () => this.app.act({ rule: view.rule, node: part.node, ...action }));
      return b;
    };
    const assign = document.createElement("div");
    assign.className = "buttons";
    assign.append(
      button("Terminal", { kind: "assign", to: "terminal" }, "assign-terminal"),
      button("Remove (Del)", { kind: "assign", to: "epsilon" }, "assign-epsilon"),
      ...state.symbols.map((s, i) => {
        const b = button(`→ ${s.name}`, { kind: "assign", to: { symbol: { symbol: i } } });
        b.className = "assign-symbol";
        b.dataset.symbol = String(i);
        return b;
      }),
    );
    let n = state.symbols.length + 1;
    while (state.symbols.some((x) => x.name === `Symbol${n}`)) n += 1;
    const own = button("New symbol from it", { kind: "symbol_from_leaf", name: `Symbol${n}` }, "symbol-from-leaf");
    own.title = "A new symbol with this sub-shape's shape, assigned to it (rename it in the explorer)";
    assign.append(own);
    const children = [title, assign];
    if (part.kind === "symbol") {
      const anchor = document.createElement("div");
      anchor.className = "buttons";
      const preview = document.createElement("label");
      const box = document.createElement("input");
      box.type = "checkbox";
      box.id = "preview-anchor";
      box.checked = this.app.previewing === part.node;
      box.addEventListener("change", () => this.app.preview(box.checked ? part.node : null));
      preview.append(box, " preview");
      anchor.title = "A on a selected face of the sub-shape moves the anchor there";
      anchor.append(
        "Anchor ",
        button("⟲ ,", { kind: "turn_anchor", clockwise: false }, "anchor-ccw"),
        button("⟳ .", { kind: "turn_anchor", clockwise: true }, "anchor-cw"),
        preview,
      );
      children.push(anchor);
    }
    if (selection.mode === "face" && view.rule != null) children.push(this.materialPicker(state, view, part, selection.face));
    this.panel.replaceChildren(...children);
  }

  /** The selected face's material: name, colour, tile size and optional texture; applying a
   * name that exists updates that material. */
  materialPicker(state, view, part, face) {
    const current = state.materials[part.face_materials?.[face]];
    let n = state.materials.length + 1;
    while (state.materials.some((m) => m.name === `Material${n}`)) n += 1;
    const box = document.createElement("div");
    box.className = "material";
    const heading = document.createElement("h3");
    heading.textContent = `Face ${face} material`;
    box.append(heading);
    const field = (label, id, value) => {
      const row = document.createElement("label");
      row.className = "setting";
      const input = document.createElement("input");
      input.id = id;
      input.value = value;
      row.append(label, input);
      box.append(row);
      return input;
    };
    const name = field("name", "material-name", current?.name ?? `Material${n}`);
    const color = field("colour", "material-color", current?.color ?? "#a0a0a0");
    const width = field("tile width", "material-tile-width", current?.tile[0] ?? 1);
    const height = field("tile height", "material-tile-height", current?.tile[1] ?? 1);
    const texture = field("texture", "material-texture", current?.texture ?? "");
    for (const input of [width, height]) input.type = "number";
    const buttons = document.createElement("div");
    buttons.className = "buttons";
    const apply = document.createElement("button");
    apply.id = "apply-material";
    apply.textContent = "Apply to face";
    apply.addEventListener("click", () => this.app.act({
      kind: "face_material", rule: view.rule, node: part.node, face,
      material: {
        name: name.value, color: color.value || null, texture: texture.value || null,
        tile: [Number(width.value), Number(height.value)],
      },
    }));
    const clearButton = document.createElement("button");
    clearButton.id = "clear-material";
    clearButton.textContent = "No material";
    clearButton.addEventListener("click", () => this.app.act({ kind: "face_material", rule: view.rule, node: part.node, face, material: null }));
    buttons.append(apply, clearButton);
    box.append(buttons);
    return box;
  }
}
