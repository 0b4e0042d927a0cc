# SPDX-License-Identifier: BSD-3-Clause
"""User scripts on the gripper (docs/scripting.md) end to end: the custom
command channel in the UMI and wsg50-ros-pkg dialects (wsgsim's own test
scripts in tests/e2e/scripts/), flags and life cycle, error paths, options.
Everything runs on a paused simulated clock advanced with STEP; a request
that must stay unanswered is checked by a built-in query sent after it on
the same connection, whose reply comes after any reply to the request."""
import json
import os
import shutil
import socket
import struct
import subprocess
import sys
import tempfile
import unittest

from gclclient import Wsgsim

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = os.path.join(HERE, "scripts")
E_SUCCESS, E_CMD_UNKNOWN, E_CMD_PENDING, E_OVERRUN = 0, 14, 26, 27
SF_BLOCKED_MINUS = 1 << 2
SF_SCRIPT_RUNNING, SF_SCRIPT_FAILURE = 1 << 19, 1 << 20
STEP_MS = 50


def free_udp_port():
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def umi_pd(target, speed=0.0, kp=15.0, kd=0.001, travel=80.0, blocked=None):
    return struct.pack("<Bffffff", 0, target, speed, kp, kd, travel,
                       travel if blocked is None else blocked)


def ros_goal(width=0.0, speed=0.0):
    return struct.pack("<Bff", 0, width, speed)


class ScriptCase(unittest.TestCase):
    def start(self, *args, script=None, store=None):
        extra = ["--script", os.path.join(SCRIPTS, script)] if script else []
        if store:
            extra += ["--script-dir", store]
        self.bin_udp_port = free_udp_port()
        self.sim = Wsgsim("--sim-port", "0", "--start-paused", "--binary-udp-port",
                          str(self.bin_udp_port), "--binary-udp-reply-port", "0", *extra, *args)
        self.sim.start()
        self.addCleanup(self.sim.stop)
        self.ctl = self.sim.control()
        self.addCleanup(self.ctl.close)

    def store(self, **files):
        """A script store with these files (name_lua=text -> name.lua)."""
        path = tempfile.mkdtemp(prefix="wsgsim-scripts-")
        self.addCleanup(shutil.rmtree, path)
        for name, text in files.items():
            with open(os.path.join(path, name.replace("_lua", ".lua")), "w") as f:
                f.write(text)
        return path

    def binary(self):
        client = wb.BinTcp("127.0.0.1", self.sim.tcp_port, timeout=30.0)
        self.addCleanup(client.close)
        return client

    def reply(self, client, frame_id, payload=b"", status=E_SUCCESS):
        client.send_request(frame_id, payload)
        frame = client.wait_for(frame_id)
        self.assertEqual(frame.status, status, wb.describe(frame))
        return frame

    def no_reply(self, client, frame_id):
        """No frame with frame_id came before the reply to a 0x43 sent now."""
        client.send_request(0x43, b"\x00\x00\x00")
        frame = client.wait_for(0x43, on_other=lambda f: self.assertNotEqual(
            f.id, frame_id, "unexpected reply %s" % wb.describe(f)))
        self.assertEqual(frame.status, E_SUCCESS)

    def home(self, client):
        self.reply(client, 0x20, b"\x01", E_CMD_PENDING)
        for _ in range(200):
            self.ctl.step(STEP_MS)
            frame = client.read_frame(0.05)
            if frame is not None and frame.id == 0x20:
                self.assertEqual(frame.status, E_SUCCESS)
                return
        self.fail("homing did not end")

    def flags(self, client):
        return struct.unpack("<I", self.reply(client, 0x40, b"\x00\x00\x00").values)[0]

    def width(self, client):
        return struct.unpack("<f", self.reply(client, 0x43, b"\x00\x00\x00").values)[0]

    def script_state(self):
        return self.ctl.json("SCRIPT?")


