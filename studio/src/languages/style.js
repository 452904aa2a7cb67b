// The colours every grammar language of the studio shares: one highlight style over the
// standard tags, so that a rule name looks the same in CGA, a goal grammar and an L-system.
import { HighlightStyle, syntaxHighlighting } from "@codemirror/language";
import { tags as t } from "@lezer/highlight";

const style = HighlightStyle.define([
  { tag: t.keyword, color: "#7a3e9d", fontWeight: "bold" },
  { tag: t.function(t.variableName), color: "#1c5fa8" },
  { tag: t.typeName, color: "#0b7a5a", fontWeight: "bold" },
  { tag: [t.lineComment, t.blockComment], color: "#888", fontStyle: "italic" },
  { tag: t.string, color: "#a3502a" },
  { tag: t.number, color: "#b5521b" },
  { tag: [t.meta, t.propertyName], color: "#9a6700" },
  { tag: t.definitionOperator, color: "#c02050", fontWeight: "bold" },
  { tag: t.operator, color: "#555" },
  { tag: [t.bool, t.null, t.atom], color: "#7a3e9d" },
]);

export const highlighting = syntaxHighlighting(style);
