# SPDX-License-Identifier: BSD-3-Clause
"""The scripting routes of the JSON API (docs/web.md, docs/scripting.md):
the script's state, run, stop, console, and the /user/ store, with their
errors; run, stop and file changes are refused to non-loopback peers."""
import os
import re
import shutil
import tempfile
import time
import unittest

from test_sim import non_loopback_address
from webclient import MOTION_TIMEOUT, WebSim, request, wait_for

ECHO = "cmd.register(0xB5)\nprint('echo ready')\nwhile true do\n  local id, p = cmd.read()\n" \
       "  cmd.send(id, etob(E_SUCCESS), p)\nend\n"


class ScriptRoutes(unittest.TestCase):
    def setUp(self):
        self.store = tempfile.mkdtemp(prefix="wsgsim-store-")
        self.addCleanup(shutil.rmtree, self.store)
        with open(os.path.join(self.store, "echo.lua"), "w") as f:
            f.write(ECHO)
        self.sim = WebSim("--script-dir", self.store, "--start-paused", "--sim-port", "0")
        self.sim.start()
        self.addCleanup(self.sim.stop)
        self.api = self.sim.base + "/api/devices/0"

    def test_run_shows_state_console_and_stop(self):
        idle = request(self.api + "/script").json()
        self.assertEqual((idle["running"], idle["file"], idle["startup"]), (False, None, None))
        reply = request(self.api + "/script/run", "POST", {"file": "/user/echo.lua"})
        self.assertEqual(reply.status, 200, reply)
        self.assertTrue(reply.json()["running"])
        self.assertEqual(reply.json()["registered"], [0xB5])
        console = request(self.api + "/script/console").json()
        self.assertEqual(console["lines"], ["running /user/echo.lua", "echo ready"])
        later = request(self.api + "/script/console?since=%d" % console["next"]).json()
        self.assertEqual((later["lines"], later["next"]), ([], console["next"]))
        self.assertEqual(request(self.api + "/script/stop", "POST", {}).status, 200)
        self.assertFalse(request(self.api + "/script").json()["running"])
        self.assertEqual(request(self.api + "/script/stop", "POST", {}).status, 409)

    def test_console_since_takes_line_numbers_only(self):
        self.assertEqual(request(self.api + "/script/run", "POST", {"file": "echo.lua"}).status, 200)
        for since in ("-1", "18446744073709551616", "x", "1.5", ""):
            reply = request(self.api + "/script/console?since=" + since)
            self.assertEqual((reply.status, reply.json()["error"]), (400, "E_INVALID_PARAMETER"),
                             since)
        # a number not given yet: nothing, and the next line's number
        for since in ("1000", "18446744073709551615"):
            reply = request(self.api + "/script/console?since=" + since).json()
            self.assertEqual((reply["lines"], reply["next"]), ([], 2), since)

    def test_run_errors(self):
        reply = request(self.api + "/script/run", "POST", {"file": "missing.lua"})
        self.assertEqual((reply.status, reply.json()["error"]), (404, "E_NOT_FOUND"))
        reply = request(self.api + "/script/run", "POST", {})
        self.assertEqual(reply.status, 400)
        reply = request(self.api + "/script/run", "POST", {"file": "echo.lua", "x": 1})
        self.assertEqual(reply.status, 400)
        self.assertEqual(request(self.api + "/script/run").status, 405)
        self.assertEqual(request(self.api + "/script/console?since=x").status, 400)
        self.assertFalse(request(self.api + "/script").json()["running"])

    def test_a_startup_script_chosen_here_runs_from_the_next_power_on(self):
        reply = request(self.api + "/script/startup", "PUT", {"file": "/user/echo.lua"})
        self.assertEqual(reply.status, 200, reply)
        self.assertEqual(reply.json()["startup"], "/user/echo.lua")
        self.assertFalse(reply.json()["running"], "it waits for the next power-on")
        with self.sim.control() as ctl:
            self.assertEqual(ctl("RESET()"), "ACK RESET")
            state = request(self.api + "/script").json()
            self.assertTrue(state["running"])
            self.assertEqual((state["file"], state["registered"]), ("/user/echo.lua", [0xB5]))
            reply = request(self.api + "/script/startup", "PUT", {"file": None})
            self.assertEqual((reply.status, reply.json()["startup"]), (200, None))
            request(self.api + "/script/stop", "POST", {})
            self.assertEqual(ctl("RESET()"), "ACK RESET")
            self.assertFalse(request(self.api + "/script").json()["running"])

    def test_a_startup_script_must_be_a_store_file(self):
        for file in ("/user/missing.lua", "echo.lua", "/user/../echo.lua", "/etc/passwd"):
            reply = request(self.api + "/script/startup", "PUT", {"file": file})
            self.assertEqual((reply.status, reply.json()["error"]), (404, "E_NOT_FOUND"), file)
        for body in ({}, {"file": 3}, {"file": "/user/echo.lua", "run": True}):
            self.assertEqual(request(self.api + "/script/startup", "PUT", body).status, 400, body)
        self.assertEqual(request(self.api + "/script/startup", "POST", {}).status, 405)
        self.assertIsNone(request(self.api + "/script").json()["startup"])

    def test_store_list_put_get_delete(self):
        listing = request(self.api + "/files").json()
        self.assertTrue(listing["writable"])
        self.assertEqual(listing["files"], [{"name": "echo.lua", "bytes": len(ECHO)}])
        text = "print('hi')\n"
        reply = request(self.api + "/files/hi.lua", "PUT", {"text": text})
        self.assertEqual(reply.status, 201, reply)
        self.assertEqual(request(self.api + "/files/hi.lua", "PUT", {"text": text}).status, 200)
        self.assertEqual(request(self.api + "/files/hi.lua").body, text)
        with open(os.path.join(self.store, "hi.lua")) as f:
            self.assertEqual(f.read(), text)
        self.assertEqual(request(self.api + "/files/hi.lua", "DELETE", {}).status, 200)
        self.assertEqual(request(self.api + "/files/hi.lua").status, 404)
        self.assertEqual(request(self.api + "/files/hi.lua", "DELETE", {}).status, 404)
        self.assertEqual(request(self.api + "/files/..", "PUT", {"text": "x"}).status, 400)
        self.assertEqual(request(self.api + "/files/x.lua", "PUT", {}).status, 400)
        self.assertEqual(request(self.api + "/files/a%2Fb.lua").status, 400)  # a/b.lua

    def test_the_startup_script_is_not_deleted(self):
        """The file a device runs at power-on stays until the page chooses
        another or none: 409 naming it, the file kept."""
        self.assertEqual(request(self.api + "/script/startup", "PUT",
                                 {"file": "/user/echo.lua"}).status, 200)
        reply = request(self.api + "/files/echo.lua", "DELETE", {})
        self.assertEqual((reply.status, reply.json()["error"]), (409, "E_NOT_AVAILABLE"))
        self.assertEqual(reply.json()["message"], "echo.lua is device 0's startup script: "
                                                  "choose another startup script or none first")
        self.assertTrue(os.path.exists(os.path.join(self.store, "echo.lua")))
        self.assertEqual(request(self.api + "/files/echo.lua", "PUT", {"text": ECHO}).status,
                         200)  # edited, it stays the startup script
        self.assertEqual(request(self.api + "/script/startup", "PUT", {"file": None}).status, 200)
        self.assertEqual(request(self.api + "/files/echo.lua", "DELETE", {}).status, 200)
        self.assertFalse(os.path.exists(os.path.join(self.store, "echo.lua")))

    def test_a_body_over_the_limit_is_refused(self):
        reply = request(self.api + "/files/big.lua", "PUT", {"text": "-" * 5000})
        self.assertEqual(reply.status, 413)
        self.assertFalse(os.path.exists(os.path.join(self.store, "big.lua")))