class UmiDialect(ScriptCase):
    def setUp(self):
        self.start(script="umi_dialect.lua")
        self.client = self.binary()
        self.reply(self.client, 0x24, b"ack")
        self.home(self.client)
        self.ctl.step(100)  # the script polls cmd.online() every 100 ms

    def query(self):
        frame = self.reply(self.client, 0xB0, b"\x00")
        self.assertEqual(len(frame.values), 17, wb.describe(frame))
        return struct.unpack("<Bffff", frame.values)

    def test_query_reports_as_binary_and_gcl_do(self):
        state, position, speed, force, seconds = self.query()
        self.assertEqual(position, self.width(self.client))
        flags = self.flags(self.client)
        self.assertEqual(state, flags & 0xFF)
        self.assertTrue(flags & SF_SCRIPT_RUNNING)
        self.assertEqual(speed, 0.0)
        sim_ms = json.loads(self.ctl("SIMTIME?").split("=")[1])[0]
        self.assertAlmostEqual(seconds, sim_ms / 1000.0, places=3)
        gcl = self.sim.tcp()
        self.addCleanup(gcl.close)
        self.assertEqual(gcl.query_float("POS"), round(position, 1))
        bits = json.loads(gcl.command("SYSFLAGS?").split("=")[1])
        self.assertEqual(bits[19], 1)  # SF_SCRIPT_RUNNING

    def test_pd_steps_converge_on_the_target(self):
        for _ in range(100):
            self.reply(self.client, 0xB1, umi_pd(50.0))
            self.ctl.step(33)
        state, position, speed, force, _ = self.query()
        self.assertAlmostEqual(position, 50.0, delta=0.2)
        self.assertAlmostEqual(self.width(self.client), position, delta=1e-4)
        self.assertLess(abs(speed), 1.0)

    def test_a_part_blocks_with_the_blocked_force_limit(self):
        self.ctl("PART(30,20)")
        for _ in range(60):
            self.reply(self.client, 0xB1, umi_pd(10.0, travel=80.0, blocked=20.0))
            self.ctl.step(33)
        state, position, speed, force, _ = self.query()
        self.assertAlmostEqual(force, 20.0, delta=0.01)
        self.assertGreater(position, 28.0)
        self.assertTrue(self.flags(self.client) & SF_BLOCKED_MINUS)
        limit = struct.unpack("<f", self.reply(self.client, 0x33).values)[0]
        self.assertEqual(limit, 20.0)

    def test_coverage_counts_the_custom_ids(self):
        self.query()
        report = self.ctl.json("COVERAGE?")
        custom = [item["id"] for item in report["binary"]["custom_ids_answered"]]
        self.assertIn("0xB0", custom)


class UmiStart(ScriptCase):
    def test_requests_wait_while_the_script_sleeps(self):
        """Without a host the script polls every 100 ms: on a paused clock a
        request is answered once STEP reaches its wake-up (script time is
        simulated time)."""
        self.start(script="umi_dialect.lua")
        client = self.binary()
        client.send_request(0xB0, b"\x00")
        self.no_reply(client, 0xB0)
        self.ctl.step(100)
        self.assertEqual(client.wait_for(0xB0).status, E_SUCCESS)


