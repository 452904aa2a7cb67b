// The symbol explorer (thesis 3.1.3–3.1.4, area 4): the symbols with their rules; choosing one
// shows it in the edit view; new symbol, new rule, rename and delete. Names are typed into an
// inline field (Enter confirms, Escape cancels), so the explorer needs no dialogs.
export class Explorer {
  constructor(root, app) {
    this.root = root;
    this.app = app;
    this.list = root.querySelector("#symbols");
    this.naming = null;
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
  }

  /** Shows the name field for a new symbol or a rename. */
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
    const field = document.createElement("input");
    field.id = "name-field";
    field.value = current;
    field.setAttribute("aria-label", purpose === "rename" ? "New name" : "Symbol name");
    field.addEventListener("keydown", (event) => {
      event.stopPropagation();
      if (event.key === "Escape") this.closeField();
      if (event.key !== "Enter") return;
      const name = field.value;
      this.closeField();
      if (purpose === "symbol") this.app.act({ kind: "add_symbol", name }, (made) => ({ symbol: made.index }));
      else if (view.rule != null) this.app.act({ kind: "rename_rule", rule: view.rule, name });
      else this.app.act({ kind: "rename_symbol", symbol: view.symbol, name });
    });
    this.naming = field;
    this.list.prepend(field);
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
