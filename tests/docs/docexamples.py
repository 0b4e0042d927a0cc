# SPDX-License-Identifier: BSD-3-Clause
"""The command examples of README.md and docs/*.md, read from the files and
run the way a reader pastes them.

The convention (docs/development.md, "Examples in these documents"): every fenced
block names its kind in its info string, `KIND [ATTRIBUTE]...`:

  sh          shell commands, run in order, each must exit 0
  sh norun    shown, not run (needs root, hardware or a long build); the
              text around it says so
  sh server   run on a fresh `make run` (build/wsgsim, default options)
  sh server="ARGS"          ... started as `build/wsgsim ARGS`
  sh serves   each line starts a server in the foreground: it must get
              ready, and stop cleanly on Ctrl-C (SIGINT)
  transcript  a GCL conversation over TCP (port=N, default 1000): `> ` is
              sent, `< ` must come back; `server` as above
  output      what the runnable block before it prints on stdout
  python      run with python3; `python norun` for a fragment
  text, ini, json, dbc   not commands: never run

A block right after `<!-- file: NAME -->` is written to the working
directory as NAME, not run. In `output` and `<` lines, `…` stands for any
text; an `output` line that is only `…` stands for any number of lines.
AUTOSEND lines (`< @...`) are samples: the same line may come more often.

Each document runs in a session of its own: one bash, in a network
namespace of its own (`unshare -rn`: the documented ports are free and
port 1000 can be bound), in a directory that looks like a built checkout
(build/, tools/, docs/, python/) with tools/ and build/ on PATH as if
installed. Jobs a block starts with `&` run on for the blocks after it;
a line ending in `&` that starts wsgsim is waited for until wsgsim is
ready. Every wait is bounded only against hangs.
"""
import os
import re
import select
import shlex
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
HERE = os.path.dirname(os.path.abspath(__file__))
DOCUMENTS = ["README.md"] + sorted(os.path.join("docs", name)
                                   for name in os.listdir(os.path.join(ROOT, "docs"))
                                   if name.endswith(".md"))
RUNNABLE = {"sh", "transcript", "python"}
KINDS = RUNNABLE | {"output", "text", "ini", "json", "dbc"}
TIMEOUT = 120  # per command, against hangs only
FENCE = re.compile(r"^```(.*)$")
FILE_MARK = re.compile(r"^<!-- file: (\S+) -->$")
# A line that looks like a command a reader could paste: it must be in a
# runnable block (or one marked norun).
COMMAND = re.compile(r"^ {0,4}(\$ )?(sudo |make( |$)|build/\S|tools/\S|curl |wsgsim |wsgctl |wsgbin |"
                     r"wsgplot |wsgcalib |wsgfit |wsgcheck |fingersim |nc |printf |python3 |pytest |candump |cansend |"
                     r"systemctl |journalctl |> [A-Z])")

# A usage synopsis (`wsgsim [--tcp-port N] ...`) is no command to paste.
SYNOPSIS = re.compile(r"\[(-|[A-Z])")


class Block:
    def __init__(self, path, line, info, text, file_name):
        self.path, self.line, self.text, self.file_name = path, line, text, file_name
        words = shlex.split(info) if info.strip() else []
        self.kind = words[0] if words else ""
        self.attrs = {}
        for word in words[1:]:
            key, _, value = word.partition("=")
            self.attrs[key] = value if _ else True
        self.output = None  # the output block that follows, if any

    def where(self):
        return "%s:%d" % (self.path, self.line)

    @property
    def runs(self):
        return self.kind in RUNNABLE and "norun" not in self.attrs and self.file_name is None