class RosDialect(ScriptCase):
    def start_ros(self, fingers):
        self.start("--fingers", fingers, script="ros_dialect.lua")
        self.client = self.binary()
        self.home(self.client)
        self.ctl.step(100)

    def measure(self, frame_id=0xB0, payload=None):
        frame = self.reply(self.client, frame_id, payload or ros_goal())
        self.assertEqual(len(frame.raw), 6 + 23 + 2)
        return struct.unpack("<Bfffff", frame.values)

    def test_two_fmf_fingers_answer_23_bytes(self):
        self.start_ros("fmf,fmf")
        state, position, speed, force, f0, f1 = self.measure()
        self.assertEqual(position, self.width(self.client))
        for force in (f0, f1):  # an FMF's reading near zero, never NaN
            self.assertLess(abs(force), 5.0)
        self.assertIn("#FMF fingers: 2", self.sim.drain_log())

    def test_position_goal_moves_without_waiting(self):
        self.start_ros("fmf,fmf")
        self.measure(0xB1, ros_goal(40.0, 100.0))
        self.assertEqual(self.ctl.run_until_done()[1], "done")
        self.assertAlmostEqual(self.width(self.client), 40.0, delta=0.05)

    def test_speed_goal_closes_until_blocked_then_stops(self):
        self.start_ros("fmf,fmf")
        self.ctl("PART(30,50)")
        self.measure(0xB2, ros_goal(0.0, -50.0))
        for _ in range(40):
            self.ctl.step(STEP_MS)
            self.measure()  # each request lets the script check for a block
        state, position, speed, force, f0, f1 = self.measure()
        self.assertGreater(position, 28.0)
        self.assertLess(position, 30.0)
        self.assertEqual(speed, 0.0)
        self.assertFalse(state & 0x02)  # not moving

    def speed_after_goals(self, gap_ms):
        """Position goal 30 mm from 20 mm, then +40 mm/s gap_ms later: the
        jaws' speed measured from positions 200 ms on, over 1 s."""
        self.measure(0xB1, ros_goal(20.0, 100.0))
        self.assertEqual(self.ctl.run_until_done()[1], "done")
        self.measure(0xB1, ros_goal(30.0, 100.0))
        if gap_ms:
            self.ctl.step(gap_ms)
        self.measure(0xB2, ros_goal(0.0, 40.0))
        self.ctl.step(200)
        before = self.width(self.client)
        self.ctl.step(1000)
        return self.width(self.client) - before

    def test_a_speed_goal_as_a_position_goal_arrives_drives_the_jaws(self):
        """wsg50-ros-pkg's node sends a speed goal once, on the tick after a
        position goal, the move still running; its script calls mc.speed
        without stopping: velocity mode takes the move over."""
        self.start_ros("fmf,fmf")
        self.assertAlmostEqual(self.speed_after_goals(0), 40.0, delta=0.1)

    def test_a_speed_goal_during_the_move_drives_the_jaws(self):
        self.start_ros("fmf,fmf")
        self.assertAlmostEqual(self.speed_after_goals(100), 40.0, delta=0.1)

    def test_a_gcl_move_taken_over_by_the_script_ends_aborted(self):
        """Velocity mode ends whoever's MOVE runs, as a superseding MOVE does:
        the GCL client hears ERR MOVE 19 and never FIN MOVE."""
        self.start_ros("fmf,fmf")
        gcl = self.sim.tcp()
        self.addCleanup(gcl.close)
        gcl.expect("MOVE(60)", "ACK MOVE")
        self.ctl.step(100)
        self.measure(0xB2, ros_goal(0.0, -40.0))
        self.assertEqual(gcl.read_line(), "ERR MOVE 19")
        self.ctl.step(500)
        self.assertEqual(gcl.query_float("SPEED"), 40.0)

    def test_other_fingers_leave_every_request_unanswered(self):
        self.start_ros("fmf,dsa")
        self.client.send_request(0xB0, ros_goal())
        self.ctl.step(500)
        self.no_reply(self.client, 0xB0)
        flags = self.flags(self.client)
        self.assertTrue(flags & SF_SCRIPT_RUNNING)
        self.assertFalse(flags & SF_SCRIPT_FAILURE)
        log = self.sim.drain_log()
        self.assertIn("#FMF fingers: 1", log)
        self.assertIn("bad argument #1 to 'ntob' (number expected, got nil)", log)


ECHO = """
cmd.register(0xB5)
while true do
    local id, payload = cmd.read()
    cmd.send(id, etob(E_SUCCESS), #payload, payload, "ok", true, {{1, {2}}, 3}, false)
end
"""

SILENT = """
cmd.register(0xB0)
sleep(1e9)
"""


