// The editor's language for each kind of grammar file, by its extension: CGA-like grammars,
// goal grammars, L-systems, implicit caves (StreamLanguage tokenizers) and topological
// grammars (JSON, with CodeMirror's lezer JSON grammar).
import { json } from "@codemirror/lang-json";
import { cgaLanguage, goalLanguage } from "./cga.js";
import { lsysLanguage } from "./lsys.js";
import { caveLanguage } from "./cave.js";
import { highlighting } from "./style.js";

/** The kind of a grammar file: `cga` (also .mul, .sgl), `goal`, `lsys`, `cave` or `topo`. */
export function kindOf(path) {
  const extension = (path || "").toLowerCase().split(".").pop();
  return { goal: "goal", lsys: "lsys", cave: "cave", grammar: "topo" }[extension] || "cga";
}

const languages = {
  cga: cgaLanguage,
  goal: goalLanguage,
  lsys: lsysLanguage,
  cave: caveLanguage,
  topo: json(),
};

/** The editor extensions that colour a file of `path`'s kind. */
export function languageFor(path) {
  return [languages[kindOf(path)], highlighting];
}
