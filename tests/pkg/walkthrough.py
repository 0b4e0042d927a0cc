# SPDX-License-Identifier: BSD-3-Clause
"""Runs docs/testing-your-driver.md's example with pytest: the files the
document introduces with '<!-- file: NAME -->' are written to a directory
and pytest runs there, the way a reader would."""
import os
import re
import subprocess

from pkgenv import ROOT, TIMEOUT

DOC = os.path.join(ROOT, "docs", "testing-your-driver.md")
FILE_BLOCK = re.compile(r"<!-- file: (\S+) -->\n```python\n(.*?)```", re.S)


def write_example(directory):
    """Writes the document's files into directory; returns their names."""
    with open(DOC) as f:
        blocks = FILE_BLOCK.findall(f.read())
    for name, code in blocks:
        with open(os.path.join(directory, name), "w") as out:
            out.write(code)
    return [name for name, _ in blocks]


def run_pytest(directory, env, *options):
    """Debian's python3 -m pytest in directory; returns the result."""
    command = ["/usr/bin/python3", "-m", "pytest", "-q", "-p", "no:cacheprovider"] + \
        list(options)
    return subprocess.run(command, cwd=directory, env=env, capture_output=True, text=True,
                          timeout=TIMEOUT * 5, stdin=subprocess.DEVNULL)