def read_blocks(path):
    """The fenced blocks of a document, in order."""
    blocks = []
    with open(os.path.join(ROOT, path), encoding="utf-8") as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines):
        match = FENCE.match(lines[i])
        if not match:
            i += 1
            continue
        start = i
        mark = FILE_MARK.match(lines[i - 1]) if i > 0 else None
        i += 1
        while i < len(lines) and lines[i].rstrip() != "```":
            i += 1
        if i >= len(lines):
            raise ValueError("%s:%d: a fence that is never closed" % (path, start + 1))
        block = Block(path, start + 1, match.group(1), "\n".join(lines[start + 1:i]) + "\n",
                      mark.group(1) if mark else None)
        if block.kind == "output" and blocks:
            blocks[-1].output = block
        blocks.append(block)
        i += 1
    return blocks


def convention_errors(blocks):
    """What breaks the convention: unknown kinds, commands in blocks that
    are neither run nor marked norun, output blocks without a command."""
    errors = []
    previous = None
    for block in blocks:
        if block.kind not in KINDS:
            errors.append("%s: fence kind %r: name one of %s" % (block.where(), block.kind,
                                                                  ", ".join(sorted(KINDS))))
        elif block.kind in ("text", "ini", "json", "dbc"):
            for number, line in enumerate(block.text.splitlines(), block.line + 1):
                if COMMAND.match(line) and not SYNOPSIS.search(line):
                    errors.append("%s:%d: a command in a %s block: make it ```sh (run) or "
                                  "```sh norun" % (block.path, number, block.kind))
        elif block.kind == "output" and (previous is None or not previous.runs):
            errors.append("%s: an output block must follow a block that runs" % block.where())
        unknown = set(block.attrs) - {"norun", "server", "serves", "port"}
        if unknown:
            errors.append("%s: unknown attribute(s) %s" % (block.where(), ", ".join(unknown)))
        previous = block
    return errors


def commands(text):
    """The commands of a sh block: lines (backslash continuations joined),
    without blank lines and whole-line comments."""
    result, pending = [], ""
    for line in text.splitlines():
        if line.rstrip().endswith("\\"):
            pending += line.rstrip()[:-1] + " "
            continue
        line = pending + line
        pending = ""
        if line.strip() and not line.lstrip().startswith("#"):
            result.append(line)
    return result


def pattern(line):
    """An expected line with … as 'any text'."""
    return re.compile("^" + ".*".join(re.escape(part) for part in line.split("…")) + "$")


def output_mismatch(expected, actual):
    """None when actual (lines) fits expected (lines with …), else why."""
    # reachable: the actual lines consumed so far after each expected line
    reachable = {0}
    for line in expected:
        if line.strip() == "…":  # any number of lines
            reachable = set(range(min(reachable), len(actual) + 1)) if reachable else set()
            continue
        match = pattern(line).match
        reachable = {a + 1 for a in reachable if a < len(actual) and match(actual[a])}
    if len(actual) in reachable:
        return None
    return "expected:\n  %s\ngot:\n  %s" % ("\n  ".join(expected), "\n  ".join(actual))


def make_checkout(directory):
    """A directory that looks like a built checkout: the built programs
    ($WSGSIM, $FINGERSIM or build/), tools/, docs/, python/."""
    build = os.path.join(directory, "build")
    os.mkdir(build)
    for name, variable in (("wsgsim", "WSGSIM"), ("fingersim", "FINGERSIM")):
        target = os.path.abspath(os.environ.get(variable, os.path.join(ROOT, "build", name)))
        if os.path.exists(target):
            os.symlink(target, os.path.join(build, name))
    for name in ("tools", "docs", "python"):
        os.symlink(os.path.join(ROOT, name), os.path.join(directory, name))
    os.mkdir(os.path.join(directory, "home"))