class ReadOnlyStore(unittest.TestCase):
    def test_the_startup_scripts_directory_is_read_only(self):
        store = tempfile.mkdtemp(prefix="wsgsim-store-")
        self.addCleanup(shutil.rmtree, store)
        with open(os.path.join(store, "echo.lua"), "w") as f:
            f.write(ECHO)
        sim = WebSim("--script", os.path.join(store, "echo.lua"), "--start-paused")
        sim.start()
        self.addCleanup(sim.stop)
        api = sim.base + "/api/devices/0"
        state = request(api + "/script").json()
        self.assertTrue(state["running"])
        self.assertEqual(state["startup"], os.path.join(store, "echo.lua"))
        self.assertFalse(request(api + "/files").json()["writable"])
        reply = request(api + "/files/x.lua", "PUT", {"text": "x"})
        self.assertEqual((reply.status, reply.json()["error"]), (403, "E_ACCESS_DENIED"))

    def test_no_store_is_404(self):
        sim = WebSim("--start-paused")
        sim.start()
        self.addCleanup(sim.stop)
        self.assertEqual(request(sim.base + "/api/devices/0/files").status, 404)
        with tempfile.NamedTemporaryFile("w", suffix=".lua") as f:  # no store: nothing runs
            f.write("print('host')\n")
            f.flush()
            reply = request(sim.base + "/api/devices/0/script/run", "POST", {"file": f.name})
        self.assertEqual((reply.status, reply.json()["error"]), (404, "E_NOT_FOUND"))
        self.assertFalse(request(sim.base + "/api/devices/0/script").json()["running"])


