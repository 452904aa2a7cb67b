// Syntax colouring for CGA-like grammars (CGA, and the .mul and .sgl notations, which share its
// tokens): a StreamLanguage tokenizer. Meaning (errors, rule names) comes from the server's
// parser; this only colours.
import { StreamLanguage, HighlightStyle, syntaxHighlighting } from "@codemirror/language";
import { tags as t } from "@lezer/highlight";

const keywords = new Set([
  "attr", "const", "import", "case", "else", "with", "version", "style", "extends",
  "true", "false", "NIL", "fulfills", "axiom", "goal", "rule",
]);

const operations = new Set([
  "extrude", "split", "comp", "setback", "offset", "i", "s", "t", "r", "color", "set", "roofGable",
  "roofHip", "roofPyramid", "roofShed", "texture", "setupProjection", "projectUV", "center",
  "alignScopeToAxes", "alignScopeToGeometry", "rotateScope", "mirror", "mirrorScope", "innerRectangle",
  "insertAlongUV", "primitiveCube", "primitiveCylinder", "primitiveSphere", "primitiveQuad",
  "primitiveCone", "print", "report", "label", "tileUV", "scaleUV", "translateUV", "rotateUV",
  "deleteUV", "normalizeUV", "reverseNormals", "trim", "cleanupGeometry", "convexify", "envelope",
  "footprint", "reduceGeometry", "resetGeometry", "setNormals", "softenNormals", "splitArea",
  "taper", "NIL", "rand", "p", "scope", "geometry", "comp", "joint", "bend", "implicit",
]);

export const cgaLanguage = StreamLanguage.define({
  name: "cga",
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
    if (stream.match(/^@[A-Za-z_]\w*/)) return "meta";
    if (stream.match("-->") || stream.match("->")) return "definitionOperator";
    if (stream.match(/^[|:*{}\[\]()]/)) return "punctuation";
    if (stream.match(/^[+\-*\/%<>=!&^]+/)) return "operator";
    const word = stream.match(/^[A-Za-z_][\w.]*/);
    if (word) {
      const name = word[0];
      if (keywords.has(name)) return "keyword";
      if (operations.has(name)) return "variableName.function";
      return /^[A-Z]/.test(name) ? "typeName" : "variableName";
    }
    stream.next();
    return null;
  },
  languageData: { commentTokens: { line: "//", block: { open: "/*", close: "*/" } } },
});

const style = HighlightStyle.define([
  { tag: t.keyword, color: "#7a3e9d", fontWeight: "bold" },
  { tag: t.function(t.variableName), color: "#1c5fa8" },
  { tag: t.typeName, color: "#0b7a5a", fontWeight: "bold" },
  { tag: [t.lineComment, t.blockComment], color: "#888", fontStyle: "italic" },
  { tag: t.string, color: "#a3502a" },
  { tag: t.number, color: "#b5521b" },
  { tag: t.meta, color: "#9a6700" },
  { tag: t.definitionOperator, color: "#c02050", fontWeight: "bold" },
  { tag: t.operator, color: "#555" },
]);

export const cga = [cgaLanguage, syntaxHighlighting(style)];
