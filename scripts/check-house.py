#!/usr/bin/env python3
"""The house rules that the code's own comments state, checked so that they stay true (CI runs this):

- layers: every file of a layer of src/ uses only the layers listed before it in src/lib.rs's "## Layers" list
  (from `crate::…` paths in the code, unit tests left out);
- functions: at most MAX_LONG functions in src/ run over FUNCTION_LINES lines (from `fn` to its closing brace, unit
  tests left out), and each of those says why in its doc comment (a line with "over 80 lines");
- files: no file in src/render holds more than RENDER_FILE_LINES lines;
- module headers: no `//!` header in src/ (but the crate's, src/lib.rs) runs over HEADER_LINES lines;
- citations: every `model.md §N` (or §N.M, and the §s listed after it) in src/, glsl/, crates/ and the docs names a
  section docs/model.md has;
- links: every relative link of README.md, ARCHITECTURE.md and docs/ leads to a file that exists, and to a heading
  of it where it names one (GitHub's anchors).

Usage: scripts/check-house.py [--list]   (--list prints every long function and header, passing or not)
"""
import os
import re
import sys

FUNCTION_LINES = 80
MAX_LONG = 2
RENDER_FILE_LINES = 500
HEADER_LINES = 12


def strip(src):
    """The source with comments, strings and character literals blanked (newlines kept, so lines still count)."""
    out, i, n = [], 0, len(src)
    while i < n:
        if src.startswith("//", i):
            j = src.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif src.startswith("/*", i):
            j = src.find("*/", i) + 2
            out.append(re.sub(r"[^\n]", " ", src[i:j]))
            i = j
        elif re.match(r'r#*"', src[i : i + 10]) and (i == 0 or not (src[i - 1].isalnum() or src[i - 1] == "_")):
            hashes = re.match(r'r(#*)"', src[i:]).group(1)
            j = src.find('"' + hashes, i + 2 + len(hashes)) + 1 + len(hashes)
            out.append(re.sub(r"[^\n]", " ", src[i:j]))
            i = j
        elif src[i] == '"':
            j = i + 1
            while src[j] != '"':
                j += 2 if src[j] == "\\" else 1
            out.append(re.sub(r"[^\n]", " ", src[i : j + 1]))
            i = j + 1
        elif src[i] == "'":
            m = re.match(r"'(\\.|\\u\{[0-9a-fA-F]+\}|[^\\'])'", src[i:])
            length = len(m.group(0)) if m else 1
            out.append(" " * length if m else "'")
            i += length
        else:
            out.append(src[i])
            i += 1
    return "".join(out)


def block_end(code, start):
    """The index of the brace that closes the one at `start`."""
    depth = 0
    for k in range(start, len(code)):
        if code[k] == "{":
            depth += 1
        elif code[k] == "}":
            depth -= 1
            if depth == 0:
                return k
    raise ValueError("unbalanced braces")


def test_ranges(code):
    ranges = []
    for m in re.finditer(r"#\[cfg\(test\)\]\s*(pub(\([^)]*\))?\s+)?mod\s+\w+\s*\{", code):
        ranges.append((m.start(), block_end(code, m.end() - 1)))
    return ranges


def sources(root="src"):
    for folder, _, names in os.walk(root):
        for name in sorted(names):
            if name.endswith(".rs"):
                path = os.path.join(folder, name)
                yield path, open(path, encoding="utf-8").read()


def long_functions(path, text):
    code = strip(text)
    tests = test_ranges(code)
    lines = text.split("\n")
    for m in re.finditer(r"\bfn\s+(\w+)", code):
        if any(a <= m.start() <= b for a, b in tests):
            continue
        k, depth = m.end(), 0
        while k < len(code):
            c = code[k]
            if c in "(<[":
                depth += 1
            elif c in ")>]" and not (c == ">" and code[k - 1] == "-"):
                depth -= 1
            elif c == ";" and depth <= 0:
                k = -1
                break
            elif c == "{" and depth <= 0:
                break
            k += 1
        if k < 0 or k >= len(code):
            continue
        first = code.count("\n", 0, m.start())
        last = code.count("\n", 0, block_end(code, k))
        if last - first + 1 > FUNCTION_LINES:
            # Its doc comment: the `///` lines (and attributes) just above it.
            doc, j = [], first - 1
            while j >= 0 and lines[j].strip().startswith(("///", "#[", "pub", "unsafe", "async", "const")):
                doc.append(lines[j])
                j -= 1
            reason = any("over 80 lines" in d for d in doc)
            yield last - first + 1, first + 1, m.group(1), reason


def layers():
    """Each top-level entry of src/ (a folder or a file) and its place in lib.rs's list of layers."""
    text = open("src/lib.rs", encoding="utf-8").read()
    listed = text.split("//! ## Layers", 1)[1].split("\n\n", 1)[0]
    order = {}
    for m in re.finditer(r"^//! (\d+)\. (.*)$", listed, re.M):
        for name in re.findall(r"\[`(\w+)`\]|`(\w+)`", m.group(2)):
            order.setdefault(name[0] or name[1], int(m.group(1)))
    return order


def layer_of(path, order):
    top = path.split(os.sep)[1]
    return top[:-3] if top.endswith(".rs") else top


