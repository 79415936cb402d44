#!/usr/bin/env python3
"""List the functions in crates/*/src longer than N lines (issue 35).

A function's length runs from the line of its `fn` keyword to the line of
its closing brace, both counted. Test code is left out: `tests/` folders and
modules under `#[cfg(test)]`. Strings (raw and byte ones too), character
literals and comments are skipped when braces are matched, so a `{` in a
format string does not count.

    python3 .ci/long_functions.py                # list, longest first
    python3 .ci/long_functions.py --lines 150 --max 2

Exits 1 when more than --max functions are over the limit.
"""

import argparse
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent


def tokens(text):
    """Yield (token, line) with comments, strings and char literals dropped.

    Tokens are identifiers/numbers (a run of word characters), `#`, and single
    punctuation characters; a string or char literal becomes the token `"`.
    """
    i, n, line = 0, len(text), 1

    def word(c):
        return c.isalnum() or c == "_"

    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
        elif c.isspace():
            i += 1
        elif text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if text.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif text.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    line += text[i] == "\n"
                    i += 1
        elif c == '"':
            start = line
            i += 1
            while i < n and text[i] != '"':
                if text[i] == "\\":
                    line += text[i + 1] == "\n"
                    i += 2
                    continue
                line += text[i] == "\n"
                i += 1
            i += 1
            yield '"', start
        elif c == "'":
            # A char literal ('a', '\n', '\u{7b}', '{') or a lifetime ('a).
            if i + 1 < n and text[i + 1] == "\\":
                j = text.find("'", i + 2)
                i = j + 1
                yield '"', line
            elif i + 2 < n and text[i + 2] == "'":
                i += 3
                yield '"', line
            else:
                i += 1
                yield "'", line
        elif word(c):
            j = i
            while j < n and word(text[j]):
                j += 1
            ident = text[i:j]
            # Raw (and byte) strings: r"..", r#".."#, br#".."#; b".." and b'x'.
            if ident in ("r", "br", "cr") and j < n and text[j] in '"#':
                k = j
                while k < n and text[k] == "#":
                    k += 1
                if k < n and text[k] == '"':
                    close = '"' + "#" * (k - j)
                    end = text.find(close, k + 1)
                    end = n if end < 0 else end + len(close)
                    yield '"', line
                    line += text.count("\n", k, end)
                    i = end
                    continue
            if ident in ("b", "c") and j < n and text[j] in "\"'":
                i = j  # the literal is read on the next pass
                continue
            yield ident, line
            i = j
        else:
            yield c, line
            i += 1


def matching(toks, k, pair="{}"):
    """Index of the token closing the `pair[0]` at toks[k]."""
    depth = 0
    for m in range(k, len(toks)):
        t = toks[m][0]
        if t == pair[0]:
            depth += 1
        elif t == pair[1]:
            depth -= 1
            if depth == 0:
                return m
    return len(toks) - 1


def functions(path):
    """Yield (name, first line, last line) of each fn with a body in path."""
    toks = list(tokens(path.read_text(encoding="utf-8")))
    k = 0
    while k < len(toks):
        t = toks[k][0]
        # #[cfg(test)] ... mod name { ... }: skip the whole module.
        if t == "#" and [x[0] for x in toks[k + 1 : k + 7]] == ["[", "cfg", "(", "test", ")", "]"]:
            m = k + 7
            while m < len(toks) and toks[m][0] == "#":  # further attributes
                m = matching(toks, m + 1, "[]") + 1
            if m < len(toks) and toks[m][0] in ("mod", "pub"):
                while m < len(toks) and toks[m][0] not in ("{", ";"):
                    m += 1
                if m < len(toks) and toks[m][0] == "{":
                    k = matching(toks, m) + 1
                    continue
            k += 1
            continue
        if t == "fn" and k + 1 < len(toks) and (toks[k + 1][0][:1].isalpha() or toks[k + 1][0][:1] == "_"):
            name, first = toks[k + 1][0], toks[k][1]
            # The body: the first `{` outside (), [] and <> of the signature;
            # a `;` first means a declaration without a body.
            m, nest = k + 2, 0
            while m < len(toks):
                x = toks[m][0]
                if x in "([":
                    nest += 1
                elif x in ")]":
                    nest -= 1
                elif x in ("{", ";") and nest == 0:
                    break
                m += 1
            if m < len(toks) and toks[m][0] == "{":
                end = matching(toks, m)
                yield name, first, toks[end][1]
            k += 2  # nested fns are found on the way
            continue
        k += 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lines", type=int, default=150, help="longer than this is listed (150)")
    parser.add_argument("--max", type=int, default=None, help="exit 1 when more are listed")
    parser.add_argument("--root", type=pathlib.Path, default=ROOT, help="the workspace")
    args = parser.parse_args()

    long = []
    for path in sorted(args.root.glob("crates/*/src/**/*.rs")):
        rel = path.relative_to(args.root)
        if "tests" in rel.parts[3:-1] or rel.parts[3:] == ("tests.rs",):
            continue
        for name, first, last in functions(path):
            lines = last - first + 1
            if lines > args.lines:
                long.append((lines, f"{rel}:{first}", name))
    long.sort(key=lambda r: (-r[0], r[1]))
    for lines, where, name in long:
        print(f"{lines:5}  {name:32} {where}")
    print(f"{len(long)} functions over {args.lines} lines")
    if args.max is not None and len(long) > args.max:
        print(f"more than --max {args.max}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
