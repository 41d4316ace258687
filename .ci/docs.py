#!/usr/bin/env python3
"""The documents' links and the book's doc-tests.

Usage: .ci/docs.py

Checks, without network and without mdbook:
- every relative link and image of README.md, BENCHMARKS.md, RELIABILITY.md,
  ARCHITECTURE.md and the book (docs/, drafts left out) names a file or folder that exists,
  and a `#fragment` names a heading of the target (GitHub's slugs: lower case, punctuation
  dropped, spaces to hyphens);
- every chapter that docs/src/SUMMARY.md lists is included by src/lib.rs's doc-test module
  (`include_str!("../docs/src/CHAPTER.md")`), so `cargo test --workspace` compiles and runs
  its ```rust blocks.
Exits 1 with one line per problem.
"""
import os
import re
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def documents():
    for name in ["README.md", "BENCHMARKS.md", "RELIABILITY.md", "ARCHITECTURE.md"]:
        yield os.path.join(ROOT, name)
    for folder, dirs, files in os.walk(os.path.join(ROOT, "docs")):
        dirs[:] = [d for d in dirs if d != "drafts"]
        for f in sorted(files):
            if f.endswith(".md"):
                yield os.path.join(folder, f)


def prose(text):
    """The text with fenced code blocks and inline code blanked (links there are not links)."""
    out, fence = [], False
    for line in text.split("\n"):
        if line.lstrip().startswith("```"):
            fence = not fence
            out.append("")
            continue
        out.append("" if fence else re.sub(r"`[^`]*`", "", line))
    return "\n".join(out)


def slug(heading):
    s = heading.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def anchors(path):
    """The fragments the headings of a markdown file define (repeats get -1, -2, ...)."""
    found, seen, fence = set(), {}, False
    for line in open(path, encoding="utf-8").read().split("\n"):
        if line.lstrip().startswith("```"):
            fence = not fence
            continue
        m = None if fence else re.match(r"^#{1,6}\s+(.*)", line)
        if m:
            base = slug(m.group(1))
            n = seen.get(base, 0)
            seen[base] = n + 1
            found.add(base if n == 0 else f"{base}-{n}")
    return found


def check_links(problems):
    for doc in documents():
        text = prose(open(doc, encoding="utf-8").read())
        for m in LINK.finditer(text):
            target = m.group(1)
            lineno = text.count("\n", 0, m.start()) + 1
            if re.match(r"^[a-z]+:", target):
                continue
            path, _, fragment = target.partition("#")
            full = os.path.normpath(os.path.join(os.path.dirname(doc), path)) if path else doc
            where = f"{os.path.relpath(doc, ROOT)}:{lineno}"
            if not os.path.exists(full):
                problems.append(f"{where}: link to {target}: no such file")
            elif fragment and full.endswith(".md") and fragment not in anchors(full):
                problems.append(f"{where}: link to {target}: no heading #{fragment}")


def check_doctests(problems):
    summary = open(os.path.join(ROOT, "docs/src/SUMMARY.md"), encoding="utf-8").read()
    lib = open(os.path.join(ROOT, "src/lib.rs"), encoding="utf-8").read()
    for chapter in re.findall(r"\]\(([^)]+\.md)\)", summary):
        if f'include_str!("../docs/src/{chapter}")' not in lib:
            problems.append(f"docs/src/SUMMARY.md: chapter {chapter} is not a doc-test in src/lib.rs")


def check_fences(problems):
    """A fence line is three backticks and an optional language, nothing after: text after
    a closing fence makes markdown (and rustdoc) read on in a code block."""
    for doc in documents():
        for lineno, line in enumerate(open(doc, encoding="utf-8").read().split("\n"), 1):
            stripped = line.strip()
            if stripped.startswith("```") and not re.match(r"^```[\w,+-]*$", stripped):
                problems.append(f"{os.path.relpath(doc, ROOT)}:{lineno}: text after a code fence")


def main():
    problems = []
    check_fences(problems)
    check_links(problems)
    check_doctests(problems)
    for p in problems:
        print(p)
    if problems:
        sys.exit(1)
    print("docs.py: every link resolves; every chapter is a doc-test")


if __name__ == "__main__":
    main()
