# SPDX-License-Identifier: BSD-3-Clause
"""Operations and settings through the web interface, as a GCL client sees
them: the page is a third front end of the device, not a GCL client."""
import os
import sys
import tempfile
import unittest

from test_api import WebCase
from webclient import GclError, WebSim, request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402


def paused_case_args():
    return ("--start-paused", "--sim-port", "0", "--no-disconnect-faststop")


class Operations(WebCase):
    ARGS = paused_case_args()

    def op(self, name, body=None, device=0):
        return self.call("POST", "/api/devices/%d/ops/%s" % (device, name), body or {})

    def state(self):
        return self.get("/api/devices/0/state").json()

    def home(self, ctl):
        self.assertEqual(self.op("home").status, 202)
        ctl.step(3000)
        self.assertEqual(self.state()["web_op"]["status"], "E_SUCCESS")

    def test_long_op_is_202_and_its_end_shows_in_the_state(self):
        with self.sim.control() as ctl:
            reply = self.op("home", {"direction": "default"})
            self.assertEqual(reply.status, 202)
            self.assertEqual(reply.json(), {"status": "E_SUCCESS", "code": 0, "started": True})
            s = self.state()
            self.assertEqual((s["motion"], s["web_op"]["op"], s["web_op"]["done"]),
                             ("home", "home", False))
            ctl.step(3000)
            s = self.state()
            self.assertEqual(s["motion"], "none")
            self.assertTrue(s["referenced"])
            self.assertEqual((s["web_op"]["done"], s["web_op"]["status"], s["web_op"]["code"]),
                             (True, "E_SUCCESS", 0))
            self.assertGreater(s["web_op"]["ended_ms"], s["web_op"]["started_ms"])

    def test_move_on_the_page_is_the_width_a_gcl_client_reads(self):
        with self.sim.control() as ctl, self.sim.tcp() as gcl:
            self.home(ctl)
            self.assertEqual(self.op("move", {"position_mm": 20, "speed_mm_s": 50}).status, 202)
            ctl.step(2000)
            gcl.expect("POS?", "POS=20.0")
            self.assertEqual(self.state()["position_mm"], 20)

    def test_grip_on_the_page_holds_for_gcl(self):
        with self.sim.control() as ctl, self.sim.tcp() as gcl:
            self.home(ctl)
            self.assertEqual(ctl("PART(40,100)"), "ACK PART")
            self.assertEqual(self.op("grip", {"force_n": 20, "width_mm": 40}).status, 202)
            ctl.step(3000)
            gcl.expect("GRIPSTATE?", "GRIPSTATE=4")
            s = self.state()
            self.assertEqual(s["grip_state"], {"code": 4, "name": "HOLDING"})
            self.assertEqual(s["part"]["width_mm"], 40)
            self.assertEqual(self.op("release", {"distance_mm": 5}).status, 202)
            ctl.step(2000)
            gcl.expect("GRIPSTATE?", "GRIPSTATE=0")

    def test_a_gcl_move_ends_the_page_move_and_the_page_hears_it(self):
        with self.sim.control() as ctl, self.sim.tcp() as gcl:
            self.home(ctl)
            self.assertEqual(self.op("move", {"position_mm": 10, "speed_mm_s": 10}).status, 202)
            ctl.step(100)
            self.assertEqual(gcl.command("MOVE(80)"), "ACK MOVE")
            s = self.state()["web_op"]
            self.assertEqual((s["op"], s["done"], s["status"]), ("move", True, "E_CMD_ABORTED"))
            ctl.step_until(gcl, "FIN MOVE")

    def test_a_reset_forgets_the_page_operation(self):
        with self.sim.control() as ctl:
            self.assertEqual(self.op("home").status, 202)
            self.assertFalse(self.state()["web_op"]["done"])
            self.assertEqual(ctl("RESET()"), "ACK RESET")
            s = self.state()
            self.assertEqual((s["web_op"], s["motion"]), (None, "none"))

    def test_immediate_ops_are_200(self):
        with self.sim.control() as ctl:
            self.home(ctl)
            self.assertEqual(self.op("move", {"position_mm": 30}).status, 202)
            self.assertEqual(self.op("stop").json(), {"status": "E_SUCCESS", "code": 0})
            ctl.step(10)  # the abort reaches its owner at the next control step
            self.assertEqual(self.state()["web_op"]["status"], "E_CMD_ABORTED")
            self.assertEqual(self.op("fast_stop").status, 200)
            self.assertIn("SF_FAST_STOP", self.state()["sysflags"]["set"])
            refused = self.op("move", {"position_mm": 30})
            self.assertEqual((refused.status, refused.json()["error"]), (422, "E_ACCESS_DENIED"))
            self.assertEqual(self.op("fsack").status, 200)
            self.assertNotIn("SF_FAST_STOP", self.state()["sysflags"]["set"])
            ctl.step(1000)  # the finger bus settles
            self.assertEqual(self.op("tare", {"finger": 0}).status, 200)
            self.assertEqual(self.op("tare").status, 200)

    def test_a_refusal_leaves_the_command_failure_flag_to_gcl(self):
        with self.sim.tcp() as gcl:
            self.assertEqual(self.op("move", {"position_mm": 30}).status, 422)  # not homed
            self.assertNotIn("SF_CMD_FAILURE", self.state()["sysflags"]["set"])
            gcl.expect("POS?", "POS=55.0")


