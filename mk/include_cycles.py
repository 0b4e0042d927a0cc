#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Finds circles in the include graph of a tree's modules: a module is a
source file's path without its extension (x.c with x.h), and module A
points to B when a file of A includes B's header. A header without a
source (a folder's shared x_internal.h) is no module: who includes it
includes what it includes. A circle means that neither module can be read,
built or tested without the other.

usage: mk/include_cycles.py -I DIR... FILE...

Each '#include "NAME"' is looked up next to its file, then in the -I
directories in order, as the compiler does; names found nowhere (system
headers) are left out. Prints each circle as 'include circle: A -> B ->
A', then a total; exits 1 when there is any.
"""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def resolve(name, here, dirs):
    for d in [here] + dirs:
        path = os.path.normpath(os.path.join(d, name))
        if os.path.isfile(path):
            return path
    return None


def strongly_connected(edges):
    """Tarjan's groups of modules that reach each other (more than one)."""
    index, low, stack, on, groups = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(edges.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while True:
                w = stack.pop()
                on.discard(w)
                group.append(w)
                if w == v:
                    break
            if len(group) > 1:
                groups.append(sorted(group))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return groups


def main(argv):
    dirs, files = [], []
    args = iter(argv)
    for arg in args:
        if arg == "-I":
            dirs.append(next(args))
        elif arg.startswith("-I"):
            dirs.append(arg[2:])
        else:
            files.append(arg)
    includes = {}
    for path in files:
        with open(path, encoding="utf-8") as f:
            names = INCLUDE.findall(f.read())
        found = (resolve(name, os.path.dirname(path), dirs) for name in names)
        includes[os.path.normpath(path)] = [h for h in found if h]
    modules = {os.path.splitext(p)[0] for p in includes if p.endswith(".c")}

    def reached(header, seen):
        """The modules a header stands for: its own, or those of what a
        header without a source includes."""
        module = os.path.splitext(header)[0]
        if module in modules or header in seen:
            return {module} if module in modules else set()
        seen.add(header)
        out = set()
        for inner in includes.get(header, ()):
            out |= reached(inner, seen)
        return out

    edges = {}
    for path, headers in includes.items():
        module = os.path.splitext(path)[0]
        if module not in modules:
            continue
        for header in headers:
            for target in reached(header, set()) - {module}:
                edges.setdefault(module, set()).add(target)
    groups = strongly_connected(edges)
    for group in groups:
        print("include circle: " + " <-> ".join(group))
    print(f"include circles: {len(groups)} among {len(files)} files")
    return 1 if groups else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
