# SPDX-License-Identifier: BSD-3-Clause
"""Starting and stopping a wsgsim process on free ports."""
import os
import select
import shutil
import signal
import subprocess
import tempfile
import time

from .binary import binary_client
from .control import Control
from .gcl import DEFAULT_TIMEOUT, GclError, GclTcp, GclUdp

START_TIMEOUT = 60.0  # wsgsim up and listening
STOP_TIMEOUT = 60.0  # wsgsim gone after SIGTERM (valgrind checks leaks at exit)
LOOPBACK = {"0.0.0.0": "127.0.0.1", "::": "::1"}


def find_binary(binary=None):
    """The wsgsim program: binary, else $WSGSIM, else wsgsim on PATH."""
    found = binary or os.environ.get("WSGSIM") or shutil.which("wsgsim")
    if not found:
        raise GclError("no wsgsim program: install the wsgsim package, put it on PATH "
                       "or set WSGSIM=/path/to/wsgsim")
    return found


def option_value(args, name):
    """The value of the last --name X or --name=X in args, or None."""
    value = None
    for i, arg in enumerate(args):
        if arg == name and i + 1 < len(args):
            value = args[i + 1]
        elif arg.startswith(name + "="):
            value = arg[len(name) + 1:]
    return value


class Wsgsim:
    """A virtual gripper on free loopback ports: `with Wsgsim() as sim: sim.tcp()`.

    args are wsgsim options (wsgsim --help); they come after the defaults
    (--bind 127.0.0.1 --tcp-port 0 --udp-port 0), so they override them.
    The binary protocol is served on the TCP port; binary UDP is off unless
    args name --binary-udp-port N (its default, 1500, is one port per host),
    and the web interface is off unless args name --http-port N (its port
    is then self.http_port).
    paused=True starts the simulated clock paused at 0 and opens the control
    channel (sim.control().step(ms) advances it); control=True opens the
    control channel alone; coverage=PATH writes the protocol coverage report
    there at exit; net="rough" (or any --net conditions, docs/network.md)
    puts every session on that wire: its replies split, joined, delayed,
    its datagrams lost, doubled or reordered. timing="wsg50" (or an INI path) gives the
    device the real device's pace (--timing, docs/timing.md), seed=N seeds
    every random choice of the run (--seed). The ports are read from the
    --ready-file wsgsim writes
    once it serves, so any log level works. $WSGSIM_PREFIX runs the server
    under a tool, e.g. "valgrind --error-exitcode=99".
    """

    def __init__(self, *args, binary=None, paused=False, control=False, coverage=None, net=None,
                 timing=None, seed=None):
        self.binary = binary
        extra = ["--net", net] if net else []
        if timing is not None:
            extra += ["--timing", str(timing)]
        if seed is not None:
            extra += ["--seed", str(seed)]
        if paused:
            extra += ["--start-paused"]
        if paused or control:
            extra += ["--sim-port", "0"]
        if coverage:
            extra += ["--coverage", str(coverage)]
        args = [str(a) for a in args]
        if "--binary-udp-port" not in args:
            # the device's default (1500) is one port for every instance, and a
            # port picked here could be taken by the server's own free ports
            # before it binds it: binary UDP only when the caller names a port
            extra += ["--binary-udp-port", "0"]
        if "--http-port" not in args:
            # the web interface's default (8080) is one port for every
            # instance, as above: only when the caller names a port
            extra += ["--http-port", "0"]
        self.args = ["--bind", "127.0.0.1", "--tcp-port", "0", "--udp-port", "0"] + extra + args
        self.prefix = os.environ.get("WSGSIM_PREFIX", "").split()
        self.proc = None
        self.tcp_port = None
        self.udp_port = None
        self.sim_port = None
        self.http_port = None
        self.ready = {}  # the --ready-file's keys: pid, tcp_port, udp_port, sim_port, http_port
        self.log = []  # every line wsgsim logged so far
        self._log_buffer = b""
        self._tmpdir = None
        self.returncode = None  # the exit status, once stopped

    def __enter__(self):
        self.start()
        return self

    def __exit__(self, *exc):
        self.stop()

    @property
    def host(self):
        """The address clients connect to (the loopback one for a wildcard --bind)."""
        bind = option_value(self.args, "--bind") or "127.0.0.1"
        return LOOPBACK.get(bind, bind)

    def _ready_path(self):
        given = option_value(self.args, "--ready-file")
        if given:
            return given, []
        self._tmpdir = tempfile.TemporaryDirectory(prefix="wsgsim-")
        path = os.path.join(self._tmpdir.name, "ready")
        return path, ["--ready-file", path]

    def start(self, timeout=START_TIMEOUT):
        binary = self.binary = find_binary(self.binary)
        if os.sep in binary and not os.path.exists(binary):
            raise GclError("%s does not exist: run make first" % binary)
        self._log_buffer = b""
        ready_path, ready_args = self._ready_path()
        self.proc = subprocess.Popen(self.prefix + [binary] + self.args + ready_args,
                                     stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, bufsize=0)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if os.path.exists(ready_path):
                self._read_ready(ready_path)
                self.drain_log(0)  # the ready line is logged before the file appears
                return
            if self._read_log_line(min(0.05, deadline - time.monotonic())) is None and \
                    self.proc.poll() is not None:
                break
        self.stop()
        raise GclError("wsgsim did not start: %s" % "".join(self.log))

    def _read_ready(self, path):
        with open(path) as f:
            self.ready = dict(line.rstrip("\n").split("=", 1) for line in f if "=" in line)
        port = lambda key: int(self.ready[key]) if key in self.ready else -1  # noqa: E731
        self.tcp_port, self.udp_port = port("tcp_port"), port("udp_port")
        self.sim_port = port("sim_port") if "sim_port" in self.ready else None
        self.http_port = port("http_port") if "http_port" in self.ready else None

    def _read_log_line(self, timeout):
        """One line of the server's stderr, or None after timeout / at its end.

        Reads the raw descriptor into our own buffer: select() on a buffered
        pipe object would miss lines Python had already buffered."""
        deadline = time.monotonic() + max(timeout, 0)
        while b"\n" not in self._log_buffer:
            ready, _, _ = select.select([self.proc.stderr], [], [],
                                        max(deadline - time.monotonic(), 0))
            if not ready:
                return None
            chunk = os.read(self.proc.stderr.fileno(), 65536)
            if not chunk:
                return None
            self._log_buffer += chunk
        raw, self._log_buffer = self._log_buffer.split(b"\n", 1)
        line = raw.decode(errors="replace") + "\n"
        self.log.append(line)
        return line

    def drain_log(self, timeout=0.05):
        """Reads what the server logged so far (non-blocking beyond timeout)."""
        while self._read_log_line(timeout) is not None:
            pass
        return "".join(self.log)

    def alive(self):
        return self.proc is not None and self.proc.poll() is None

    def stop(self):
        """SIGTERM, then waits; returns the exit status (None if never started)."""
        if self.proc is None:
            return None
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=STOP_TIMEOUT)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        rest = self._log_buffer
        while True:
            chunk = os.read(self.proc.stderr.fileno(), 65536)
            if not chunk:
                break
            rest += chunk
        self._log_buffer = b""
        self.log.append(rest.decode(errors="replace"))
        self.proc.stderr.close()
        code = self.returncode = self.proc.returncode
        self.proc = None
        if self._tmpdir is not None:
            self._tmpdir.cleanup()
            self._tmpdir = None
        return code

    def tcp(self, timeout=DEFAULT_TIMEOUT):
        """A new GCL connection over TCP."""
        return GclTcp(self.host, self.tcp_port, timeout)

    def udp(self, timeout=DEFAULT_TIMEOUT):
        """A new GCL peer over UDP."""
        return GclUdp(self.host, self.udp_port, timeout)

    def control(self, timeout=DEFAULT_TIMEOUT):
        """A connection to the control channel (paused=True, control=True or --sim-port)."""
        if self.sim_port is None:
            raise GclError("no control channel: start with paused=True, control=True "
                           "or --sim-port 0")
        bind = option_value(self.args, "--sim-bind") or "127.0.0.1"
        self.sim_addr = LOOPBACK.get(bind, bind)
        return Control(self.sim_addr, self.sim_port, timeout)

    def binary_protocol(self, timeout=DEFAULT_TIMEOUT):
        """A client of the WSG binary protocol (wsgsim.binary). (self.binary
        is the program's path.)"""
        return binary_client(self, timeout)
