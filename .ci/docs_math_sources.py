#!/usr/bin/env python3
"""The TeX of every formula in the doc comments under src/, as rustdoc's Markdown passes it to the page.

Display math is a fenced block ```math … ``` and inline math a code span `$…$` (katex-header.html).
A doc comment is a run of `///` or `//!` lines; rustdoc removes the indentation common to its
non-blank lines, and CommonMark removes from each line of a fence's content as many leading spaces
as the opening fence is indented.

  docs_math_sources.py [SRC]     JSON: formulas [{file, line, display, shown, tex}], raw [TeX
                                 delimiters `$$`, `\\(`, `\\[` left in the Markdown]
  docs_math_sources.py compare SOURCES RENDERED
      compares the sources' TeX with the TeX KaTeX received on the rendered pages (as multisets,
      character for character) and exits non-zero on any difference, KaTeX error or untypeset formula.

`shown` is false for the module docs (`//!`) of a module declared without `pub`: rustdoc renders no
page for it. Every other formula must be rendered exactly once.
"""
import json
import os
import re
import sys
from collections import Counter

DOC = re.compile(r"^\s*(//!|///)(.*)$")
FENCE = re.compile(r"^( {0,3})(`{3,}|~{3,})\s*math\s*$")
INLINE = re.compile(r"(?<!`)`(\$[^`$]+\$)`(?!`)")


def doc_runs(lines):
    """Yield (first line number, marker, [text after the marker]) for each doc comment run."""
    i = 0
    while i < len(lines):
        m = DOC.match(lines[i])
        if not m:
            i += 1
            continue
        marker, start, body = m.group(1), i, []
        while i < len(lines):
            m = DOC.match(lines[i])
            if not m or m.group(1) != marker:
                break
            body.append(m.group(2))
            i += 1
        yield start, marker, body


def unindent(body):
    ind = min((len(x) - len(x.lstrip(" ")) for x in body if x.strip()), default=0)
    return [x[ind:] if x.strip() else x.strip() for x in body]


def module_is_public(path):
    """Whether every module from the crate root down to the one in `path` is declared `pub mod`."""
    d, f = os.path.split(path)
    if f in ("lib.rs", "main.rs") and os.path.basename(d) == "src" or "/bin/" in path:
        return True
    name = os.path.basename(d) if f == "mod.rs" else f[:-3]
    parent_dir = os.path.dirname(d) if f == "mod.rs" else d
    candidates = [os.path.join(parent_dir, "mod.rs"), parent_dir + ".rs", os.path.join(parent_dir, "lib.rs")]
    for parent in candidates:
        if os.path.exists(parent) and (parent.endswith("mod.rs") or parent.endswith(".rs")):
            text = open(parent, encoding="utf-8").read()
            m = re.search(r"^\s*(pub(?:\([^)]*\))?\s+)?mod\s+" + re.escape(name) + r"\s*;", text, re.M)
            if m:
                return m.group(1) is not None and m.group(1).strip() == "pub" and module_is_public(parent)
    return False


