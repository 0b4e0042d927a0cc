# SPDX-License-Identifier: BSD-3-Clause
"""The conventions of a well-kept Linux daemon: help and version,
log levels and timestamps, SIGHUP reopening the log, record and CAN log
files, the ready file and systemd's READY=1, --list-models --json, one
error-prefix style, and listening on names and IPv6."""
import json
import os
import re
import signal
import socket
import subprocess
import tempfile
import unittest

from gclclient import GclTcp, GclUdp, Wsgsim, wait_for

ISO_STAMP = re.compile(r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z wsgsim \[\d+\.\d{6}\] ")


def ask(client):
    """One query whose reply does not depend on earlier tests' FAST STOPs."""
    reply = client.command("GRIPSTATE?")
    if not reply.startswith("GRIPSTATE="):
        raise AssertionError("GRIPSTATE?: %r" % reply)


def binary():
    return Wsgsim().binary


def run(*args, **kw):
    # binary UDP and the web interface off: their default ports (1500, 8080)
    # are not this test's to take
    return subprocess.run([binary(), "--binary-udp-port", "0", "--http-port", "0"] + list(args),
                          capture_output=True,
                          text=True, timeout=60,
                          stdin=subprocess.DEVNULL, **kw)


class Case(unittest.TestCase):
    def setUp(self):
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        self.tmp = tmp.name

    def path(self, name):
        return os.path.join(self.tmp, name)

    def start(self, *args, **keywords):
        sim = Wsgsim(*args, **keywords)
        sim.start()
        self.addCleanup(self.stop, sim)
        return sim

    def stop(self, sim):
        code = sim.stop()
        if code is not None:
            self.assertEqual(code, 0, "wsgsim did not shut down cleanly:\n" + "".join(sim.log))


class HelpAndVersion(Case):
    def test_short_and_long_help_are_the_same_page(self):
        long, short = run("--help"), run("-h")
        self.assertEqual((long.returncode, short.returncode), (0, 0))
        self.assertEqual(long.stdout, short.stdout)
        self.assertTrue(long.stdout.startswith("Usage: wsgsim [OPTION]..."))
        self.assertEqual(long.stderr, "")

    def test_every_option_has_its_line_in_help(self):
        page = run("--help").stdout
        described = set(re.findall(r"^\s+(?:-\w, )?(--[a-z][a-z0-9-]*)", page, re.M))
        for option in ("--log-level", "--quiet", "--log-timestamps", "--log-file",
                       "--ready-file", "--can-log", "--json", "--bind", "--version", "--help"):
            self.assertIn(option, described)
        for option in described:  # each accepted: no "unknown option" for any of them
            self.assertNotIn("unknown option", run(option, "x", "--help").stderr, option)

    def test_short_and_long_version(self):
        long, short = run("--version"), run("-V")
        self.assertEqual(long.stdout, short.stdout)
        self.assertRegex(long.stdout, r"^wsgsim \d+\.\d+\.\d+ ")


class ErrorStyle(Case):
    """Every command-line or start-up error is one or more lines 'wsgsim: ...'
    on stderr and exit status 2, whatever path the program was run by."""

    BAD = [
        ["--bogus"], ["-x"], ["--tcp-port"], ["--tcp-port", "x"], ["--log-level", "loud"],
        ["--json"], ["stray"], ["--no-tcp", "--no-udp"], ["--model", "WSG 99"],
        ["--can", "vcan0", "--can-log", "x.log"], ["--config", "/nonexistent.ini"],
        ["--bind", "no.such.host.invalid", "--tcp-port", "0", "--no-udp"],
        ["--log-file", "/nonexistent/dir/log", "--tcp-port", "0", "--udp-port", "0"],
        ["--ready-file", "/nonexistent/dir/ready", "--tcp-port", "0", "--udp-port", "0",
         "--bind", "127.0.0.1"],
        ["--can-log", "/nonexistent/dir/can.log", "--tcp-port", "0", "--udp-port", "0",
         "--bind", "127.0.0.1"],
    ]

    def test_one_prefix_and_status_2(self):
        for args in self.BAD:
            with self.subTest(args=args):
                result = run(*args)
                self.assertEqual(result.returncode, 2, result.stderr)
                lines = result.stderr.splitlines()
                self.assertTrue(lines, "no message")
                for line in lines:
                    self.assertTrue(line.startswith("wsgsim: "), "%r: %r" % (args, line))

    def test_errors_say_what_would_be_accepted(self):
        """A refused value's error gives the way to a good one: the models,
        the range, the item of a list that is wrong."""
        expected = {
            ("--model", "foo"): ["unknown --model 'foo'", "'WSG 50-110', 'WSG 50-210', "
                                 "'WSG 32-068', 'WSG 25-064'", "--list-models"],
            ("--tcp-port", "70000"): ["invalid --tcp-port '70000'", "from 0 to 65535",
                                      "0: a free port"],
            ("--http-port", "x"): ["from 0 to 65535", "0: off"],
            ("--fingers", "fmf,xyz"): ["invalid --fingers 'fmf,xyz': 'xyz' is no finger",
                                       "none, generic, fmf or dsa"],
            ("--fingers", "abc,dsa"): ["'abc' is no finger"],
            ("--fingers", "fmf,dsa,fmf"): ["two fingers at most"],
            ("--devices", "0"): ["invalid --devices '0': expected an integer from 1 to 10000"],
            ("--max-clients", "500"): ["from 1 to 128"],
        }
        for args, parts in expected.items():
            with self.subTest(args=args):
                result = run(*args)
                self.assertEqual(result.returncode, 2, result.stderr)
                self.assertEqual(len(result.stderr.splitlines()), 1, result.stderr)
                for part in parts:
                    self.assertIn(part, result.stderr)

    def test_prefix_is_the_name_not_the_path(self):
        result = subprocess.run([os.path.abspath(binary()), "--bogus"], capture_output=True,
                                text=True, timeout=60)
        self.assertEqual(result.stderr, "wsgsim: unknown option '--bogus' (see --help)\n")


class ListModels(Case):
    def test_json_lists_the_same_models_as_text(self):
        text = run("--list-models").stdout.splitlines()
        listed = json.loads(run("--list-models", "--json").stdout)
        self.assertEqual([m["name"] for m in listed], [line.split("  ")[0].strip() for line in text])
        self.assertEqual(sum(m["default"] for m in listed), 1)
        for model in listed:
            self.assertGreater(model["stroke_mm"], 0)
            self.assertLessEqual(model["force_min_n"], model["force_max_n"])
        # the order of the two options does not matter
        self.assertEqual(json.loads(run("--json", "--list-models").stdout), listed)


class LogLevels(Case):
    def logged(self, *args):
        sim = self.start("--sim-port", "0", *args)
        ctl = sim.control()
        self.addCleanup(ctl.close)
        self.assertEqual(ctl("FAILNEXT(HOME,5)"), "ACK FAILNEXT")  # logs a warning
        sim.stop()
        return "".join(sim.log)

    def test_default_is_info(self):
        log = self.logged()
        self.assertIn("] info: virtual ", log)
        self.assertIn("] warning: fault injected", log)
        self.assertNotIn("] debug: ", log)

    def test_warn_hides_info(self):
        log = self.logged("--log-level", "warn")
        self.assertNotIn("] info: ", log)
        self.assertIn("] warning: fault injected", log)

    def test_quiet_and_error_log_errors_only(self):
        for args in (["--quiet"], ["--log-level", "error"]):
            log = self.logged(*args)
            self.assertNotIn("] info: ", log)
            self.assertNotIn("] warning: ", log)

    def test_debug_adds_debug_lines(self):
        log = self.logged("--log-level", "debug", "--ready-file", self.path("ready"))
        self.assertIn("] debug: ready file %s written" % self.path("ready"), log)

    def test_wall_clock_timestamps(self):
        sim = self.start("--log-timestamps", "--trace")
        with sim.tcp() as c:
            ask(c)
        sim.stop()
        lines = [line for line in "".join(sim.log).splitlines() if line]
        self.assertTrue(lines)
        for line in lines:
            self.assertTrue(ISO_STAMP.match(line) or re.match(r"^\S+Z trace \[", line), line)


class Rotation(Case):
    def test_sighup_reopens_log_record_and_can_log(self):
        log, record, can = self.path("wsgsim.log"), self.path("rec.txt"), self.path("can.log")
        sim = self.start("--log-file", log, "--record", record, "--can-log", can, paused=True)
        ctl = sim.control()
        self.addCleanup(ctl.close)
        with sim.tcp() as c:
            ask(c)
            ctl.step(50)
            for name in (log, record, can):
                os.rename(name, name + ".1")
            sim.proc.send_signal(signal.SIGHUP)
            wait_for("the new log file", lambda: os.path.exists(log) and
                     "log file reopened" in open(log).read())
            ask(c)
            ctl.step(50)
        self.assertTrue(sim.alive(), "SIGHUP must not end wsgsim")
        self.stop(sim)
        self.assertIn("ready: tcp", open(log + ".1").read())
        self.assertIn("shutting down", open(log).read())
        self.assertEqual(open(record).read().count("GRIPSTATE?"), 1)
        self.assertTrue(open(record).read().startswith("# wsgsim record"))
        self.assertEqual(open(record + ".1").read().count("GRIPSTATE?"), 1)
        self.assertGreater(os.path.getsize(can + ".1"), 0)
        self.assertGreater(os.path.getsize(can), 0)

    def test_log_file_is_appended_to(self):
        log = self.path("wsgsim.log")
        with open(log, "w") as f:
            f.write("earlier line\n")
        sim = self.start("--log-file", log)
        self.stop(sim)
        text = open(log).read()
        self.assertTrue(text.startswith("earlier line\n"))
        self.assertIn("ready: tcp", text)
        self.assertNotIn("ready: tcp", "".join(sim.log), "the log went to the file, not stderr")


class Readiness(Case):
    def test_ready_file_names_the_ports_and_goes_at_exit(self):
        ready = self.path("ready")
        sim = self.start("--ready-file", ready, "--sim-port", "0")
        values = dict(line.split("=", 1) for line in open(ready).read().splitlines())
        self.assertEqual(int(values["pid"]), sim.proc.pid)
        self.assertEqual(int(values["tcp_port"]), sim.tcp_port)
        self.assertEqual(int(values["udp_port"]), sim.udp_port)
        self.assertIn("sim_port", values)
        with sim.tcp() as c:
            ask(c)
        self.stop(sim)
        self.assertFalse(os.path.exists(ready))

    def test_ready_file_leaves_out_what_is_not_served(self):
        ready = self.path("ready")
        self.start("--ready-file", ready, "--no-udp")
        keys = [line.split("=")[0] for line in open(ready).read().splitlines()]
        self.assertEqual(keys, ["pid", "tcp_port", "bin_tcp_port"])  # binary UDP is UDP too

    def test_systemd_notify_socket_gets_ready(self):
        sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        self.addCleanup(sock.close)
        sock.bind(self.path("notify"))
        sock.settimeout(60)
        os.environ["NOTIFY_SOCKET"] = self.path("notify")
        try:
            sim = self.start()
        finally:
            del os.environ["NOTIFY_SOCKET"]
        message = sock.recv(4096).decode()
        self.assertIn("READY=1", message.split("\n"))
        self.assertIn("STATUS=virtual ", message)
        self.assertIn("MAINPID=%d" % sim.proc.pid, message.split("\n"))
        self.stop(sim)
        self.assertIn("STOPPING=1", sock.recv(4096).decode())


class Addresses(Case):
    def test_localhost_by_name(self):
        sim = self.start("--bind", "localhost")
        with GclTcp("127.0.0.1", sim.tcp_port) as c:
            ask(c)

    def test_ipv6_loopback(self):
        sim = self.start("--bind", "::1")
        self.assertIn("tcp [::1]:%d" % sim.tcp_port, "".join(sim.log))
        with GclTcp("::1", sim.tcp_port) as c:
            ask(c)
        with GclUdp("::1", sim.udp_port) as u:
            ask(u)

    def test_any_ipv6_serves_both_families(self):
        sim = self.start("--bind", "::")
        for host in ("::1", "127.0.0.1"):
            with self.subTest(host=host):
                with GclTcp(host, sim.tcp_port) as c:
                    ask(c)
                with GclUdp(host, sim.udp_port) as u:
                    ask(u)


if __name__ == "__main__":
    unittest.main()