class Channel(ScriptCase):
    def test_send_emits_exactly_the_flattened_bytes(self):
        self.start(store=self.store(echo_lua=ECHO), script=None)
        self.assertEqual(self.ctl("SCRIPT_RUN(\"echo.lua\")"), "ACK SCRIPT_RUN")
        client = self.binary()
        frame = self.reply(client, 0xB5, b"\x07\x08")
        self.assertEqual(frame.raw, wb.encode_frame(0xB5, b"\x00\x00\x02\x07\x08ok\x01\x01\x02\x03\x00"))

    def test_udp_requests_reach_the_script(self):
        self.start(store=self.store(echo_lua=ECHO))
        self.ctl("SCRIPT_RUN(\"/user/echo.lua\")")
        client = wb.BinUdp("127.0.0.1", self.bin_udp_port, reply_port=0, timeout=30.0,
                           bind_host="127.0.0.1")
        self.addCleanup(client.close)
        client.send_request(0xB5, b"\x01")
        self.assertEqual(client.wait_for(0xB5).values, b"\x01\x01ok\x01\x01\x02\x03\x00")

    def test_unregistered_ids_stay_unknown(self):
        self.start(store=self.store(echo_lua=ECHO))
        client = self.binary()
        self.reply(client, 0xB5, b"", E_CMD_UNKNOWN)
        self.ctl("SCRIPT_RUN(\"echo.lua\")")
        self.reply(client, 0xB6, b"", E_CMD_UNKNOWN)
        self.reply(client, 0xB5, b"")
        self.ctl("SCRIPT_STOP()")
        self.reply(client, 0xB5, b"", E_CMD_UNKNOWN)
        self.assertEqual(self.script_state()["registered"], [])

    def test_a_full_queue_answers_overrun(self):
        self.start(store=self.store(silent_lua=SILENT))
        self.ctl('SCRIPT_RUN("silent.lua")')
        client = self.binary()
        for _ in range(16):
            client.send_request(0xB0)
        self.reply(client, 0xB0, b"", E_OVERRUN)
        self.assertEqual(self.script_state()["queued"], 16)

    def test_each_device_of_a_fleet_has_its_own_script(self):
        self.start("--devices", "2", store=self.store(echo_lua=ECHO))
        self.ctl("DEVICE=1")
        self.ctl("SCRIPT_RUN(\"echo.lua\")")
        self.assertEqual(self.script_state()["registered"], [0xB5])
        self.ctl("DEVICE=0")
        self.assertEqual(self.script_state()["registered"], [])
        self.assertFalse(self.script_state()["running"])


EXTREMES = """
cmd.register(0xB7)
cmd.read()
local fraction = pcall(cmd.send, 0xB7, 1.5)
local too_big = pcall(cmd.send, 0xB7, 256)
local no_number = pcall(ntob)
local builtin = pcall(cmd.register, 0x21)
cmd.send(0xB7, ntob(1e300), ntob(-1e300), fraction, too_big, no_number, builtin,
         etob(mc.move(1e300, 1e300)), etob(mc.speed(-1e300)))
sleep(math.huge)
"""


class Bindings(ScriptCase):
    def test_bad_arguments_raise_and_extreme_numbers_are_clamped(self):
        self.start(store=self.store(extremes_lua=EXTREMES))
        self.ctl('SCRIPT_RUN("extremes.lua")')
        client = self.binary()
        frame = self.reply(client, 0xB7, b"")
        # +inf, -inf, four refused calls; mc.move(inf) is E_INVALID_PARAMETER as 0x21 with
        # an infinite width is; mc.speed(-inf) is clamped and meets the unhomed device
        self.assertEqual(frame.raw[6:-2], bytes.fromhex("0000807f 000080ff 00000000 1800 0300"))
        self.ctl.step(1000)  # sleep(math.huge) never ends, the device serves on
        state = self.script_state()
        self.assertTrue(state["running"])
        self.assertEqual(self.flags(client) & SF_SCRIPT_FAILURE, 0)


