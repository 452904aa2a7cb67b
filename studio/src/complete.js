// Completion for every kind of grammar file: the names the current text defines (so a rule
// just typed is offered at once) and, for CGA-like and goal grammars, the engine's operations,
// built-in functions and shape queries, served by the server from the engine's own tables
// (GET /api/vocabulary) with their signatures.
import { autocompletion } from "@codemirror/autocomplete";
import { kindOf } from "./languages/index.js";

let vocabulary = null;

/** Fetches the engine's vocabulary once; completion works without it until it arrives. */
export async function loadVocabulary() {
  const response = await fetch("/api/vocabulary");
  if (response.ok) vocabulary = await response.json();
  return vocabulary;
}

const unique = (names) => [...new Set(names)];

/** The names `text` defines, per kind: rules, attributes and constants, goals, symbols. */
export function definedNames(kind, text) {
  const all = (regex, group = 1) => [...text.matchAll(regex)].map((m) => m[group]);
  switch (kind) {
    case "cga":
      return {
        rules: unique(all(/^[ \t]*([A-Za-z_][\w.]*)[ \t]*(?:\([^)\n]*\))?[ \t]*(?:-->|->)/gm)),
        attributes: unique([...all(/\battr[ \t]+([A-Za-z_]\w*)/g), ...all(/\bconst[ \t]+([A-Za-z_]\w*)/g)]),
      };
    case "goal":
      return {
        rules: unique([...all(/\+"?([A-Za-z_][\w.-]*)/g), ...all(/\b(?:fulfills|goal|is|tag|adds|axiom)\(?[ \t]*"?([A-Za-z_][\w.-]*)/g)]),
        // `@Weight(2)` is an annotation, not an attribute.
        attributes: unique(all(/@([A-Za-z_][\w.]*)(?!\w*\()/g)),
      };
    case "lsys":
      return {
        rules: unique(all(/^[ \t]*(?:[^\n#]*<[ \t]*)?([A-Za-z])(?:\([^)\n]*\))?[^\n]*?(?:-->|->|→)/gm)),
        attributes: unique(all(/^[ \t]*(?:define:|#define)[ \t]+([A-Za-z_]\w*)/gim)),
      };
    case "cave":
      return { rules: unique(all(/^[ \t]*let[ \t]+([A-Za-z_]\w*)/gm)), attributes: [] };
    default:
      return { rules: unique(all(/"name":\s*"([^"]+)"/g)), attributes: [] };
  }
}

function options(kind, text) {
  const names = definedNames(kind, text);
  const list = [
    ...names.rules.map((label) => ({ label, type: "class", detail: kind === "goal" ? "goal" : "rule", boost: 2 })),
    ...names.attributes.map((label) => ({ label, type: "variable", detail: "attribute", boost: 1 })),
  ];
  if (vocabulary && (kind === "cga" || kind === "goal")) {
    for (const op of vocabulary.operations) {
      list.push({
        label: op.name,
        type: "function",
        detail: op.signature || (op.support === "implemented" ? "operation" : op.support),
        info: op.support === "implemented" ? undefined : `${op.support}: accepted, without effect on the model`,
      });
    }
    for (const f of vocabulary.functions) {
      list.push({ label: f.name, type: "method", detail: f.signature || "function" });
    }
    for (const q of vocabulary.queries) list.push({ label: q.name, type: "property", detail: "query" });
  }
  return list;
}

function source(kind) {
  return (context) => {
    const word = context.matchBefore(kind === "topo" ? /"?[\w.-]*/ : /[A-Za-z_@][\w.]*/);
    if (!word || (word.from === word.to && !context.explicit)) return null;
    const from = word.text.startsWith("@") || word.text.startsWith('"') ? word.from + 1 : word.from;
    const text = context.state.doc.toString();
    // The word being typed is not a name the text defines yet.
    const typed = context.state.sliceDoc(from, context.pos);
    return {
      from,
      options: options(kind, text.slice(0, word.from) + text.slice(context.pos))
        .filter((o) => o.label !== typed || kind === "topo"),
      validFor: /^[\w.]*$/,
    };
  };
}

/** The completion extension for a file of `path`'s kind. */
export function completionFor(path) {
  return autocompletion({ override: [source(kindOf(path))], activateOnTyping: true });
}