SECRET = "sk-THIS-IS-A-SECRET-4711"
# A key file whose third line does not compile: Lua's message would quote it.
KEY_FILE = "-----BEGIN PRIVATE KEY-----\nMIIEvQIBADANBgkqhkiG9w0BAQEFAASC\n'%s\n" % SECRET
SAVED = "; saved by the web page\n[device]\n"
CONFIG = "; a configuration kept in the store under a .lua name\n[device]\n"


class StoreBoundaries(unittest.TestCase):
    """The web reaches the store's Lua files and nothing else, in the shipped
    units' layout (the save file in the store): no host path runs, no text
    from outside the store is echoed, wsgsim's own files are no store files,
    and nothing but a regular file is opened (a FIFO would block)."""

    def setUp(self):
        self.top = tempfile.mkdtemp(prefix="wsgsim-top-")
        self.addCleanup(shutil.rmtree, self.top)
        self.store = os.path.join(self.top, "scripts")
        os.mkdir(self.store)
        self.files = {"echo.lua": ECHO, "saved.ini": SAVED, "config.lua": CONFIG}
        for name, text in self.files.items():
            self.write(os.path.join(self.store, name), text)
        self.write(os.path.join(self.top, "key.pem"), KEY_FILE)
        self.write(os.path.join(self.top, "outside.lua"), "print('%s')\n" % SECRET)
        os.mkfifo(os.path.join(self.store, "pipe.lua"))
        self.log_file = os.path.join(self.store, "wsgsim.log")
        self.sim = WebSim("--script-dir", self.store, "--save-file",
                          os.path.join(self.store, "saved.ini"), "--config",
                          os.path.join(self.store, "config.lua"), "--log-file", self.log_file,
                          "--start-paused", "--sim-port", "0")
        self.sim.start()
        self.addCleanup(self.sim.stop)
        self.api = self.sim.base + "/api/devices/0"

    @staticmethod
    def write(path, text):
        with open(path, "w") as f:
            f.write(text)

    def log(self):
        with open(self.log_file, errors="replace") as f:
            return f.read()

    def assert_serving(self):
        with self.sim.control() as ctl:
            self.assertEqual(ctl("SIMTIME?"), "SIMTIME=[0.000,0.000]")
        self.assertEqual(request(self.api + "/script").status, 200)

    def test_a_fifo_in_the_store_blocks_nothing(self):
        reply = request(self.api + "/files/pipe.lua")
        self.assertEqual((reply.status, reply.json()["message"]), (404, "not a regular file"))
        reply = request(self.api + "/script/run", "POST", {"file": "/user/pipe.lua"})
        self.assertEqual(reply.status, 404, reply)
        reply = request(self.api + "/script/startup", "PUT", {"file": "/user/pipe.lua"})
        self.assertEqual(reply.status, 404, reply)
        names = [f["name"] for f in request(self.api + "/files").json()["files"]]
        self.assertEqual(names, ["echo.lua"])
        # a FIFO where a write puts its temporary file: removed, not opened
        os.mkfifo(os.path.join(self.store, "new.lua.part"))
        self.assertEqual(request(self.api + "/files/new.lua", "PUT", {"text": "x = 1\n"}).status,
                         201)
        self.assertEqual(request(self.api + "/files/new.lua").body, "x = 1\n")
        self.assert_serving()

    def test_run_takes_store_files_only_and_echoes_nothing_from_outside(self):
        key = os.path.join(self.top, "key.pem")
        for file in (key, os.path.join(self.top, "outside.lua"), "/user/../key.pem",
                     "../outside.lua", "/user/../outside.lua", "/user/saved.ini", "config.lua",
                     "/user/wsgsim.log", "/user/config.lua", "/etc/passwd"):
            reply = request(self.api + "/script/run", "POST", {"file": file})
            self.assertEqual((reply.status, reply.json()["error"]), (404, "E_NOT_FOUND"), file)
            self.assertNotIn(SECRET, reply.body)
        # a missing host path and an existing one get the same answer
        missing = request(self.api + "/script/run", "POST", {"file": key + "x"}).json()["message"]
        present = request(self.api + "/script/run", "POST", {"file": key}).json()["message"]
        self.assertEqual(missing.replace(key + "x", key), present)
        state = request(self.api + "/script").json()
        self.assertEqual((state["running"], state["file"], state["error"]), (False, None, None))
        for url in ("/script", "/script/console", "/files", "/system"):
            self.assertNotIn(SECRET, request(self.api + url).body, url)
        self.assertNotIn(SECRET, self.log())
        self.assertEqual(request(self.api + "/script/run", "POST", {"file": "echo.lua"}).status,
                         200)

    def test_wsgsims_own_files_are_not_store_files(self):
        for name in ("saved.ini", "config.lua", "wsgsim.log"):
            for method, body in (("PUT", {"text": "[web]\nallow_remote = yes\n"}),
                                 ("DELETE", {}), ("GET", None)):
                reply = request(self.api + "/files/" + name, method, body)
                self.assertEqual((reply.status, reply.json()["error"]),
                                 (400, "E_INVALID_PARAMETER"), (method, name))
        reply = request(self.api + "/script/startup", "PUT", {"file": "/user/config.lua"})
        self.assertEqual(reply.status, 404)
        for name, text in self.files.items():
            with open(os.path.join(self.store, name)) as f:
                self.assertEqual(f.read(), text, name)
        self.assertTrue(os.path.exists(self.log_file))
        names = [f["name"] for f in request(self.api + "/files").json()["files"]]
        self.assertEqual(names, ["echo.lua"])  # a store file is NAME.lua, and not wsgsim's own

    def test_nul_characters_are_refused_not_cut(self):
        for name in ("x%00.lua", "x.lua%00.txt"):  # cut at the NUL: "x", "x.lua"
            reply = request(self.api + "/files/" + name, "PUT", {"text": "print(1)\n"})
            self.assertEqual((reply.status, reply.json()["error"]), (400, "E_INVALID_PARAMETER"))
        reply = request(self.api + "/files/t.lua", "PUT", {"text": "abc\u0000def"})
        self.assertEqual((reply.status, reply.json()["error"]), (400, "E_CMD_FORMAT_ERROR"))
        reply = request(self.api + "/files/t.lua", "PUT", raw=b'{"text":"abc\x00def"}')
        self.assertEqual(reply.status, 400)
        self.assertEqual(request(self.api + "/script/console?since=0%00").status, 400)
        reply = request(self.api + "/script/run", "POST", {"file": "echo.lua\u0000x"})
        self.assertEqual(reply.status, 400)
        self.assertEqual(sorted(os.listdir(self.store)), sorted(list(self.files) + [
            "pipe.lua", "wsgsim.log"]))
        # an escaped backslash before "u0000" is text, not a NUL
        reply = request(self.api + "/files/t.lua", "PUT", {"text": "\\u0000"})
        self.assertEqual(reply.status, 201, reply)
        self.assertEqual(request(self.api + "/files/t.lua").body, "\\u0000")

    def test_bytes_after_the_json_object_are_refused(self):
        for raw in (b'{"text":"abc"} {"text":"x"}', b'{"text":"abc"}x', b'{"text":"abc"}}'):
            reply = request(self.api + "/files/t.lua", "PUT", raw=raw)
            self.assertEqual((reply.status, reply.json()["error"]), (400, "E_CMD_FORMAT_ERROR"),
                             raw)
        self.assertFalse(os.path.exists(os.path.join(self.store, "t.lua")))
        reply = request(self.api + "/files/t.lua", "PUT", raw=b'{"text":"abc"} \r\n')
        self.assertEqual(reply.status, 201, reply)  # white space may follow