class LifeCycle(ScriptCase):
    def test_a_syntax_error_starts_the_device_with_the_failure_flag(self):
        store = self.store(bad_lua="cmd.register(0xB0)\nlocal x = = 1\n")
        self.start(store=store, script=None)
        self.ctl('SCRIPT_RUN("bad.lua")')
        state = self.script_state()
        self.assertFalse(state["running"])
        self.assertTrue(state["failure"])
        self.assertTrue(state["error"].startswith("bad.lua:2:"), state["error"])
        client = self.binary()
        flags = self.flags(client)
        self.assertTrue(flags & SF_SCRIPT_FAILURE)
        self.assertFalse(flags & SF_SCRIPT_RUNNING)
        self.reply(client, 0xB0, b"", E_CMD_UNKNOWN)

    def test_startup_script_that_does_not_compile(self):
        store = self.store(bad_lua="this is not lua\n")
        self.start("--script", os.path.join(store, "bad.lua"))
        state = json.loads(self.ctl("STATE?").split("=", 1)[1])["script"]
        self.assertTrue(state["failure"])
        self.assertIn("script error: bad.lua:1:", self.sim.drain_log())

    def test_a_runtime_error_releases_the_ids_and_stops_velocity_mode(self):
        store = self.store(crash_lua="""
cmd.register(0xB0)
mc.speed(-20)
sleep(100)
error("gave up")
""")
        self.start(store=store)
        client = self.binary()
        self.home(client)
        self.ctl('SCRIPT_RUN("crash.lua")')
        self.ctl.step(50)
        self.assertTrue(self.flags(client) & 0x02)  # moving in velocity mode
        self.ctl.step(100)
        state = self.script_state()
        self.assertEqual(state["error"], "crash.lua:5: gave up")
        self.assertEqual(state["registered"], [])
        self.ctl.step(200)
        self.assertFalse(self.flags(client) & 0x02)
        self.reply(client, 0xB0, b"", E_CMD_UNKNOWN)

    def test_an_endless_loop_leaves_the_device_serving(self):
        store = self.store(loop_lua="cmd.register(0xB0)\nlocal n = 0\nwhile true do n = n + 1 end\n")
        self.start(store=store)
        self.ctl('SCRIPT_RUN("loop.lua")')
        gcl = self.sim.tcp()
        self.addCleanup(gcl.close)
        for _ in range(3):
            self.assertTrue(gcl.command("POS?").startswith("POS="))
            self.ctl.step(10)
        self.assertTrue(self.script_state()["running"])
        self.assertEqual(self.ctl("SCRIPT_STOP()"), "ACK SCRIPT_STOP")
        state = self.script_state()
        self.assertFalse(state["running"])
        self.assertFalse(state["failure"])  # stopped by the user, not failed

    def test_memory_is_capped(self):
        store = self.store(hog_lua="local t = {}\nwhile true do t[#t + 1] = {} end\n")
        self.start(store=store)
        self.ctl('SCRIPT_RUN("hog.lua")')
        client = self.binary()
        for _ in range(600):
            state = self.script_state()
            if not state["running"]:
                break
            self.flags(client)  # the loop runs a slice per pass
        self.assertTrue(state["failure"])
        self.assertIn("not enough memory", state["error"])

    def test_reset_runs_the_startup_script_again(self):
        self.start(script="umi_dialect.lua")
        self.ctl("SCRIPT_STOP()")
        self.assertFalse(self.script_state()["running"])
        self.ctl("RESET()")
        state = self.script_state()
        self.assertTrue(state["running"])
        self.assertEqual(state["registered"], [0xB0, 0xB1])

    def test_config_file_startup_and_per_device_scripts(self):
        store = self.store(echo_lua=ECHO, silent_lua=SILENT)
        config = os.path.join(store, "wsgsim.ini")
        with open(config, "w") as f:
            f.write("[script]\ndir = %s\nstartup = /user/echo.lua\n\n"
                    "[device.1]\nscript = /user/silent.lua\n" % store)
        self.start("--config", config, "--devices", "2")
        self.assertEqual(self.script_state()["registered"], [0xB5])
        self.ctl("DEVICE=1")
        self.assertEqual(self.script_state()["registered"], [0xB0])

    def test_no_autostart_keeps_the_script_selected_but_idle(self):
        self.start("--no-script-autostart", script="umi_dialect.lua")
        self.assertFalse(self.script_state()["running"])
        client = self.binary()
        self.reply(client, 0xB0, b"\x00", E_CMD_UNKNOWN)
        self.assertFalse(self.flags(client) & SF_SCRIPT_RUNNING)

    def test_a_missing_startup_file_is_a_start_error(self):
        binary = os.environ.get("WSGSIM", os.path.join(HERE, "..", "..", "build", "wsgsim"))
        result = subprocess.run([binary, "--script", "/nonexistent/cmd_measure.lua"],
                                capture_output=True, text=True, timeout=60)
        self.assertEqual(result.returncode, 2)
        self.assertEqual(result.stderr.count("\n"), 1, result.stderr)
        self.assertTrue(result.stderr.startswith("wsgsim: --script /nonexistent/cmd_measure.lua"))


