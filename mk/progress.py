#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs a long build step with its whole output in a log file, and shows
where it is: the lines that mark its stages, with the time since it began,
and a line every HEARTBEAT seconds while nothing new shows. On failure the
log's last lines and its path; the exit status is the command's.

usage: mk/progress.py NAME LOG REGEX -- COMMAND [ARG]...
  NAME   the prefix of every line shown ("deb", "image")
  LOG    the file that gets all of the command's output (stdout and stderr)
  REGEX  the lines shown (Python syntax, matched at the start of a line)
"""
import re
import subprocess
import sys
import threading
import time

HEARTBEAT = 30  # seconds between "still working" lines while no stage shows
TAIL = 40  # lines of the log shown on failure


def show(name, start, text):
    print("%s: [%4ds] %s" % (name, time.monotonic() - start, text), flush=True)


def main(argv):
    if len(argv) < 5 or argv[3] != "--":
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    name, log_path, stages, command = argv[0], argv[1], re.compile(argv[2]), argv[4:]
    start = time.monotonic()
    last_shown = [start]
    lock = threading.Lock()
    done = threading.Event()

    def heartbeat():
        while not done.wait(5):
            with lock:
                if time.monotonic() - last_shown[0] >= HEARTBEAT:
                    show(name, start, "... still working (all of it: %s)" % log_path)
                    last_shown[0] = time.monotonic()

    show(name, start, "%s (log: %s)" % (" ".join(command), log_path))
    threading.Thread(target=heartbeat, daemon=True).start()
    with open(log_path, "wb") as log:
        proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        for raw in proc.stdout:
            log.write(raw)
            log.flush()
            line = raw.decode(errors="replace").rstrip()
            if stages.match(line):
                with lock:
                    show(name, start, line.strip())
                    last_shown[0] = time.monotonic()
        code = proc.wait()
    done.set()
    if code != 0:
        with open(log_path, errors="replace") as log:
            sys.stdout.write("".join(log.readlines()[-TAIL:]))
        show(name, start, "failed (exit status %d), see %s" % (code, log_path))
    else:
        show(name, start, "done")
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
