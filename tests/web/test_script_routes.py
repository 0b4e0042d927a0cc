# SPDX-License-Identifier: BSD-3-Clause
"""The scripting routes of the JSON API (docs/web.md, docs/scripting.md):
the script's state, run, stop, console, and the /user/ store, with their
errors; run, stop and file changes are refused to non-loopback peers."""
import os
import shutil
import tempfile
import unittest

from test_sim import non_loopback_address
from webclient import WebSim, request

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