class Session:
    """One bash in a network namespace of its own, commands fed one by one."""

    def __init__(self, directory):
        self.directory = directory
        self.stderr_path = os.path.join(directory, ".stderr")
        self.stderr = open(self.stderr_path, "w+b")
        env = {"PATH": "%s/tools:%s/build:/usr/local/bin:/usr/bin:/bin" % (directory, directory),
               "HOME": os.path.join(directory, "home"), "LANG": "C.UTF-8", "TERM": "dumb"}
        self.marker = "__docexample_%d__" % os.getpid()
        self.proc = subprocess.Popen(
            ["unshare", "-rn", "/usr/bin/python3", os.path.join(HERE, "netns_shell.py")],
            cwd=directory, env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
            stderr=self.stderr, bufsize=0)
        code, out = self.run("id -u")
        if code != 0 or out.strip() != "0":
            raise AssertionError("no network namespace (unshare -rn): %s %s"
                                 % (out, self.new_stderr()))

    def new_stderr(self, since=0):
        self.stderr.flush()
        with open(self.stderr_path, "rb") as f:
            f.seek(since)
            return f.read().decode(errors="replace")

    def stderr_size(self):
        return os.path.getsize(self.stderr_path)

    def run(self, command, timeout=TIMEOUT):
        """(exit status, stdout) of one command in the session."""
        # stdin: /dev/null unless the command names its own (the shell reads
        # the next commands from its own stdin)
        self.proc.stdin.write(("{\n%s\n} </dev/null\nprintf '\\n%s %%d\\n' $?\n"
                               % (command, self.marker)).encode())
        out = b""
        deadline = time.monotonic() + timeout
        end = re.compile(rb"\n" + self.marker.encode() + rb" (\d+)\n$")
        while True:
            if time.monotonic() > deadline:
                self.close()
                raise AssertionError("%r did not end within %d s" % (command, timeout))
            chunk = self._read(deadline)
            if chunk is None:
                continue
            if not chunk:
                raise AssertionError("the shell ended during %r: %s"
                                     % (command, self.new_stderr()))
            out += chunk
            match = end.search(out)
            if match:
                return int(match.group(1)), out[:match.start()].decode(errors="replace")

    def _read(self, deadline):
        """Bytes from the shell; None when the deadline passed, b"" at its end."""
        wait = max(0.0, deadline - time.monotonic())
        ready, _, _ = select.select([self.proc.stdout], [], [], wait)
        return os.read(self.proc.stdout.fileno(), 65536) if ready else None

    def wait_ready(self, since, what):
        """Waits until the wsgsim just started in the background ($!) says
        it is ready."""
        _, pid = self.run("echo $!")
        deadline = time.monotonic() + TIMEOUT
        while time.monotonic() < deadline:
            text = self.new_stderr(since)
            if " ready: " in text:
                return
            code, _ = self.run("kill -0 %s 2>/dev/null" % pid.strip())
            if code != 0:
                raise AssertionError("%s ended before it was ready:\n%s" % (what, text))
            time.sleep(0.02)
        raise AssertionError("%s was not ready within %d s" % (what, TIMEOUT))

    def stop_jobs(self):
        """Stops every job the session started as Ctrl-C would; one that is
        still there after a minute is killed (a hang guard only)."""
        self.run("for j in $(jobs -p); do kill -INT $j 2>/dev/null; done; "
                 "for i in $(seq 600); do [ -z \"$(jobs -pr)\" ] && break; sleep 0.1; done; "
                 "kill -KILL $(jobs -pr) 2>/dev/null; wait")

    def close(self):
        if self.proc.poll() is None:
            try:
                self.proc.stdin.close()
            except OSError:
                pass
            try:
                self.proc.wait(timeout=TIMEOUT)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.stderr.close()


def without_comment(command):
    """The command without its trailing `# comment`."""
    return re.sub(r"(^|\s)#.*$", "", command).rstrip()


def starts_wsgsim(command):
    words = without_comment(command).split()
    return bool(words) and os.path.basename(words[0]) == "wsgsim"


def run_sh(session, block, failures):
    """Runs a sh block; returns its stdout."""
    stdout = ""
    for command in commands(block.text):
        since = session.stderr_size()
        background = without_comment(command).endswith("&")
        code, out = session.run(command)
        stdout += out
        if code != 0:
            failures.append("%s: `%s` exited with %d:\n%s%s" % (
                block.where(), command.strip(), code, out, session.new_stderr(since)))
            return stdout
        if background and starts_wsgsim(command):
            session.wait_ready(since, "`%s`" % command.strip())
    return stdout


