// The derivation tree beside the preview: one row per shape, children created only when their
// parent is opened (and at most PAGE of them at a time), so a tree of 100,000 shapes costs
// the DOM no more than the rows the user opened.

/** Children rows made at once; a "more" row makes the next ones. */
const PAGE = 200;

/** A tree's shapes indexed for the view: children of each node in order (CSR arrays). */
export class TreeIndex {
  constructor(tree) {
    this.tree = tree;
    const n = tree.parent.length;
    this.count = n;
    const counts = new Uint32Array(n + 1);
    for (let i = 0; i < n; i++) if (tree.parent[i] >= 0) counts[tree.parent[i] + 1] += 1;
    for (let i = 0; i < n; i++) counts[i + 1] += counts[i];
    this.first = counts;
    this.children = new Uint32Array(n);
    const fill = counts.slice(0, n);
    this.roots = [];
    for (let i = 0; i < n; i++) {
      const p = tree.parent[i];
      if (p < 0) this.roots.push(i);
      else this.children[fill[p]++] = i;
    }
  }

  childrenOf(node) {
    return this.children.subarray(this.first[node], this.first[node + 1]);
  }

  name(node) {
    return this.tree.symbols[this.tree.symbol[node]];
  }

  /** The node and its ancestors, the root last. */
  path(node) {
    const chain = [];
    for (let at = node; at >= 0; at = this.tree.parent[at]) chain.push(at);
    return chain;
  }
}

export class TreeView {
  /** `onSelect(node)` is called when the user clicks a row. */
  constructor(container, onSelect) {
    this.container = container;
    this.onSelect = onSelect;
    this.index = null;
    this.rows = new Map();
    this.selected = -1;
  }

  /** Shows a new tree, with its initial shapes closed; `open` lists nodes to open again. */
  show(index, open = []) {
    this.index = index;
    this.rows.clear();
    this.selected = -1;
    const list = document.createElement("ul");
    list.setAttribute("role", "group");
    this.appendRows(list, index.roots, 0);
    this.container.replaceChildren(list);
    for (const node of open) if (node < index.count) this.reveal(node, false);
  }

  /** The nodes whose rows are open (to reopen them in the next tree). */
  openNodes() {
    return [...this.rows].filter(([, row]) => row.classList.contains("open")).map(([node]) => node);
  }

  appendRows(list, nodes, from) {
    const end = Math.min(nodes.length, from + PAGE);
    for (let i = from; i < end; i++) list.append(this.row(nodes[i]));
    if (end < nodes.length) {
      const more = document.createElement("li");
      more.className = "more";
      more.textContent = `… ${nodes.length - end} more`;
      more.addEventListener("click", (event) => {
        event.stopPropagation();
        more.remove();
        this.appendRows(list, nodes, end);
      });
      list.append(more);
    }
  }

  row(node) {
    const index = this.index;
    const item = document.createElement("li");
    item.setAttribute("role", "treeitem");
    item.dataset.node = node;
    const label = document.createElement("div");
    label.className = "label";
    const children = index.childrenOf(node).length;
    const toggle = document.createElement("span");
    toggle.className = children ? "toggle" : "toggle leaf";
    label.append(toggle, index.name(node));
    if (children) {
      const count = document.createElement("span");
      count.className = "count";
      count.textContent = ` (${children})`;
      label.append(count);
      item.setAttribute("aria-expanded", "false");
    }
    toggle.addEventListener("click", (event) => {
      event.stopPropagation();
      this.toggle(node);
    });
    label.addEventListener("click", () => this.onSelect(node));
    item.append(label);
    this.rows.set(node, item);
    return item;
  }

  /** Opens or closes a node's row; its children's rows are made the first time. */
  toggle(node, open) {
    const item = this.rows.get(node);
    if (!item || !this.index.childrenOf(node).length) return;
    const opening = open ?? !item.classList.contains("open");
    item.classList.toggle("open", opening);
    item.setAttribute("aria-expanded", String(opening));
    if (opening && !item.querySelector(":scope > ul")) {
      const list = document.createElement("ul");
      list.setAttribute("role", "group");
      this.appendRows(list, [...this.index.childrenOf(node)], 0);
      item.append(list);
    }
  }

  /** Opens the rows down to `node` (making the page of rows it is on) and marks it selected. */
  reveal(node, select = true) {
    const path = this.index.path(node).reverse();
    for (const at of path.slice(0, -1)) {
      this.toggle(at, true);
      if (!this.rows.has(path[path.indexOf(at) + 1])) {
        // Beyond the rows made so far: make pages until it is there.
        const list = this.rows.get(at).querySelector(":scope > ul");
        let more = list.querySelector(":scope > li.more");
        while (more && !this.rows.has(path[path.indexOf(at) + 1])) {
          more.click();
          more = list.querySelector(":scope > li.more");
        }
      }
    }
    if (!select) {
      this.toggle(node, true);
      return;
    }
    this.rows.get(this.selected)?.classList.remove("selected");
    this.selected = node;
    const item = this.rows.get(node);
    item.classList.add("selected");
    item.querySelector(":scope > .label").scrollIntoView({ block: "nearest" });
  }
}
