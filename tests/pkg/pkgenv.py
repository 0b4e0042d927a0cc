# SPDX-License-Identifier: BSD-3-Clause
"""What the tests/pkg suites share: where the built things are, and how to
run a program and start a wsgsim (the wsgsim Python package of this tree)."""
import gzip
import os
import re
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))

from wsgsim import GclError, Wsgsim, read_record  # noqa: E402,F401

TIMEOUT = 120  # an upper bound against hangs only


def env_path(name, default):
    return os.path.abspath(os.environ.get(name, os.path.join(ROOT, default)))


WSGSIM = env_path("WSGSIM", "build/wsgsim")
FINGERSIM = env_path("FINGERSIM", "build/fingersim")
MAN_DIR = env_path("MAN_DIR", "build/man")
DEB_DIR = env_path("DEB_DIR", "build/deb")
DBC = os.path.join(ROOT, "docs", "finger-bus.dbc")
PROGRAMS = {"wsgsim": WSGSIM, "fingersim": FINGERSIM,
            "wsgctl": os.path.join(ROOT, "tools", "wsgctl"),
            "wsgplot": os.path.join(ROOT, "tools", "wsgplot"),
            "wsgbin": os.path.join(ROOT, "tools", "wsgbin"),
            "wsgprobe": os.path.join(ROOT, "tools", "wsgprobe"),
            "wsgproxy": env_path("WSGPROXY", "build/wsgproxy"),
            "wsgcalib": os.path.join(ROOT, "tools", "wsgcalib"),
            "wsgfit": os.path.join(ROOT, "tools", "wsgfit"),
            "wsgcheck": os.path.join(ROOT, "tools", "wsgcheck")}


def run(argv, **kw):
    """argv's result, text, nothing on stdin; timeout= another bound
    against hangs."""
    kw.setdefault("stdin", subprocess.DEVNULL)
    kw.setdefault("timeout", TIMEOUT)
    return subprocess.run(argv, capture_output=True, text=True, **kw)


def gcl_exchange(binary):
    """Starts binary as a virtual gripper and has a short GCL conversation;
    returns the replies."""
    with Wsgsim("--part", "40", binary=binary) as sim:
        with sim.tcp() as gcl:
            replies = [gcl.command("GRIPSTATE?"), gcl.command("SN?"),
                       gcl.long_command("HOME()", "HOME"), gcl.command("BYE()")]
        code = sim.stop()
    if code != 0:
        raise GclError("%s exited with %s:\n%s" % (binary, code, "".join(sim.log)))
    return replies


def man_named_files(page):
    """The files of the package a man page (.1 or .1.gz) names: its full
    /usr/.../wsgsim/... paths and the documents (NAME.md, NAME.md.gz) it lists
    after "The documentation in DIR:", each as an absolute path."""
    opener = gzip.open if page.endswith(".gz") else open
    with opener(page, "rt") as f:
        text = f.read().replace("\\-", "-").replace("\\&", "")
    text = re.sub(r"\\f[BRIP]", "", text)
    named = set(re.findall(r"(/usr/[\w./-]*/wsgsim/[\w./-]*[\w])", text))
    for folder, listing in re.findall(r"documentation in (/[\w./-]+): ([^;]*?\.)\s*$", text,
                                      re.M | re.S):
        named.update(os.path.join(folder, name)
                     for name in re.findall(r"([\w-]+\.md(?:\.gz)?)", listing))
    return sorted(named)