def run_serves(session, block, failures):
    """Each line starts a server in the foreground: ready, then Ctrl-C."""
    for command in commands(block.text):
        since = session.stderr_size()
        session.run(without_comment(command) + " &")
        try:
            session.wait_ready(since, "`%s`" % command.strip())
        except AssertionError as err:
            failures.append("%s: %s" % (block.where(), err))
            return
        code, _ = session.run("kill -INT $!; wait $!")
        if code != 0:
            failures.append("%s: `%s` exited with %d after Ctrl-C:\n%s" % (
                block.where(), command.strip(), code, session.new_stderr(since)))


def start_server(session, block):
    session.stop_jobs()
    args = block.attrs["server"]
    command = "build/wsgsim %s &" % (args if isinstance(args, str) else "")
    since = session.stderr_size()
    code, out = session.run(command)
    if code != 0:
        raise AssertionError("%s: `%s` exited with %d" % (block.where(), command, code))
    session.wait_ready(since, "`%s`" % command)


def run_transcript(session, block, failures):
    path = os.path.join(session.directory, ".transcript")
    with open(path, "w") as f:
        f.write(block.text)
    port = block.attrs.get("port", "1000")
    code, out = session.run("/usr/bin/python3 %s %s %s" % (
        shlex.quote(os.path.join(HERE, "transcript.py")), port, shlex.quote(path)))
    if code != 0:
        failures.append("%s: the transcript differs:\n%s" % (block.where(), out))


def run_python(session, block, failures):
    path = os.path.join(session.directory, ".example.py")
    with open(path, "w") as f:
        f.write(block.text)
    code, out = session.run("python3 .example.py")
    if code != 0:
        failures.append("%s: the python example exited with %d:\n%s%s" % (
            block.where(), code, out, session.new_stderr()))
    return out


def run_block(session, block, failures):
    """Runs one block; returns its stdout when it has one to compare."""
    if block.kind == "transcript":
        run_transcript(session, block, failures)
        return None
    if block.kind == "python":
        return run_python(session, block, failures)
    if "serves" in block.attrs:
        run_serves(session, block, failures)
        return None
    return run_sh(session, block, failures)


def run_document(path):
    """Runs a document's examples; returns the failures (empty: all good)."""
    blocks = read_blocks(path)
    failures = convention_errors(blocks)
    if failures or not any(b.runs for b in blocks):
        return failures
    with tempfile.TemporaryDirectory(prefix="docexamples-") as directory:
        make_checkout(directory)
        session = Session(directory)
        try:
            for block in blocks:
                if block.file_name is not None:
                    with open(os.path.join(directory, block.file_name), "w") as f:
                        f.write(block.text)
                if not block.runs:
                    continue
                if "server" in block.attrs:
                    start_server(session, block)
                count = len(failures)
                stdout = run_block(session, block, failures)
                if os.environ.get("DOCEXAMPLES_SHOW") and stdout is not None:
                    print("%s:\n%s" % (block.where(), stdout))
                if block.output is not None and stdout is not None and len(failures) == count:
                    why = output_mismatch(block.output.text.rstrip("\n").split("\n"),
                                          stdout.rstrip("\n").split("\n"))
                    if why:
                        failures.append("%s: the output differs from %s: %s" % (
                            block.where(), block.output.where(), why))
                if "server" in block.attrs:
                    session.stop_jobs()  # the fresh `make run` was this block's
                if len(failures) > count:
                    break  # the blocks after it build on it
        finally:
            try:
                session.stop_jobs()
            except AssertionError:
                pass
            session.close()
    return failures


if __name__ == "__main__":
    problems = []
    for document in sys.argv[1:] or DOCUMENTS:
        problems += run_document(document)
    print("\n\n".join(problems) or "every example works")
    sys.exit(1 if problems else 0)
