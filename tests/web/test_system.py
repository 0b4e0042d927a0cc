# SPDX-License-Identifier: BSD-3-Clause
"""GET /api/devices/{id}/system (docs/web.md): the page's System view: the
identity a GCL client reads, the uptime since the last power-on on the
simulated clock, and the last lines of wsgsim's log, paged by ?since=N."""
import os
import shutil
import tempfile

from test_api import WebCase
from webclient import MOTION_TIMEOUT, GclTcp, WebSim, request, wait_for

LOG_KEPT = 100  # lines the log keeps for the page


class System(WebCase):
    ARGS = ("--start-paused", "--sim-port", "0", "--devices", "2")

    def system(self, query="", device=0):
        reply = self.get("/api/devices/%d/system%s" % (device, query))
        self.assertEqual(reply.status, 200, reply)
        return reply.json()

    def test_identity_is_what_gcl_reads(self):
        for device in (0, 1):
            j = self.system(device=device)
            port = self.get("/api/devices").json()["devices"][device]["tcp_port"]
            gcl = GclTcp("127.0.0.1", port)
            self.addCleanup(gcl.close)
            self.assertEqual(j["id"], device)
            self.assertEqual('DEVTYPE="%s"' % j["model"], gcl.command("DEVTYPE?"))
            self.assertEqual('VERSION="%s"' % j["firmware_version"], gcl.command("VERSION?"))
            self.assertEqual("SN=%d" % j["serial"], gcl.command("SN?"))
            self.assertEqual((j["stroke_mm"], j["force_min_n"], j["force_max_n"]), (110, 5, 80))
            # the ranges the page's fields show, as GCL's refusals draw them
            self.assertEqual((j["speed_min_mm_s"], j["speed_max_mm_s"]), (5, 420))
            self.assertEqual(gcl.command("MOVE(50, %g)" % (j["speed_max_mm_s"] + 1)),
                             "ERR MOVE 28")
            self.assertEqual((j["accel_min_mm_s2"] > 0, j["accel_max_mm_s2"] > 0), (True, True))
            settings = "/api/devices/%d/settings" % device
            reply = request(self.sim.base + settings, method="PUT",
                            body={"accel_mm_s2": j["accel_max_mm_s2"] + 1})
            self.assertEqual((reply.status, reply.json()["error"]), (422, "E_RANGE_ERROR"))
            reply = request(self.sim.base + settings, method="PUT",
                            body={"accel_mm_s2": j["accel_max_mm_s2"]})
            self.assertEqual(reply.status, 200)
            self.assertEqual(j["force_overdrive_n"], 0)  # the WSG 50 has no overdrive
            self.assertRegex(j["wsgsim_version"], r"^\d+\.\d+")
            self.assertFalse(j["script_store"])  # no --script-dir: …/files is 404
            self.assertEqual(self.get("/api/devices/%d/files" % device).status, 404)

    def test_timing_profile_shown(self):
        """The System view names the timing profile the control channel set."""
        with self.sim.control() as ctl:
            self.assertEqual(self.system()["timing"], "ideal")
            self.assertEqual(ctl("TIMING=wsg50"), 'TIMING="wsg50"')
            self.assertEqual(self.system()["timing"], "wsg50")
            self.assertTrue(ctl("TIMING=nope").startswith("ERR TIMING"))
            self.assertEqual(self.system()["timing"], "wsg50")
            self.assertEqual(ctl("TIMING=ideal"), 'TIMING="ideal"')

    def test_uptime_restarts_at_a_power_cycle(self):
        with self.sim.control() as ctl:
            first = self.system()
            self.assertEqual(first["uptime_ms"], first["time_ms"])  # powered on at start
            self.assertTrue(ctl("STEP(250)").startswith("STEP="))
            self.assertEqual(self.system()["uptime_ms"], first["uptime_ms"] + 250)
            self.assertEqual(ctl("RESET()"), "ACK RESET")
            self.assertTrue(ctl("STEP(100)").startswith("STEP="))
            after = self.system()
            self.assertEqual(after["uptime_ms"], 100)
            self.assertEqual(after["time_ms"], first["time_ms"] + 350)

    def test_log_lines_are_paged_by_number(self):
        log = self.system()["log"]
        self.assertTrue(any("ready: tcp" in line for line in log["lines"]), log)
        self.assertEqual(len(log["lines"]), log["next"])
        later = self.system("?since=%d" % log["next"])["log"]
        self.assertEqual(later, {"next": log["next"], "lines": []})
        with self.sim.control() as ctl:  # a power cycle is logged
            self.assertEqual(ctl("RESET()"), "ACK RESET")
        news = self.system("?since=%d" % log["next"])["log"]
        self.assertGreater(news["next"], log["next"])
        self.assertEqual(len(news["lines"]), news["next"] - log["next"])
        self.assertEqual(self.system()["log"]["lines"][:len(log["lines"])], log["lines"])

    def test_bad_requests(self):
        for query in ("?since=x", "?since=", "?since=-1", "?since=1x"):
            self.assert_error(self.get("/api/devices/0/system" + query), 400,
                              "E_INVALID_PARAMETER")
        reply = self.call("POST", "/api/devices/0/system", {})
        self.assert_error(reply, 405, "E_CMD_UNKNOWN")
        self.assertEqual(reply.headers["Allow"], "GET")
        self.assert_error(self.get("/api/devices/2/system"), 404, "E_NOT_FOUND")