FLOOD_LINES = 3000
LOG_BURST, LOG_RATE = 100, 20  # host_log_script's limit: a burst, then lines per second
FLOOD = ("for i = 1, %d do print('flood ' .. i) end\n"
         "while true do sleep(100) print('tick') end\n" % FLOOD_LINES)


class ScriptLog(unittest.TestCase):
    """A script's output reaches the console whole and the log escaped and
    rate-limited: a print loop cannot flood the log or the terminal."""

    def setUp(self):
        self.store = tempfile.mkdtemp(prefix="wsgsim-store-")
        self.addCleanup(shutil.rmtree, self.store)
        with open(os.path.join(self.store, "flood.lua"), "w") as f:
            f.write(FLOOD)
        with open(os.path.join(self.store, "raw.lua"), "w") as f:
            f.write("print('raw\\r\\27[2J\\\\ \\195\\169 end')\n")
        with open(os.path.join(self.store, "fail.lua"), "w") as f:
            f.write("error('bad\\27[2J\\rend', 0)\n")
        self.log_file = os.path.join(self.store, "wsgsim.log")
        self.sim = WebSim("--script-dir", self.store, "--log-file", self.log_file,
                          "--start-paused", "--sim-port", "0")
        self.sim.start()
        self.addCleanup(self.sim.stop)
        self.api = self.sim.base + "/api/devices/0"

    def log(self):
        with open(self.log_file, "rb") as f:
            return f.read()

    def console_next(self):
        return request(self.api + "/script/console").json()["next"]

    def test_a_print_flood_is_rate_limited_in_the_log_and_kept_in_the_console(self):
        started = time.monotonic()
        self.assertEqual(request(self.api + "/script/run", "POST", {"file": "flood.lua"}).status,
                         200)
        # "running ..." and the flood; the loop then sleeps
        wait_for("the flood's end", lambda: self.console_next() >= FLOOD_LINES + 1,
                 MOTION_TIMEOUT)
        elapsed = time.monotonic() - started
        console = request(self.api + "/script/console?since=%d" % FLOOD_LINES).json()["lines"]
        self.assertEqual(console[-1], "flood %d" % FLOOD_LINES)  # the console keeps every line
        logged = len(re.findall(rb"script: flood \d+\n", self.log()))
        self.assertLess(logged, FLOOD_LINES)
        # a bound that only grows with a slower machine: the burst, then the rate
        self.assertLessEqual(logged, LOG_BURST + LOG_RATE * elapsed)
        # every line is logged or counted: the counts come before the next
        # line let through (the script's ticks, on the stepped clock)
        with self.sim.control() as ctl:
            def accounted():
                ctl.step(100)
                counts = re.findall(rb"warning: (\d+) lines from scripts suppressed "
                                    rb"\(rate limit\)", self.log())
                return logged + sum(int(n) for n in counts) >= FLOOD_LINES
            wait_for("the count of the suppressed lines", accounted, MOTION_TIMEOUT)

    def test_control_bytes_are_escaped_in_the_log(self):
        for name in ("raw.lua", "fail.lua"):
            self.assertEqual(request(self.api + "/script/run", "POST", {"file": name}).status, 200)
        console = request(self.api + "/script/console").json()["lines"]
        self.assertEqual(console, ["running raw.lua", "raw\r\x1b[2J\\ \u00e9 end",
                                   "running fail.lua", "bad\x1b[2J\rend"])  # as written
        log = self.log()
        self.assertIn(rb"script: raw\x0D\x1B[2J\\ \xC3\xA9 end" + b"\n", log)
        self.assertIn(rb"script error: bad\x1B[2J\x0Dend" + b"\n", log)
        self.assertNotIn(b"\r", log)
        self.assertNotIn(b"\x1b", log)


