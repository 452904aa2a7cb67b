// The symbol explorer (thesis 3.1.3–3.1.4, area 4): the symbols with their rules; choosing one
// shows it in the edit view; new symbol (a box of the size typed beside its name), new rule,
// rename, delete, and the colour of the symbol shown. Names, sizes and colours are typed into
// inline fields (Enter confirms, Escape cancels), so the explorer needs no dialogs.

/** The axes of a new box symbol's size fields. */
const AXES = ["x", "y", "z"];
export class Explorer {
  constructor(root, app) {
    this.root = root;
    this.app = app;
    this.list = root.querySelector("#symbols");
    this.colorRow = root.querySelector("#symbol-color-row");
    this.color = root.querySelector("#symbol-color");
    this.naming = null;
    // "change" comes with Enter and when the field loses the focus.
    this.color.addEventListener("change", () => this.recolor());
    this.color.addEventListener("keydown", (event) => {
      if (event.key === "Escape") this.color.value = this.shownColor();
    });
    root.querySelector("#new-symbol").addEventListener("click", () => this.ask("symbol"));
    root.querySelector("#new-rule").addEventListener("click", () => this.newRule());
    root.querySelector("#rename").addEventListener("click", () => this.ask("rename"));
    root.querySelector("#delete").addEventListener("click", () => this.remove());
  }

  /** Redraws the list from the project state. */
  show(state, view) {
    const items = state.symbols.map((symbol, s) => {
      const item = document.createElement("li");
      item.append(entry(symbol.name, "symbol", s, view.rule == null && view.symbol === s, () => this.app.choose({ symbol: s })));
      const rules = document.createElement("ul");
      for (const r of symbol.rules) {
        const rule = state.rules[r];
        const li = document.createElement("li");
        li.append(entry(rule.weight === 1 ? rule.name : `${rule.name} (${rule.weight})`, "rule", r, view.rule === r, () => this.app.choose({ rule: r })));
        rules.append(li);
      }
      item.append(rules);
      return item;
    });
    this.list.replaceChildren(...items);
    if (this.naming) this.list.prepend(this.naming);
    const shown = this.shownSymbol();
    this.colorRow.hidden = shown == null;
    if (shown != null) {
      this.colorRow.querySelector("span").textContent = `colour of ${state.symbols[shown].name}`;
      if (document.activeElement !== this.color) this.color.value = this.shownColor();
    }
  }

  /** The symbol shown in the edit view, or whose rule is shown. */
  shownSymbol() {
    const { state, view } = this.app;
    if (view.rule != null) return state.rules[view.rule]?.symbol ?? null;
    return view.symbol ?? null;
  }

  /** The shown symbol's colour, `#rrggbb`, or "" for the default grey. */
  shownColor() {
    const symbol = this.shownSymbol();
    return symbol == null ? "" : this.app.state.symbols[symbol].color ?? "";
  }

  /** Gives the shown symbol the colour typed (blank: the default grey), if it changed. */
  recolor() {
    const symbol = this.shownSymbol();
    const color = this.color.value.trim();
    if (symbol == null || color === this.shownColor()) return;
    this.app.act({ kind: "set_color", symbol, color: color || null });
  }

  /** Shows the name field for a rename, or the name and size fields for a new symbol. */
  ask(purpose) {
    const { state, view } = this.app;
    let current = "";
    if (purpose === "rename") {
      if (view.rule != null) current = state.rules[view.rule].name;
      else if (view.symbol != null) current = state.symbols[view.symbol].name;
      else return this.app.status("choose a symbol or rule to rename", true);
    } else {
      let n = state.symbols.length + 1;
      while (state.symbols.some((s) => s.name === `Symbol${n}`)) n += 1;
      current = `Symbol${n}`;
    }
    this.closeField();
    const form = document.createElement("div");
    form.id = "name-form";
    const field = document.createElement("input");
    field.id = "name-field";
    field.value = current;
    field.setAttribute("aria-label", purpose === "rename" ? "New name" : "Symbol name");
    form.append(field);
    // A new symbol is a box: its size along x, y and z in metres (Tab moves between fields).
    const sizes = purpose === "symbol" ? AXES.map((axis) => {
      const size = document.createElement("input");
      size.type = "number";
      size.id = `size-${axis}`;
      size.className = "size";
      size.min = "0";
      size.step = "any";
      size.value = "1";
      size.title = `size along ${axis} (metres)`;
      size.setAttribute("aria-label", `Size along ${axis}`);
      return size;
    }) : [];
    if (sizes.length) {
      const row = document.createElement("div");
      row.className = "sizes";
      row.append("size", ...sizes);
      form.append(row);
    }
    const confirm = () => {
      const name = field.value;
      const size = sizes.map((input) => Number(input.value));
      this.closeField();
      if (purpose === "symbol") this.app.act({ kind: "add_symbol", name, size }, (made) => ({ symbol: made.index }));
      else if (view.rule != null) this.app.act({ kind: "rename_rule", rule: view.rule, name });
      else this.app.act({ kind: "rename_symbol", symbol: view.symbol, name });
    };
    for (const input of [field, ...sizes]) {
      input.addEventListener("keydown", (event) => {
        event.stopPropagation();
        if (event.key === "Escape") this.closeField();
        if (event.key === "Enter") confirm();
      });
    }
    this.naming = form;
    this.list.prepend(form);
    field.focus();
    field.select();
  }

  closeField() {
    this.naming?.remove();
    this.naming = null;
  }

  newRule() {
    const { state, view } = this.app;
    const symbol = view.rule != null ? state.rules[view.rule].symbol : view.symbol;
    if (symbol == null) return this.app.status("choose the symbol the rule rewrites", true);
    const name = `${state.symbols[symbol].name} rule ${state.symbols[symbol].rules.length + 1}`;
    this.app.act({ kind: "add_rule", symbol, name }, (made) => ({ rule: made.index }));
  }

  remove() {
    const { view } = this.app;
    if (view.rule != null) {
      this.app.act({ kind: "delete_rule", rule: view.rule }, () => ({}));
    } else if (view.symbol != null) {
      this.app.act({ kind: "delete_symbol", symbol: view.symbol }, () => ({}));
    } else {
      this.app.status("choose a symbol or rule to delete", true);
    }
  }
}

function entry(text, kind, index, chosen, choose) {
  const button = document.createElement("button");
  button.className = `entry ${kind}${chosen ? " chosen" : ""}`;
  button.dataset[kind] = String(index);
  button.textContent = text;
  button.addEventListener("click", choose);
  return button;
}