class Settings(WebCase):
    ARGS = ("--no-disconnect-faststop",)

    def settings(self):
        return self.get("/api/devices/0/settings").json()

    def put(self, body):
        return self.call("PUT", "/api/devices/0/settings", body)

    def test_get_has_every_field(self):
        s = self.settings()
        self.assertEqual(set(s), {
            "protocol", "tcp_port", "udp_port", "binary_udp_port", "binary_crc_check",
            "faststop_on_disconnect", "pwt_mm", "clt_mm", "pullback_mm", "force_n",
            "speed_mm_s", "accel_mm_s2", "soft_limits", "soft_limit_minus_mm",
            "soft_limit_plus_mm", "overdrive", "tag", "config_file", "save_file"})
        self.assertEqual((s["protocol"], s["tcp_port"], s["config_file"], s["save_file"]),
                         ("auto", self.sim.tcp_port, None, None))
        self.assertFalse(s["faststop_on_disconnect"])
        self.assertEqual((s["pwt_mm"], s["clt_mm"], s["pullback_mm"]), (10, 10, 10))

    def test_put_applies_at_once_and_a_new_gcl_connection_reads_it(self):
        reply = self.put({"pwt_mm": 3.5, "clt_mm": 2, "force_n": 30, "speed_mm_s": 50,
                          "tag": "cell-7"})
        self.assertEqual(reply.status, 200, reply)
        self.assertEqual((reply.json()["pwt_mm"], reply.json()["tag"]), (3.5, "cell-7"))
        with self.sim.tcp() as gcl:
            gcl.expect("PWT?", "PWT=3.5")
            gcl.expect("CLT?", "CLT=2.0")
        self.assertEqual(self.get("/api/devices").json()["devices"][0]["tag"], "cell-7")

    def test_all_or_nothing(self):
        before = self.settings()
        j = self.put({"pwt_mm": 5, "tag": "x", "soft_limits": True, "clt_mm": 500}).json()
        self.assertEqual((j["error"], j["code"]), ("E_RANGE_ERROR", 28))
        self.assertIn("clt_mm", j["message"])
        self.assertEqual(self.settings(), before)
        j = self.put({"pullback_mm": 111}).json()  # within the stroke, as the file checks it
        self.assertEqual((j["error"], j["message"].split(":")[0]), ("E_RANGE_ERROR", "pullback_mm"))
        j = self.put({"pwt_mm": 5, "tag": "y" * 60}).json()
        self.assertEqual(j["error"], "E_RANGE_ERROR")
        self.assertIn("tag", j["message"])
        self.assertEqual(self.settings(), before)
        with self.sim.tcp() as gcl:
            gcl.expect("PWT?", "PWT=10.0")

    def test_a_tag_that_could_forge_a_reply_is_refused(self):
        """The core's one rule: CR, LF, '"' or a byte beyond ASCII
        (invalid UTF-8 too) is 422 E_INVALID_PARAMETER naming the tag, and
        nothing changes; a GCL client's TAG? reads the old tag."""
        self.assertEqual(self.put({"tag": "cell-7"}).status, 200)
        before = self.settings()
        for tag in ("a\nFIN HOME", "a\rFIN HOME", 'a" FIN', "caf\u00e9"):
            reply = self.put({"tag": tag, "pwt_mm": 5})
            self.assert_error(reply, 422, "E_INVALID_PARAMETER")
            self.assertIn("tag", reply.json()["message"])
        raw = b'{"tag": "bad \xff\xfe utf-8", "pwt_mm": 5}'
        self.assert_error(self.call("PUT", "/api/devices/0/settings", raw=raw), 422,
                          "E_INVALID_PARAMETER")
        self.assertEqual(self.settings(), before)
        with self.sim.tcp() as gcl:
            gcl.expect("TAG?", 'TAG="cell-7"')
            gcl.expect("PWT?", "PWT=10.0")

    def test_soft_limits_move_past_each_other(self):
        self.assertEqual(self.put({"soft_limit_minus_mm": 5, "soft_limit_plus_mm": 8}).status,
                         200)
        reply = self.put({"soft_limit_minus_mm": 60, "soft_limit_plus_mm": 100,
                          "soft_limits": True})
        self.assertEqual(reply.status, 200, reply)
        s = reply.json()
        self.assertEqual((s["soft_limit_minus_mm"], s["soft_limit_plus_mm"], s["soft_limits"]),
                         (60, 100, True))
        before = self.settings()
        bad = self.put({"soft_limit_minus_mm": 10, "soft_limit_plus_mm": 5})
        self.assertEqual(bad.json()["error"], "E_RANGE_ERROR")
        self.assertEqual(self.settings(), before)

    def test_fixed_fields_may_be_repeated_not_changed(self):
        whole = self.settings()
        self.assertEqual(self.put(whole).status, 200)  # what GET gave, PUT back
        for field, value in (("tcp_port", whole["tcp_port"] + 1), ("protocol", "gcl"),
                             ("config_file", "/tmp/x.ini"), ("save_file", "/tmp/y.ini")):
            j = self.put({field: value}).json()
            self.assertEqual(j["error"], "E_ACCESS_DENIED")
            self.assertIn(field, j["message"])
        self.assertEqual(self.settings(), whole)

    def test_save_without_config_is_409(self):
        reply = self.call("POST", "/api/devices/0/settings/save", {})
        self.assertEqual((reply.status, reply.json()["error"]), (409, "E_NOT_AVAILABLE"))