class SavedStartupScript(unittest.TestCase):
    """Save keeps the startup script chosen on the page: [script] startup with
    autostart, or autostart = no for none; a new process runs it."""

    def setUp(self):
        self.store = tempfile.mkdtemp(prefix="wsgsim-store-")
        self.addCleanup(shutil.rmtree, self.store)
        with open(os.path.join(self.store, "echo.lua"), "w") as f:
            f.write(ECHO)
        self.saved = os.path.join(self.store, "saved.ini")

    def start(self):
        sim = WebSim("--script-dir", self.store, "--save-file", self.saved)
        sim.start()
        self.addCleanup(sim.stop)
        return sim, sim.base + "/api/devices/0"

    def saved_text(self):
        with open(self.saved) as f:
            return f.read()

    def test_save_keeps_the_choice_and_none(self):
        sim, api = self.start()
        self.assertEqual(request(api + "/script/startup", "PUT", {"file": "/user/echo.lua"}).status,
                         200)
        self.assertEqual(request(api + "/settings/save", "POST", {}).status, 200)
        self.assertIn("startup = /user/echo.lua", self.saved_text())
        self.assertIn("autostart = yes", self.saved_text())
        sim.stop()
        _, api = self.start()
        state = request(api + "/script").json()
        self.assertEqual((state["startup"], state["running"]), ("/user/echo.lua", True))
        self.assertEqual(request(api + "/script/startup", "PUT", {"file": None}).status, 200)
        self.assertEqual(request(api + "/settings/save", "POST", {}).status, 200)
        self.assertIn("autostart = no", self.saved_text())

    def test_a_saved_startup_script_gone_meanwhile(self):
        """The saved choice's file deleted outside wsgsim: the device starts,
        the script failed and said so; Save keeps the choice until the page
        changes it, and none saved starts clean."""
        sim, api = self.start()
        self.assertEqual(request(api + "/script/startup", "PUT", {"file": "/user/echo.lua"}).status,
                         200)
        self.assertEqual(request(api + "/settings/save", "POST", {}).status, 200)
        sim.stop()
        os.remove(os.path.join(self.store, "echo.lua"))
        sim, api = self.start()
        state = request(api + "/script").json()
        self.assertEqual((state["startup"], state["running"], state["failure"], state["error"]),
                         ("/user/echo.lua", False, True,
                          "startup script /user/echo.lua: No such file or directory"))
        console = request(api + "/script/console").json()["lines"]
        self.assertEqual(console, ["startup script /user/echo.lua: No such file or directory"])
        self.assertIn("warning: script error: startup script /user/echo.lua", sim.drain_log())
        self.assertEqual(request(api + "/settings/save", "POST", {}).status, 200)
        self.assertIn("startup = /user/echo.lua", self.saved_text())  # kept
        self.assertIn("autostart = yes", self.saved_text())
        self.assertEqual(request(api + "/script/startup", "PUT", {"file": None}).status, 200)
        self.assertEqual(request(api + "/settings/save", "POST", {}).status, 200)
        self.assertIn("autostart = no", self.saved_text())
        sim.stop()
        sim, api = self.start()
        state = request(api + "/script").json()
        self.assertEqual((state["startup"], state["failure"]), (None, False))
        self.assertNotIn("script error", sim.drain_log())