def citations():
    """Failures for each `model.md §…` that names no section of docs/model.md."""
    model = open("docs/model.md", encoding="utf-8").read()
    sections = set(re.findall(r"^##+ (\d+(?:\.\d+)*)[. ]", model, re.M))
    failures = []
    roots = ["src", "glsl", "crates", "docs"]
    files = [os.path.join(d, n) for r in roots for d, _, ns in os.walk(r) for n in ns
             if n.endswith((".rs", ".glsl", ".md")) and "experiments" not in d]
    for path in files + ["README.md", "ARCHITECTURE.md"]:
        text = open(path, encoding="utf-8").read()
        for m in re.finditer(r"model\.md[^§\n]{0,3}((?:§\s?\d+(?:\.\d+)*(?:[–-]§?\d+(?:\.\d+)*)?(?:,\s*)?)+)", text):
            for ref in re.findall(r"\d+(?:\.\d+)*", m.group(1)):
                if ref not in sections:
                    line = text.count("\n", 0, m.start()) + 1
                    failures.append(f"{path}:{line}: cites model.md §{ref}, which docs/model.md does not have")
    return failures


def anchor(heading):
    """GitHub's anchor of a heading: lower case, letters, marks, numbers, `_`, spaces as hyphens, the rest dropped."""
    import unicodedata
    kept = "".join(c for c in heading.strip().lower()
                   if unicodedata.category(c)[0] in "LMN" or c in "_- ")
    return kept.replace(" ", "-")


def links():
    """Failures for each relative markdown link that leads nowhere."""
    failures = []
    pages = ["README.md", "ARCHITECTURE.md"] + [os.path.join(d, n) for d, _, ns in os.walk("docs") for n in ns
                                                if n.endswith(".md")]
    anchors = {}
    for page in pages:
        text = open(page, encoding="utf-8").read()
        prose = re.sub(r"```.*?```", "", text, flags=re.S)
        for m in re.finditer(r"\]\(([^)\s]+)\)", prose):
            target = m.group(1)
            if re.match(r"[a-z]+:", target):
                continue
            path, _, frag = target.partition("#")
            file = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
            line = text.count("\n", 0, text.find(m.group(0))) + 1
            if not os.path.exists(file):
                failures.append(f"{page}:{line}: the link {target} leads to no file")
                continue
            if frag and file.endswith(".md"):
                if file not in anchors:
                    body = re.sub(r"```.*?```", "", open(file, encoding="utf-8").read(), flags=re.S)
                    anchors[file] = {anchor(h) for h in re.findall(r"^#+ (.*)$", body, re.M)}
                if frag not in anchors[file]:
                    failures.append(f"{page}:{line}: the link {target} names no heading of {file}")
    return failures


def main():
    failures = citations() + links()
    listing = "--list" in sys.argv
    order = layers()
    long_ones = []
    for path, text in sources():
        if path.startswith("src/render/") and text.count("\n") > RENDER_FILE_LINES:
            failures.append(f"{path}: {text.count(chr(10))} lines (src/render holds files of at most {RENDER_FILE_LINES})")
        header = 0
        for line in text.split("\n"):
            if not line.startswith("//!"):
                break
            header += 1
        if header > HEADER_LINES and path != "src/lib.rs":
            failures.append(f"{path}: a module header of {header} lines (at most {HEADER_LINES}: derivations go to "
                            f"docs/model.md, figures to docs/)")
        for length, line, name, reason in long_functions(path, text):
            long_ones.append((length, path, line, name, reason))
        layer = layer_of(path, order)
        if layer in ("lib", "main", "fuzz") or layer not in order:
            if layer not in ("lib", "main", "fuzz"):
                failures.append(f"{path}: its layer {layer!r} is not in src/lib.rs's list of layers")
            continue
        code = strip(text)
        tests = test_ranges(code)
        for m in re.finditer(r"\bcrate::(\w+)", code):
            if any(a <= m.start() <= b for a, b in tests):
                continue
            used = m.group(1)
            if used in order and order[used] > order[layer]:
                line = code.count("\n", 0, m.start()) + 1
                failures.append(f"{path}:{line}: layer {order[layer]} ({layer}) uses crate::{used}, layer "
                                f"{order[used]}, listed after it in src/lib.rs")
    long_ones.sort(reverse=True)
    for length, path, line, name, reason in long_ones:
        if listing:
            print(f"{path}:{line}: fn {name}: {length} lines" + ("" if reason else " (no reason given)"))
        if not reason:
            failures.append(f"{path}:{line}: fn {name} runs {length} lines (over {FUNCTION_LINES}) without saying why "
                            f"in its doc comment (a line with \"over 80 lines\")")
    if len(long_ones) > MAX_LONG:
        failures.append(f"{len(long_ones)} functions in src/ run over {FUNCTION_LINES} lines (at most {MAX_LONG})")
    for f in failures:
        print(f"check-house: {f}")
    if not failures:
        print(f"check-house: layers as src/lib.rs lists them; {len(long_ones)} functions over {FUNCTION_LINES} lines "
              f"(at most {MAX_LONG}, each with its reason); src/render's files within {RENDER_FILE_LINES} lines; "
              f"module headers within {HEADER_LINES} lines; every model.md § cited exists; every relative link of the docs leads "
              f"somewhere")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