class Save(unittest.TestCase):
    CONFIG = ("; the cell's gripper\n[device]\ntag = \"old\"\n\n[motion]\n"
              "; tolerance for the parts of line 3\npart_width_tolerance = 8\n")

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory(prefix="wsgsim-web-")
        self.addCleanup(self.dir.cleanup)
        self.path = os.path.join(self.dir.name, "gripper.ini")
        with open(self.path, "w") as f:
            f.write(self.CONFIG)

    def start(self):
        sim = WebSim("--config", self.path, "--no-disconnect-faststop")
        sim.start()
        self.addCleanup(sim.stop)
        return sim

    def test_motion_settings_another_model_refuses_are_not_saved(self):
        # Found by fuzzing (tests/fuzz/fuzz_config.c): the [motion] keys are
        # every device's, so device 0's defaults (force 40 N) written for a
        # fleet with a WSG 25-064 (5-20 N) made a file wsgsim refused.
        fleet = self.CONFIG + "\n[device.1]\nmodel = WSG 25-064\n"
        with open(self.path, "w") as f:
            f.write(fleet)
        sim = self.start()
        reply = request(sim.base + "/api/devices/0/settings/save", "POST", body={})
        self.assertEqual((reply.status, reply.json()["error"]), (422, "E_WRITE_ERROR"))
        self.assertIn("default_force: 40 is outside 5..20 for the WSG 25-064",
                      reply.json()["message"])
        sim.stop()
        with open(self.path) as f:
            self.assertEqual(f.read(), fleet)
        self.start()  # the file still starts the fleet

    def test_motion_settings_every_model_takes_are_saved_for_a_fleet(self):
        fleet = self.CONFIG + "\n[device.1]\nmodel = WSG 25-064\n"
        with open(self.path, "w") as f:
            f.write(fleet)
        sim = self.start()
        base = sim.base + "/api/devices/1/settings"
        self.assertEqual(request(base, "PUT", {"force_n": 15}).status, 200)
        self.assertEqual(request(base + "/save", "POST", body={}).status, 200)
        sim.stop()
        with open(self.path) as f:
            self.assertIn("default_force = 15\n", f.read())
        again = self.start()
        s = request(again.base + "/api/devices/0/settings").json()
        self.assertEqual(s["force_n"], 15)

    def test_saved_settings_are_what_a_new_process_starts_with(self):
        sim = self.start()
        base = sim.base + "/api/devices/0/settings"
        self.assertEqual(request(base).json()["pwt_mm"], 8)
        self.assertEqual(request(base).json()["config_file"], self.path)
        changed = request(base, "PUT", {"pwt_mm": 4.25, "pullback_mm": 7, "tag": "cell 7",
                                        "faststop_on_disconnect": False,
                                        "binary_crc_check": False})
        self.assertEqual(changed.status, 200, changed)
        saved = request(base + "/save", "POST", {})
        self.assertEqual(saved.status, 200, saved)
        self.assertTrue(saved.json()["saved"])
        sim.stop()
        with open(self.path) as f:
            text = f.read()
        self.assertIn("; the cell's gripper\n", text)  # comments stay
        self.assertIn("; tolerance for the parts of line 3\npart_width_tolerance = 4.25\n", text)
        self.assertIn('tag = "cell 7"', text)
        again = self.start()
        s = request(again.base + "/api/devices/0/settings").json()
        self.assertEqual((s["pwt_mm"], s["pullback_mm"], s["tag"], s["faststop_on_disconnect"],
                          s["binary_crc_check"]), (4.25, 7, "cell 7", False, False))
        with again.tcp() as gcl:
            gcl.expect("PWT?", "PWT=4.25")

    def test_a_tag_with_a_semicolon_is_read_back_as_saved(self):
        # any client may set the tag (binary 0x51 over the network): libinih
        # took " ;" in the saved value for a comment, and the next start
        # stopped on the file the Save had written
        sim = self.start()
        client = wb.BinTcp("127.0.0.1", sim.tcp_port)
        self.addCleanup(client.close)
        for tag in ("a ;b", "x ; y ;z", ";"):
            with self.subTest(tag):
                client.send_request(0x51, tag.encode())
                self.assertEqual(client.wait_for(0x51).status, 0)
                base = sim.base + "/api/devices/0/settings"
                self.assertEqual(request(base + "/save", "POST", body={}).status, 200)
                again = WebSim("--config", self.path, "--no-disconnect-faststop")
                again.start()
                tag_read = request(again.base + "/api/devices/0/settings").json()["tag"]
                again.stop()
                self.assertEqual(tag_read, tag)

    def test_a_reset_powers_on_with_the_saved_settings(self):
        sim = WebSim("--config", self.path, "--sim-port", "0")
        sim.start()
        self.addCleanup(sim.stop)
        base = sim.base + "/api/devices/0/settings"
        request(base, "PUT", {"clt_mm": 3})
        self.assertEqual(request(base + "/save", "POST", body={}).status, 200)
        request(base, "PUT", {"clt_mm": 6})  # not saved: a reset forgets it
        with sim.control() as ctl:
            self.assertEqual(ctl("RESET()"), "ACK RESET")
        self.assertEqual(request(base).json()["clt_mm"], 3)

    def test_another_device_saves_its_tag_in_its_section(self):
        sim = WebSim("--config", self.path, "--devices", "2")
        sim.start()
        self.addCleanup(sim.stop)
        base = sim.base + "/api/devices/1/settings"
        self.assertEqual(request(base).json()["tag"], "old-1")
        self.assertEqual(request(base, "PUT", {"tag": "left hand"}).status, 200)
        self.assertEqual(request(base + "/save", "POST", body={}).status, 200)
        sim.stop()
        with open(self.path) as f:
            self.assertTrue(f.read().endswith('\n[device.1]\ntag = "left hand"\n'))
        again = WebSim("--config", self.path, "--devices", "2")
        again.start()
        self.addCleanup(again.stop)
        tags = [d["tag"] for d in request(again.base + "/api/devices").json()["devices"]]
        self.assertEqual(tags, ["old", "left hand"])

    def test_a_tag_the_file_cannot_hold_never_reaches_it(self):
        """The device refuses such a tag (the file's rule is the core's), so
        a save after the refused PUT writes the tag in force."""
        sim = self.start()
        base = sim.base + "/api/devices/0/settings"
        self.assertEqual(request(base, "PUT", {"tag": 'say "hi"'}).status, 422)
        self.assertEqual(request(base + "/save", "POST", body={}).status, 200)
        with open(self.path) as f:
            self.assertIn('tag = "old"', f.read())


