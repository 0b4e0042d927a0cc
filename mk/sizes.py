#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The sizes of the production sources: files over the line limit and
functions over the function limit, in firmware/, hal/ and host/ (every .c
and .h git knows there).

usage: mk/sizes.py [--check] [--file-max N] [--function-max N] [DIR...]

Without --check it prints every file and function over its limit, then one
line of totals; with --check it prints the same and exits 1 when there is
any. A function is counted from the first line of its definition to its
closing brace, both included. The sources follow .clang-format (Linux
braces): a function's body opens with a '{' alone at column 0 and closes
with a '}' alone at column 0, and its definition starts at the last line
before the '{' that starts at column 0 (its parameters may wrap onto
indented lines).
"""
import argparse
import re
import subprocess
import sys

# The first line of a definition: a type or name at column 0, not a
# comment, a preprocessor line or the end of something else.
DEFINITION_START = re.compile(r"^[A-Za-z_]")
FUNCTION_NAME = re.compile(r"([A-Za-z_]\w*)\s*\(")


def production_files(dirs):
    out = subprocess.run(["git", "ls-files", "--"] + dirs, check=True, capture_output=True,
                         text=True).stdout
    return [p for p in out.splitlines() if p.endswith((".c", ".h"))]


def functions(lines):
    """(name, first line, length) of each function definition."""
    found = []
    start = None
    for i, line in enumerate(lines):
        if line == "{" and i > 0:
            start = i - 1
            while start > 0 and not DEFINITION_START.match(lines[start]):
                start -= 1
        elif line == "}" and start is not None:
            header = " ".join(lines[start:start + 4])
            name = FUNCTION_NAME.search(header)
            found.append((name.group(1) if name else "?", start + 1, i - start + 1))
            start = None
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="exit 1 when over a limit")
    parser.add_argument("--file-max", type=int, default=600)
    parser.add_argument("--function-max", type=int, default=60)
    parser.add_argument("dirs", nargs="*", default=["firmware", "hal", "host"])
    args = parser.parse_args()

    long_files = []
    long_functions = []
    function_count = 0
    paths = production_files(args.dirs)
    for path in paths:
        with open(path, encoding="utf-8") as f:
            lines = f.read().split("\n")
        if lines and lines[-1] == "":
            lines.pop()
        if len(lines) > args.file_max:
            long_files.append((len(lines), path))
        for name, first, length in functions(lines):
            function_count += 1
            if length > args.function_max:
                long_functions.append((length, f"{path}:{first}", name))

    for length, path in sorted(long_files, reverse=True):
        print(f"file over {args.file_max} lines: {path} {length}")
    for length, where, name in sorted(long_functions, reverse=True):
        print(f"function over {args.function_max} lines: {where} {name}() {length}")
    print(f"sizes: {len(paths)} files, {function_count} functions; "
          f"{len(long_files)} files over {args.file_max} lines, "
          f"{len(long_functions)} functions over {args.function_max} lines")
    return 1 if args.check and (long_files or long_functions) else 0


if __name__ == "__main__":
    sys.exit(main())