def formulas(path, raw):
    """The formulas of the doc comments in `path` (or of the Markdown file `path`, included as
    docs); TeX left outside a math fence goes to `raw`."""
    lines = open(path, encoding="utf-8").read().split("\n")
    out = []
    if path.endswith(".md"):
        runs, public = [(0, "//!", lines)], True
    else:
        runs, public = doc_runs(lines), module_is_public(path)
    for start, marker, body in runs:
        shown = public or marker == "///"
        md = unindent(body)
        i = 0
        while i < len(md):
            # A fence may sit inside a list item: strip the item's indentation before matching.
            stripped = md[i].lstrip(" ")
            lead = len(md[i]) - len(stripped)
            m = FENCE.match(stripped)
            if m:
                close = m.group(2)[0] * len(m.group(2))
                j, tex = i + 1, []
                while j < len(md) and md[j].strip() != close:
                    x = md[j]
                    k = min(lead, len(x) - len(x.lstrip(" ")))
                    tex.append(x[k:])
                    j += 1
                if j == len(md):
                    sys.exit(f"{path}:{start + i + 1}: unclosed math fence")
                out.append({"file": path, "line": start + i + 1, "display": True, "shown": shown, "tex": "\n".join(tex)})
                i = j + 1
                continue
            if stripped.startswith("```") or stripped.startswith("~~~"):
                # Another fenced block (code): skip to its end, its code spans are not Markdown.
                fence = stripped[:3]
                j = i + 1
                while j < len(md) and not md[j].lstrip(" ").startswith(fence):
                    j += 1
                i = j + 1
                continue
            if "$$" in md[i] or "\\(" in md[i] or "\\[" in md[i]:
                raw.append(f"{path}:{start + i + 1}: {md[i].strip()}")
            for m in INLINE.finditer(md[i]):
                out.append({"file": path, "line": start + i + 1, "display": False, "shown": shown, "tex": m.group(1)[1:-1]})
            i += 1
    return out


def compare(sources_json, rendered_json):
    src = json.load(open(sources_json, encoding="utf-8"))
    sources = src["formulas"]
    rendered = json.load(open(rendered_json, encoding="utf-8"))
    shown = [f for f in sources if f["shown"]]
    expected = Counter((f["display"], f["tex"]) for f in shown)
    got = Counter()
    failures = [f"TeX outside a math fence: {r}" for r in src["raw"]]
    for page in rendered["pages"]:
        for f in page["formulas"]:
            got[(f["display"], f["tex"])] += 1
        for e in page["errors"]:
            failures.append(f"{page['page']}: KaTeX error: {e}")
        if page["untypeset"]:
            failures.append(f"{page['page']}: {page['untypeset']} math fences left untypeset")
        if not page["katexLoaded"]:
            failures.append(f"{page['page']}: KaTeX did not load")
        for e in page["scriptErrors"]:
            failures.append(f"{page['page']}: script error: {e}")
    for key in sorted(set(expected) | set(got), key=str):
        if expected[key] != got[key]:
            where = [f"{f['file']}:{f['line']}" for f in shown if (f["display"], f["tex"]) == key]
            failures.append(f"in sources {expected[key]}, rendered {got[key]} ({', '.join(where) or 'no source'}): {key[1]!r}")
    if rendered["blocked"]:
        failures.append(f"requests outside the docs and KaTeX: {rendered['blocked'][:5]}")
    n_src, n_shown, n_got = len(sources), sum(expected.values()), sum(got.values())
    pages = len(rendered["pages"])
    print(f"docs-math: {n_src} formulas in the sources ({n_src - n_shown} in private module docs), "
          f"{n_shown} expected on the pages, {n_got} rendered by KaTeX {rendered['katexVersion']} on {pages} pages; "
          f"{sum(len(p['errors']) for p in rendered['pages'])} KaTeX errors; {len(failures)} differences")
    for f in failures:
        print("  " + f)
    return 1 if failures else 0


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "compare":
        sys.exit(compare(sys.argv[2], sys.argv[3]))
    root = sys.argv[1] if len(sys.argv) > 1 else "src"
    found, raw = [], []
    for d, _, files in sorted(os.walk(root)):
        for f in sorted(files):
            if f.endswith(".rs"):
                found += formulas(os.path.join(d, f), raw)
    # Markdown files the crate includes as docs (`#![doc = include_str!("../README.md")]`).
    for d, _, files in sorted(os.walk(root)):
        for f in sorted(files):
            if f.endswith(".rs"):
                text = open(os.path.join(d, f), encoding="utf-8").read()
                for inc in re.findall(r'doc\s*=\s*include_str!\("([^"]+\.md)"\)', text):
                    found += formulas(os.path.normpath(os.path.join(d, inc)), raw)
    json.dump({"formulas": found, "raw": raw}, sys.stdout, ensure_ascii=False, indent=0)


if __name__ == "__main__":
    main()
