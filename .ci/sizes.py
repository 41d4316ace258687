#!/usr/bin/env python3
"""Source files over 800 lines and library functions over 100 lines.

Usage: .ci/sizes.py [--files N] [--functions N] [DIR...]   (default: the library crates)

A function's length is the number of lines from its `fn` line to the line of its closing
brace, found by matching braces outside comments, strings and character literals.
Functions inside a `#[cfg(test)]` module, in a module file named `tests.rs` and in
tests/, benches/ and examples/ are not library functions and are skipped. Exits 1 when anything is over a limit.
"""
import os
import re
import sys

LIBRARY = ["src", "codegen/src", "math/src", "mechanism-macros/src"]
FN = re.compile(r"^\s*(pub(\([^)]*\))?\s+)?(const\s+)?(unsafe\s+)?(extern\s+\"C\"\s+)?fn\s+(\w+)")


def strip(line, state):
    """The line with comments, strings and char literals blanked; `state` carries an open
    block comment or string across lines."""
    out, i = [], 0
    while i < len(line):
        c = line[i]
        if state["block"]:
            if line.startswith("*/", i):
                state["block"] -= 1
                i += 2
            elif line.startswith("/*", i):
                state["block"] += 1
                i += 2
            else:
                i += 1
            continue
        if state["string"]:
            if c == "\\" and not state["raw"]:
                i += 2
                continue
            if c == '"' and line[i + 1:i + 1 + state["hashes"]] == "#" * state["hashes"]:
                state["string"] = False
                i += 1 + state["hashes"]
                continue
            i += 1
            continue
        if line.startswith("//", i):
            break
        if line.startswith("/*", i):
            state["block"] = 1
            i += 2
            continue
        m = re.match(r'(b?r)(#*)"', line[i:])
        if m and (i == 0 or not (line[i - 1].isalnum() or line[i - 1] == "_")):
            state.update(string=True, raw=True, hashes=len(m.group(2)))
            i += len(m.group(0))
            continue
        if c == '"':
            state.update(string=True, raw=False, hashes=0)
            i += 1
            continue
        m = re.match(r"b?'(\\.[^']*|[^\\'])'", line[i:])
        if m:
            i += len(m.group(0))
            continue
        out.append(c)
        i += 1
    return "".join(out)


def functions(path):
    """(name, first line, length) of every function outside test modules."""
    lines = open(path, encoding="utf-8").read().split("\n")
    state = {"block": 0, "string": False, "raw": False, "hashes": 0}
    code = [strip(l, state) for l in lines]
    found, test_depth, depth, open_fns = [], None, 0, []
    pending_test = False
    for k, text in enumerate(code):
        raw = lines[k].strip()
        if raw.startswith("#[cfg(test)]"):
            pending_test = True
        m = FN.match(text)
        if m and test_depth is None:
            open_fns.append((m.group(6), k, depth))
        if pending_test and re.match(r"^\s*(pub(\([^)]*\))?\s+)?mod\s+\w+\s*\{", text):
            test_depth = depth
            pending_test = False
        for c in text:
            if c == "{":
                depth += 1
            elif c == "}":
                depth -= 1
                if open_fns and depth == open_fns[-1][2]:
                    name, start, _ = open_fns.pop()
                    found.append((name, start + 1, k - start + 1))
                if test_depth is not None and depth == test_depth:
                    test_depth = None
        # A declaration without a body (`fn f(&self);`) closes at its semicolon.
        if open_fns and open_fns[-1][1] == k and text.rstrip().endswith(";") and "{" not in text:
            open_fns.pop()
    return found


def main():
    args = sys.argv[1:]
    file_limit, fn_limit = 800, 100
    if "--files" in args:
        i = args.index("--files")
        file_limit = int(args[i + 1])
        del args[i:i + 2]
    if "--functions" in args:
        i = args.index("--functions")
        fn_limit = int(args[i + 1])
        del args[i:i + 2]
    roots = args or LIBRARY
    over_files, over_fns = [], []
    for root in roots:
        for dirpath, _, names in os.walk(root):
            for name in sorted(names):
                if not name.endswith(".rs"):
                    continue
                path = os.path.join(dirpath, name)
                count = open(path, encoding="utf-8").read().count("\n")
                if count > file_limit:
                    over_files.append((count, path))
                if name == "tests.rs":
                    continue
                for fn, line, length in functions(path):
                    if length > fn_limit:
                        over_fns.append((length, f"{path}:{line}", fn))
    for count, path in sorted(over_files, reverse=True):
        print(f"file {count:5} lines  {path}")
    for length, at, fn in sorted(over_fns, reverse=True):
        print(f"fn   {length:5} lines  {at}  {fn}")
    print(f"{len(over_files)} files over {file_limit} lines, "
          f"{len(over_fns)} functions over {fn_limit} lines")
    return 1 if over_files or over_fns else 0


if __name__ == "__main__":
    sys.exit(main())
