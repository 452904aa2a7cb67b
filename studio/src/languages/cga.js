// Syntax colouring for CGA-like grammars: CGA, the .mul and .sgl notations (which share its
// tokens) and goal grammars (native and Michelangelo notation). StreamLanguage tokenizers:
// meaning (errors, rule names) comes from the server's parser; these only colour. Operation
// names are coloured by shape (a lower-case word before `(`), not from a copy of the engine's
// table, which the server serves for completion.
import { StreamLanguage } from "@codemirror/language";

const cgaKeywords = [
  "attr", "const", "import", "case", "else", "with", "version", "style", "extends",
  "true", "false", "NIL",
];

const goalKeywords = [
  ...cgaKeywords, "axiom", "local", "sync", "using", "fulfills", "goal", "is", "tag", "has",
  "if", "adds", "void", "size", "new", "Rules", "Axis",
];

function shapeLanguage(name, keywordList) {
  const keywords = new Set(keywordList);
  return StreamLanguage.define({
    name,
    startState: () => ({ comment: false }),
    token(stream, state) {
      if (state.comment) {
        if (stream.skipTo("*/")) { stream.match("*/"); state.comment = false; } else stream.skipToEnd();
        return "blockComment";
      }
      if (stream.eatSpace()) return null;
      if (stream.match("/*")) { state.comment = true; return "blockComment"; }
      if (stream.match("//") || stream.match("#")) { stream.skipToEnd(); return "lineComment"; }
      if (stream.match(/^"(?:[^"\\]|\\.)*"?/) || stream.match(/^'(?:[^'\\]|\\.)*'?/)) return "string";
      if (stream.match(/^~?-?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?%?/)) return "number";
      if (stream.match(/^@[A-Za-z_][\w.]*/)) return "meta";
      if (stream.match("-->") || stream.match("->")) return "definitionOperator";
      if (stream.match(/^\+[A-Za-z_"][\w.-]*"?/)) return "typeName";
      if (stream.match(/^[|:*{}\[\]()]/)) return "punctuation";
      if (stream.match(/^[+\-*\/%<>=!&^]+/)) return "operator";
      const word = stream.match(/^[A-Za-z_][\w.]*/);
      if (word) {
        const text = word[0];
        if (keywords.has(text)) return "keyword";
        if (/^[A-Z]/.test(text)) return "typeName";
        return stream.match(/^\s*\(/, false) ? "variableName.function" : "variableName";
      }
      stream.next();
      return null;
    },
    languageData: { commentTokens: { line: "//", block: { open: "/*", close: "*/" } } },
  });
}

export const cgaLanguage = shapeLanguage("cga", cgaKeywords);
export const goalLanguage = shapeLanguage("goal", goalKeywords);