class SaveFile(unittest.TestCase):
    """--save-file: Save writes it, not the --config file, and a new process
    reads it over the configuration (docs/web.md, "Where Save writes")."""
    CONFIG = '[device]\ntag = "config"\n[motion]\npart_width_tolerance = 8\nclamping_travel = 6\n'

    def setUp(self):
        self.dir = tempfile.TemporaryDirectory(prefix="wsgsim-web-")
        self.addCleanup(self.dir.cleanup)
        self.config = os.path.join(self.dir.name, "gripper.ini")
        self.saved = os.path.join(self.dir.name, "state", "saved.ini")
        with open(self.config, "w") as f:
            f.write(self.CONFIG)

    def start(self, *args):
        sim = WebSim(*args)
        sim.start()
        self.addCleanup(sim.stop)
        return sim, sim.base + "/api/devices/0/settings"

    def save(self, base, change):
        self.assertEqual(request(base, "PUT", change).status, 200)
        return request(base + "/save", "POST", {})

    def test_save_writes_the_save_file_and_a_restart_reads_it_over_the_config(self):
        os.mkdir(os.path.dirname(self.saved))
        sim, base = self.start("--config", self.config, "--save-file", self.saved)
        self.assertEqual((request(base).json()["config_file"], request(base).json()["save_file"]),
                         (self.config, self.saved))
        reply = self.save(base, {"pwt_mm": 4.5, "tag": "saved"})
        self.assertEqual(reply.status, 200, reply)
        self.assertEqual(reply.json()["save_file"], self.saved)
        reply = self.save(base, {"pwt_mm": 5.5})  # a second Save rewrites it in place
        self.assertEqual(reply.status, 200, reply)
        sim.stop()
        with open(self.config) as f:
            self.assertEqual(f.read(), self.CONFIG, "the configuration is not written")
        with open(self.saved) as f:
            text = f.read()
        self.assertTrue(text.startswith("# The settings the wsgsim web page saved"), text)
        self.assertEqual(text.count("part_width_tolerance = "), 1, text)
        self.assertIn("part_width_tolerance = 5.5\n", text)
        self.assertEqual(os.listdir(os.path.dirname(self.saved)), ["saved.ini"])
        _, base = self.start("--config", self.config, "--save-file", self.saved)
        s = request(base).json()
        self.assertEqual((s["pwt_mm"], s["clt_mm"], s["tag"]), (5.5, 6, "saved"))
        _, base = self.start("--config", self.config)  # the configuration alone
        s = request(base).json()
        self.assertEqual((s["pwt_mm"], s["tag"]), (8, "config"))

    def test_save_file_without_config(self):
        os.mkdir(os.path.dirname(self.saved))
        sim, base = self.start("--save-file", self.saved)
        self.assertEqual(self.save(base, {"clt_mm": 2.5}).status, 200)
        sim.stop()
        _, base = self.start("--save-file", self.saved)
        self.assertEqual(request(base).json()["clt_mm"], 2.5)

    def test_save_file_that_cannot_be_written_is_422_and_nothing_changes(self):
        _, base = self.start("--config", self.config, "--save-file", self.saved)  # no state/
        reply = self.save(base, {"pwt_mm": 4.5})
        self.assertEqual((reply.status, reply.json()["error"]), (422, "E_WRITE_ERROR"))
        self.assertIn("cannot write %s: No such file or directory" % self.saved,
                      reply.json()["message"])
        self.assertEqual(os.listdir(self.dir.name), ["gripper.ini"])

    def test_bad_save_file_stops_the_start_naming_file_and_line(self):
        os.mkdir(os.path.dirname(self.saved))
        with open(self.saved, "w") as f:
            f.write("[motion]\ndefault_speed = fast\n")
        sim = WebSim("--config", self.config, "--save-file", self.saved)
        with self.assertRaises(GclError):
            sim.start()
        self.assertIn("wsgsim: %s:2: [motion] default_speed: expected a number" % self.saved,
                      "".join(sim.log))
        self.assertEqual(sim.returncode, 2)


if __name__ == "__main__":
    unittest.main()
