// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The scene language (docs/language.md) in CodeMirror 6: a StreamLanguage mode that colours
// the command at the start of a line, option keys (`key=`), numbers and vectors, `#` comments,
// "quoted strings" and `$param` / `${param}` references; and completion of command names at the
// start of a line and of the current command's option keys, from the server's /api/info.
import { StreamLanguage, LanguageSupport, HighlightStyle, syntaxHighlighting } from '@codemirror/language';
import { tags } from '@lezer/highlight';

const kNumber = /^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?(,[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?)*(?=\s|$|#)/;

const sceneMode = {
  name: 'ramiform',
  startState: () => ({ first: true }),
  token(stream, state) {
    if (stream.sol()) state.first = true;
    if (stream.eatSpace()) return null;
    if (stream.peek() === '#') {
      stream.skipToEnd();
      return 'comment';
    }
    if (stream.peek() === '"') {
      stream.next();
      while (!stream.eol()) {
        if (stream.next() === '"') break;
      }
      state.first = false;
      return 'string';
    }
    if (stream.match(/^\$\{[A-Za-z_][\w.-]*\}/) || stream.match(/^\$[A-Za-z_][\w.-]*/)) {
      state.first = false;
      return 'variableName';
    }
    if (state.first) {
      state.first = false;
      if (stream.match(/^[A-Za-z_][\w-]*/)) return 'keyword';
    }
    if (stream.match(/^[A-Za-z_][\w-]*(?==)/)) return 'propertyName';
    if (stream.eat('=')) return 'operator';
    if (stream.match(kNumber)) return 'number';
    // Anything else up to the next space, `$` or `#`: a name, a path, a keyword value.
    if (!stream.match(/^[^\s$#"]+/)) stream.next();
    return null;
  },
  languageData: { commentTokens: { line: '#' } },
};

export const sceneLanguage = StreamLanguage.define(sceneMode);

const highlight = HighlightStyle.define([
  { tag: tags.keyword, color: '#7b3fb0', fontWeight: 'bold' },
  { tag: tags.propertyName, color: '#1b6fa8' },
  { tag: tags.number, color: '#a0522d' },
  { tag: tags.comment, color: '#6a737d', fontStyle: 'italic' },
  { tag: tags.string, color: '#22863a' },
  { tag: tags.variableName, color: '#d0367a', fontWeight: 'bold' },
  { tag: tags.operator, color: '#888' },
]);

// The command and its option keys at a position: `info.commands` is /api/info's list.
export function completionSource(getCommands) {
  return (context) => {
    const line = context.state.doc.lineAt(context.pos);
    const before = line.text.slice(0, context.pos - line.from);
    if (before.includes('#')) return null;
    const commands = getCommands();
    const word = context.matchBefore(/[\w-]*/);
    const start = word ? word.from : context.pos;
    const leading = line.text.slice(0, start - line.from);
    if (/^\s*$/.test(leading)) {
      if (!word || (word.from === word.to && !context.explicit)) return null;
      return {
        from: start,
        options: commands.map((c) => ({
          label: c.name,
          type: 'keyword',
          detail: c.synopsis ? c.synopsis.replace(/^\S+\s*/, '').slice(0, 60) : undefined,
          info: c.description || c.synopsis || undefined,
        })),
        validFor: /^[\w-]*$/,
      };
    }
    // Inside the arguments: the current command's option keys, unless this word is a value.
    if (/=[^\s]*$/.test(before)) return null;
    const name = leading.trim().split(/\s+/)[0];
    const command = commands.find((c) => c.name === name);
    if (!command || !command.options || command.options.length === 0) return null;
    if ((!word || word.from === word.to) && !context.explicit) return null;
    const used = new Set([...line.text.matchAll(/(^|\s)([\w-]+)=/g)].map((m) => m[2]));
    return {
      from: start,
      options: command.options
        .filter((o) => !used.has(o))
        .map((o) => ({ label: `${o}=`, type: 'property', detail: command.name })),
      validFor: /^[\w-]*$/,
    };
  };
}

export function sceneSupport() {
  return new LanguageSupport(sceneLanguage, [syntaxHighlighting(highlight)]);
}

// The `param NAME VALUE [key=value ...]` lines of a script: name → {value, line, min, max, step}.
export function scriptParams(text) {
  const params = new Map();
  text.split('\n').forEach((raw, i) => {
    const tokens = raw.replace(/#.*/, '').trim().split(/\s+/);
    if (tokens[0] !== 'param' || tokens.length < 3) return;
    const entry = { value: tokens[2], line: i + 1 };
    for (const t of tokens.slice(3)) {
      const m = /^(min|max|step)=(.*)$/.exec(t);
      if (m) entry[m[1]] = Number(m[2]);
    }
    params.set(tokens[1], entry);
  });
  return params;
}
