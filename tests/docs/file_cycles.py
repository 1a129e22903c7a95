# SPDX-License-Identifier: BSD-3-Clause
"""file_cycles: no circle between the library's source files.

    python3 file_cycles.py SOURCE_DIR

A file depends on another when it calls a cdpr_* function defined there or includes one of
its headers (lib/<layer>/include/cdpr/...). Two files that depend on each other, directly or
through others, share one job and should be one file, or one of them holds something that
belongs elsewhere (docs/development.md "Map of the code"). Prints every circle found and exits
1; exits 0 when there is none.
"""
import glob
import os
import re
import sys


def strip_comments(text):
    return re.sub(r"//[^\n]*|/\*.*?\*/", "", text, flags=re.S)


def main():
    root = sys.argv[1]
    sources = sorted(glob.glob(os.path.join(root, "lib", "*", "src", "*.c")))
    defined = {}
    for path in sources:
        text = strip_comments(open(path, encoding="utf-8").read())
        for m in re.finditer(r"^[a-z_][a-z0-9_ \*]*?\b(cdpr_[a-z0-9_]+)\s*\([^;{]*\)\s*\{", text,
                             re.M):
            defined[m.group(1)] = path
    # header cdpr/<prefix>/<stem>.h -> the source that implements it (same stem, same layer)
    by_header = {}
    for path in sources:
        layer = path.split(os.sep)[-3]
        stem = os.path.splitext(os.path.basename(path))[0]
        for inc in glob.glob(os.path.join(root, "lib", layer, "include", "cdpr", "**", stem + ".h"),
                             recursive=True):
            rel = os.path.relpath(inc, os.path.join(root, "lib", layer, "include"))
            by_header[rel] = path
    edges = {}
    for path in sources:
        text = strip_comments(open(path, encoding="utf-8").read())
        deps = {defined[c] for c in re.findall(r"\b(cdpr_[a-z0-9_]+)\s*\(", text) if c in defined}
        deps |= {by_header[h] for h in re.findall(r'#include "(cdpr/[^"]+)"', text)
                 if h in by_header}
        deps.discard(path)
        edges[path] = deps

    def reachable(start):
        seen, todo = set(), [start]
        while todo:
            for nxt in edges.get(todo.pop(), ()):
                if nxt not in seen:
                    seen.add(nxt)
                    todo.append(nxt)
        return seen

    circles = sorted({tuple(sorted((a, b))) for a in sources for b in edges[a]
                      if a in reachable(b)})
    for a, b in circles:
        print("circle: %s <-> %s" % (os.path.relpath(a, root), os.path.relpath(b, root)))
    print("%d source files, %d circles" % (len(sources), len(circles)))
    return 1 if circles else 0


if __name__ == "__main__":
    sys.exit(main())