class HostFiles(ScriptCase):
    """What the control channel runs from the host: any path the line holds,
    never blocking on what is not a regular file."""

    def host_dir(self, name="wsgsim-host-"):
        path = tempfile.mkdtemp(prefix=name)
        self.addCleanup(shutil.rmtree, path)
        return path

    def test_script_run_takes_a_host_path_of_100_characters(self):
        top = self.host_dir()
        folder = os.path.join(top, "d" * max(1, 100 - len(top) - len("/echo.lua") - 1))
        os.mkdir(folder)
        path = os.path.join(folder, "echo.lua")
        self.assertGreaterEqual(len(path), 100)
        with open(path, "w") as f:
            f.write(ECHO)
        self.start()
        self.assertEqual(self.ctl('SCRIPT_RUN("%s")' % path), "ACK SCRIPT_RUN")
        state = self.script_state()
        self.assertEqual((state["file"], state["running"], state["registered"]),
                         (path, True, [0xB5]))
        reply = self.ctl('SCRIPT_RUN("%s")' % (path + "x"))
        self.assertTrue(reply.startswith("ERR SCRIPT_RUN 21 "), reply)

    def test_a_fifo_blocks_nothing(self):
        fifo = os.path.join(self.host_dir(), "pipe.lua")
        os.mkfifo(fifo)
        store = self.store(dofile_lua="local ok, err = pcall(dofile, 'pipe.lua')\nerror(err, 0)\n",
                           require_lua="require 'pipe'\n")
        os.mkfifo(os.path.join(store, "pipe.lua"))
        self.start(store=store)
        reply = self.ctl('SCRIPT_RUN("%s")' % fifo)
        self.assertTrue(reply.startswith("ERR SCRIPT_RUN 21 "), reply)
        self.assertIn("not a regular file", reply)
        for name in ("dofile.lua", "require.lua"):
            self.assertEqual(self.ctl('SCRIPT_RUN("%s")' % name), "ACK SCRIPT_RUN")
            state = self.script_state()
            self.assertTrue(state["failure"], name)
            self.assertIn("not a regular file", state["error"])
        self.assertEqual(self.ctl("SIMTIME?"), "SIMTIME=[0.000,0.000]")

    def test_no_library_function_opens_a_host_file(self):
        # package.searchpath fopen()ed any path: a FIFO's open waited for a
        # writer and held the whole process, which no watchdog on CPU time
        # ends; it also told which host files exist and can be read
        fifo = os.path.join(self.host_dir(), "pipe.lua")
        os.mkfifo(fifo)
        code = "print(package.searchpath == nil and 'no searchpath' or 'searchpath')\n" \
               "print(pcall(package.searchpath, 'x', %r))\n" % fifo
        self.start(store=self.store(probe_lua=code))
        self.addCleanup(self.release_reader, fifo)  # before the stop
        self.assertEqual(self.ctl('SCRIPT_RUN("probe.lua")'), "ACK SCRIPT_RUN")
        self.assertFalse(self.script_state()["running"])
        log = self.sim.drain_log()
        self.assertIn("script: no searchpath", log)
        self.assertIn("script: false\\x09", log)  # the call raised, nothing opened

    def release_reader(self, fifo):
        """A server blocked opening the FIFO for reading goes on once a writer opens it."""
        try:
            os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
        except OSError:
            pass  # no reader: nothing blocked

    def test_a_fleet_device_without_script_options_logs_as_its_index(self):
        path = os.path.join(self.host_dir(), "hello.lua")
        with open(path, "w") as f:
            f.write("print('hello from a fleet')\n")
        self.start("--devices", "2")
        self.assertEqual(self.ctl("DEVICE=1"), "DEVICE=1")
        self.assertEqual(self.ctl('SCRIPT_RUN("%s")' % path), "ACK SCRIPT_RUN")
        self.assertIn("script[1]: hello from a fleet", self.sim.drain_log())

    def test_a_startup_store_name_must_be_a_lua_file(self):
        store = self.store(echo_lua=ECHO)
        os.rename(os.path.join(store, "echo.lua"), os.path.join(store, "echo"))
        binary = os.environ.get("WSGSIM", os.path.join(HERE, "..", "..", "build", "wsgsim"))
        result = subprocess.run([binary, "--script-dir", store, "--script", "/user/echo"],
                                capture_output=True, text=True, timeout=60)
        self.assertEqual(result.returncode, 2)
        self.assertEqual(result.stderr, "wsgsim: --script /user/echo: not a store name "
                                        "(/user/NAME.lua)\n")


if __name__ == "__main__":
    unittest.main()
