// Syntax colouring for implicit cave grammars (`.cave`, docs/implicit.md): settings and
// statements, primitives, transforms, directions, numbers and `#` comments.
import { StreamLanguage } from "@codemirror/language";

const keywords = new Set([
  "lod", "seed", "overlap", "direction", "let", "add", "subtract", "intersect", "morph",
  "repeat", "generate", "at", "random", "centre", "classic", "morphic", "per_shape",
]);
const primitives = new Set([
  "sphere", "box", "cylinder", "cone", "pyramid", "torus", "capsule", "rand",
]);

export const caveLanguage = StreamLanguage.define({
  name: "cave",
  token(stream) {
    if (stream.eatSpace()) return null;
    if (stream.peek() === "#") { stream.skipToEnd(); return "lineComment"; }
    if (stream.match(/^[+-][xyz]\b/)) return "atom";
    if (stream.match(/^-?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?%?/)) return "number";
    if (stream.match(/^\.(?:move|rotate|scale)\b/)) return "variableName.function";
    const word = stream.match(/^[A-Za-z_]\w*/);
    if (word) {
      if (keywords.has(word[0])) return "keyword";
      if (primitives.has(word[0]) || word[0].startsWith("smooth_")) return "variableName.function";
      return /^[xyz]$/.test(word[0]) ? "atom" : "typeName";
    }
    if (stream.match(/^[+\-&=]/)) return "operator";
    stream.next();
    return "punctuation";
  },
  languageData: { commentTokens: { line: "#" } },
});