class LogRing(WebCase):
    def setUp(self):
        self.store = tempfile.mkdtemp(prefix="wsgsim-store-")
        self.addCleanup(shutil.rmtree, self.store)
        self.sim = WebSim("--script-dir", self.store, "--sim-port", "0")
        self.sim.start()
        self.addCleanup(self.sim.stop)

    def test_the_last_hundred_lines_are_kept(self):
        api = self.sim.base + "/api/devices/0"
        with self.sim.control() as ctl:  # LOG(text): one log line each, not rate-limited
            for i in range(1, 151):
                self.assertEqual(ctl('LOG("line %d")' % i), "ACK LOG")
            system = request(api + "/system").json()
            old = request(api + "/system?since=0").json()["log"]
        self.assertTrue(system["script_store"])
        log = system["log"]
        self.assertEqual(len(log["lines"]), LOG_KEPT)
        self.assertTrue(log["lines"][-1].endswith("control: line 150"), log["lines"][-1])
        self.assertTrue(log["lines"][0].endswith("control: line %d" % (150 - LOG_KEPT + 1)),
                        log["lines"][0])
        self.assertEqual(old["lines"], log["lines"])  # the lines before are gone

    def test_a_long_line_is_cut_between_characters(self):
        """A line cut to 255 bytes stays UTF-8 (the reply is JSON): with and
        without one byte more before them, one of the two lines of 2-byte
        characters would be cut inside a character. (A script's error line
        is logged as it is; its print lines are escaped to ASCII.)"""
        api = self.sim.base + "/api/devices/0"
        lines = []
        for name, text in (("wide.lua", "\u00e9"), ("wider.lua", "x\u00e9")):
            with open(os.path.join(self.store, name), "w", encoding="utf-8") as f:
                f.write("error('%s' .. string.rep('\u00e9', 200), 0)\n" % text)
            self.assertEqual(request(api + "/script/run", "POST", {"file": name}).status, 200)
            wait_for("the script's end", lambda: not request(api + "/script").json()["running"],
                     MOTION_TIMEOUT)
            lines += request(api + "/system").json()["log"]["lines"][-1:]  # decoded strictly
        for line, start in zip(lines, ("script error: \u00e9", "script error: x\u00e9")):
            self.assertIn(start, line)
            self.assertLessEqual(len(line.encode()), 255)
            self.assertGreaterEqual(len(line.encode()), 254)
            self.assertTrue(line.endswith("\u00e9"), line[-5:])
