// The attributes panel: one control per attribute the server reports (a slider with its number
// for @Range, a colour picker for @Color, a select for @Enum, a checkbox for booleans, a text
// field otherwise), grouped and ordered by @Group and @Order, without @Hidden ones, with
// @Description as the tooltip, as CityEngine's Inspector shows them; and the seed. The user's
// values are kept by name and sent with every derivation; the server drops those that no longer
// fit and says so, and the panel forgets them.

export class AttrsPanel {
  /** `onChange` is called when a value or the seed changes. */
  constructor(root, onChange) {
    this.root = root;
    this.onChange = onChange;
    /** The user's values by attribute name. */
    this.values = {};
    this.seed = 0;
    this.list = root.querySelector("#attrs-list");
    /** What the rows show apart from the values, and each row's update by name: a derivation
     * that leaves them as they are updates the values in place, so a slider being dragged is
     * not replaced under the pointer. */
    this.layout = "";
    this.updates = new Map();
    this.seedInput = root.querySelector("#seed");
    this.seedInput.addEventListener("change", () => {
      const seed = Math.max(0, Math.floor(Number(this.seedInput.value)));
      this.setSeed(Number.isFinite(seed) ? seed : 0);
    });
    root.querySelector("#new-seed").addEventListener("click", () => {
      this.setSeed(Math.floor(Math.random() * 2 ** 31));
    });
  }

  setSeed(seed) {
    this.seed = seed;
    this.seedInput.value = String(seed);
    this.onChange();
  }

  /** What the server needs: the seed and the user's values. */
  settings() {
    return { seed: this.seed, attrs: { ...this.values } };
  }

  /** Forgets the values (another file). */
  reset() {
    this.values = {};
    this.layout = "";
    this.updates.clear();
    this.list.replaceChildren();
  }

  /** Shows the attributes of a derivation; forgets the values it dropped. */
  show(attrs, dropped) {
    for (const name of dropped || []) delete this.values[name];
    if (!attrs) return;
    const visible = attrs.filter((a) => !a.hidden && a.type !== "array");
    const layout = JSON.stringify(visible.map(({ value, default: _, user, ...rest }) => rest));
    if (layout === this.layout) {
      for (const attr of visible) this.updates.get(attr.name)(attr);
      return;
    }
    this.layout = layout;
    this.updates.clear();
    const groups = new Map();
    for (const attr of visible) {
      const key = attr.group.join(" › ");
      if (!groups.has(key)) groups.set(key, { order: attr.group_order ?? Infinity, first: groups.size, attrs: [] });
      const group = groups.get(key);
      if (attr.group_order !== undefined) group.order = Math.min(group.order, attr.group_order);
      group.attrs.push(attr);
    }
    // Ungrouped attributes first, then groups by their order and first appearance.
    const sorted = [...groups.entries()].sort(([ka, a], [kb, b]) =>
      (ka === "" ? -1 : 0) - (kb === "" ? -1 : 0) || a.order - b.order || a.first - b.first);
    this.list.replaceChildren(...sorted.flatMap(([name, group]) => {
      const rows = group.attrs
        .map((attr, i) => ({ attr, i }))
        .sort((a, b) => (a.attr.order ?? Infinity) - (b.attr.order ?? Infinity) || a.i - b.i)
        .map(({ attr }) => this.row(attr));
      if (name === "") return rows;
      const heading = document.createElement("h3");
      heading.textContent = name;
      return [heading, ...rows];
    }));
  }

  row(attr) {
    const row = document.createElement("div");
    row.className = "attr";
    row.title = attr.description || "";
    const label = document.createElement("label");
    label.textContent = attr.display_name || attr.name;
    row.append(label);
    const set = (value) => {
      this.values[attr.name] = value;
      row.classList.add("user");
    };
    const value = attr.value;
    let input;
    if (attr.type === "number" && attr.range) {
      const { min, max, step } = attr.range;
      input = document.createElement("input");
      input.type = "range";
      input.min = String(min);
      input.max = String(max);
      input.step = step > 0 ? String(step) : String((max - min) / 1000 || 1);
      input.value = String(value);
      const number = document.createElement("input");
      number.type = "number";
      number.className = "number";
      number.step = "any";
      number.value = String(value);
      input.addEventListener("input", () => {
        number.value = input.value;
        set(Number(input.value));
        // The page's debounce spaces the derivations of a drag.
        this.onChange();
      });
      number.addEventListener("change", () => {
        let typed = Number(number.value);
        if (!Number.isFinite(typed)) return;
        if (attr.restricted) typed = Math.min(max, Math.max(min, typed));
        number.value = String(typed);
        input.value = String(typed);
        set(typed);
        this.onChange();
      });
      row.append(input, number);
    } else if (attr.choices) {
      input = document.createElement("select");
      const choices = attr.choices.some((c) => c === value) ? attr.choices : [...attr.choices, value];
      input.replaceChildren(...choices.map((c, i) => {
        const option = document.createElement("option");
        option.value = String(i);
        option.textContent = String(c);
        option.selected = c === value;
        return option;
      }));
      input.addEventListener("change", () => {
        set(choices[Number(input.value)]);
        this.onChange();
      });
      row.append(input);
    } else if (attr.type === "boolean") {
      input = document.createElement("input");
      input.type = "checkbox";
      input.checked = value === true;
      input.addEventListener("change", () => {
        set(input.checked);
        this.onChange();
      });
      row.append(input);
    } else if (attr.type === "string" && attr.color && /^#[0-9a-f]{6}$/i.test(value)) {
      input = document.createElement("input");
      input.type = "color";
      input.value = value.toLowerCase();
      input.addEventListener("change", () => {
        set(input.value);
        this.onChange();
      });
      row.append(input);
    } else {
      input = document.createElement("input");
      input.type = attr.type === "number" ? "number" : "text";
      if (attr.type === "number") input.step = "any";
      input.value = String(value);
      input.addEventListener("change", () => {
        const typed = attr.type === "number" ? Number(input.value) : input.value;
        if (attr.type === "number" && !Number.isFinite(typed)) return;
        set(typed);
        this.onChange();
      });
      row.append(input);
    }
    input.dataset.attr = attr.name;
    input.setAttribute("aria-label", attr.display_name || attr.name);
    const reset = document.createElement("button");
    reset.className = "reset";
    reset.textContent = "↺";
    reset.addEventListener("click", () => {
      delete this.values[attr.name];
      this.onChange();
    });
    row.append(reset);
    const controls = [...row.querySelectorAll("input, select")];
    const update = (now) => {
      row.classList.toggle("user", now.user);
      reset.disabled = !now.user;
      reset.title = `Back to the grammar's value (${now.default})`;
      // The control in the user's hand keeps what the user is doing.
      if (controls.includes(document.activeElement)) return;
      for (const control of controls) {
        if (control.type === "checkbox") control.checked = now.value === true;
        else if (control.tagName === "SELECT") {
          const i = (attr.choices || []).findIndex((c) => c === now.value);
          if (i >= 0) control.value = String(i);
        } else if (control.type === "color") control.value = String(now.value).toLowerCase();
        else control.value = String(now.value);
      }
    };
    update(attr);
    this.updates.set(attr.name, update);
    return row;
  }
}
