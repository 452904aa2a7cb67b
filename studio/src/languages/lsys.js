// Syntax colouring for L-systems (docs/lsystem.md): settings `key: value`, productions with
// contexts, weights and conditions, turtle commands, parameters and `#` comments (but not
// cpfg's `#define` and `#ignore`, nor a colour like `#3a6ea5`, which are settings).
import { StreamLanguage } from "@codemirror/language";

const turtle = new Set([..."+-&^\\/|$[]!'{.}"]);

export const lsysLanguage = StreamLanguage.define({
  name: "lsys",
  startState: () => ({ production: false, parameters: 0 }),
  token(stream, state) {
    if (stream.sol()) {
      state.production = /->|→/.test(stream.string);
      state.parameters = 0;
    }
    if (stream.eatSpace()) return null;
    if (stream.match(/^#(?:define|ignore)\b/)) return "keyword";
    if (stream.match(/^#[0-9a-fA-F]{3,8}\b/)) return "string";
    if (stream.peek() === "#") { stream.skipToEnd(); return "lineComment"; }
    if (!state.production && stream.sol()) {
      if (stream.match(/^[^:#]+:(?!\S*->)/)) return "keyword";
    }
    if (stream.match("-->") || stream.match("->") || stream.match("→")) return "definitionOperator";
    if (state.parameters > 0 || !state.production) {
      if (stream.match(/^(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?/)) return "number";
      if (stream.match(/^[A-Za-z_]\w*(?=\s*\()/)) return "variableName.function";
      if (stream.match(/^[A-Za-z_]\w*/)) return "variableName";
    }
    const c = stream.next();
    if (c === "(") { state.parameters += 1; return "punctuation"; }
    if (c === ")") { state.parameters = Math.max(0, state.parameters - 1); return "punctuation"; }
    if (state.parameters > 0) return /[,]/.test(c) ? "punctuation" : "operator";
    if (c === "<" || c === ">" || c === ":") return "operator";
    if (turtle.has(c)) return "operator";
    return /[A-Z]/.test(c) ? "typeName" : "variableName";
  },
  languageData: { commentTokens: { line: "#" } },
});