class StartupScriptOfAFleet(unittest.TestCase):
    def test_another_devices_startup_script_is_not_deleted(self):
        store = tempfile.mkdtemp(prefix="wsgsim-store-")
        self.addCleanup(shutil.rmtree, store)
        with open(os.path.join(store, "echo.lua"), "w") as f:
            f.write(ECHO)
        sim = WebSim("--script-dir", store, "--start-paused", "--devices", "2")
        sim.start()
        self.addCleanup(sim.stop)
        devices = sim.base + "/api/devices/"
        self.assertEqual(request(devices + "1/script/startup", "PUT",
                                 {"file": "/user/echo.lua"}).status, 200)
        reply = request(devices + "0/files/echo.lua", "DELETE", {})
        self.assertEqual(reply.status, 409)
        self.assertIn("device 1's startup script", reply.json()["message"])
        self.assertTrue(os.path.exists(os.path.join(store, "echo.lua")))


class ScriptLoopbackRule(unittest.TestCase):
    def test_run_and_file_changes_refuse_a_non_loopback_peer(self):
        address = non_loopback_address()
        store = tempfile.mkdtemp(prefix="wsgsim-store-")
        self.addCleanup(shutil.rmtree, store)
        with open(os.path.join(store, "echo.lua"), "w") as f:
            f.write(ECHO)
        sim = WebSim("--script-dir", store, "--start-paused", http_bind="0.0.0.0")
        sim.start()
        self.addCleanup(sim.stop)
        outside = "http://%s:%d/api/devices/0" % (address, sim.http_port)
        reply = request(outside + "/script/run", "POST", {"file": "echo.lua"})
        self.assertEqual((reply.status, reply.json()["error"]), (403, "E_ACCESS_DENIED"))
        self.assertEqual(request(outside + "/files/echo.lua", "DELETE", {}).status, 403)
        reply = request(outside + "/script/startup", "PUT", {"file": "/user/echo.lua"})
        self.assertEqual(reply.status, 403)
        self.assertEqual(request(outside + "/script").status, 200)  # reading is served
        self.assertEqual(request(outside + "/files/echo.lua").status, 200)
        self.assertTrue(os.path.exists(os.path.join(store, "echo.lua")))


if __name__ == "__main__":
    unittest.main()
