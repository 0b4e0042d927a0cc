# SPDX-License-Identifier: BSD-3-Clause
"""What a script cannot do to the device (docs/scripting.md, "Limits"):
freeze it with work that never pauses (a __gc finalizer, pattern
backtracking, string.rep, table.move, a plain find, pcall inside a
table.sort comparator), run from the control channel, as the startup
script (a fleet's too) or from the web; hold the loop with short work at
every wake-up of a catch-up or a STEP; slow a fleet's other devices down
(one slice budget per loop pass, in rotation); take more memory than the
process's budget, or fill it with console lines; delay a power cycle or
the exit with its finalizers; park itself by waiting inside a coroutine
of its own or where Lua cannot yield. Nothing here measures wall time:
the freezes end by the watchdog, and the tests wait for what the device
answers after them or count loop passes."""
import os
import shutil
import struct
import sys
import tempfile
import unittest

from gclclient import Wsgsim

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "web"))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402
from webclient import WebSim, request  # noqa: E402

SF_SCRIPT_RUNNING, SF_SCRIPT_FAILURE, SF_FAST_STOP = 1 << 19, 1 << 20, 1 << 12

# Work the instruction hook never sees: it runs in C, or with hooks off.
FREEZES = {
    "finalizer": "setmetatable({}, {__gc = function() while true do end end})\n"
                 "collectgarbage()\n",
    "backtracking": 'string.find(("a"):rep(3000), ".-.-.-.-.-.-b")\n',
    # pcall catches any error raised where the script cannot yield: only
    # an exit no Lua code sees ends this
    "caught_in_sort": "local t = {3, 1, 2}\n"
                      "table.sort(t, function(a, b)\n"
                      "  while true do pcall(function() local n = 0 while true do n = n + 1 end end) end\n"
                      "end)\n",
}
# Library calls that loop in C for ever (or for hours) without the bounds:
# bounded, they end at once, the script runs on and ends normally.
BOUNDED = {
    "rep": 'assert(string.rep("", math.maxinteger) == "")\n'
           'local ok, e = pcall(string.rep, "x", math.maxinteger)\n'
           'assert(not ok and e:find("larger than a script", 1, true), e)\n'
           'assert(string.rep("ab", 3, ",") == "ab,ab,ab")\n',
    "move": "local ok, e = pcall(table.move, {}, 1, math.maxinteger // 2, 2)\n"
            'assert(not ok and e:find("more elements than", 1, true), e)\n'
            "assert(table.concat(table.move({1, 2, 3}, 1, 3, 2), \",\") == \"1,1,2,3\")\n",
    # each search some 8 ms here: the script pauses between them, as one
    # must between long library calls (docs/scripting.md, "Limits")
    "plain_find": 'local hay = ("a"):rep(4 * 1024 * 1024)\n'
                  'local needle = ("a"):rep(2 * 1024 * 1024) .. "b"\n'
                  "sleep(0)\n"
                  "assert(hay:find(needle, 1, true) == nil)\n"
                  "sleep(0)\n"
                  "assert(hay:find(needle) == nil)\n"
                  'assert(select(2, ("xxab"):find("ab", 1, true)) == 4)\n',
}
WATCHDOG = "script stopped by the watchdog"


def store(case, **files):
    path = tempfile.mkdtemp(prefix="wsgsim-guard-")
    case.addCleanup(shutil.rmtree, path)
    for name, text in files.items():
        with open(os.path.join(path, name + ".lua"), "w") as f:
            f.write(text)
    return path


class Case(unittest.TestCase):
    def start(self, *args, files=None, web=False):
        self.dir = store(self, **(files or {}))
        self.sim = (WebSim if web else Wsgsim)("--sim-port", "0", "--script-dir", self.dir, *args)
        self.sim.start()
        self.addCleanup(self.sim.stop)
        self.ctl = self.sim.control()
        self.addCleanup(self.ctl.close)

    def binary(self):
        client = wb.BinTcp("127.0.0.1", self.sim.tcp_port, timeout=30.0)
        self.addCleanup(client.close)
        return client

    def flags(self, client):
        client.send_request(0x40, b"\x00\x00\x00")
        return struct.unpack("<I", client.wait_for(0x40).values)[0]

    def script(self, device=None):
        if device is not None:
            self.ctl("DEVICE=%d" % device)
        return self.ctl.json("SCRIPT?")

    def wait_ended(self, device=None, polls=3000):
        """The script's state once it no longer runs (every poll is a loop pass)."""
        for _ in range(polls):
            state = self.script(device)
            if not state["running"]:
                return state
        self.fail("the script still runs: %r" % state)

    def assert_stopped_by_watchdog(self, state):
        self.assertFalse(state["running"])
        self.assertTrue(state["failure"])
        self.assertTrue(state["error"].startswith(WATCHDOG), state["error"])


class Freezes(Case):
    """Each freeze, started while clients wait: they are all answered once
    the watchdog has ended it, FAST STOP included."""

    def serves_everything(self):
        gcl = self.sim.tcp()
        self.addCleanup(gcl.close)
        self.assertTrue(gcl.command("POS?").startswith("POS="))
        client = self.binary()
        client.send_request(0x43, b"\x00\x00\x00")
        self.assertEqual(client.wait_for(0x43).status, 0)
        self.assertEqual(request(self.api + "/state").status, 200)
        self.assertEqual(gcl.command("FASTSTOP()"), "ACK FASTSTOP")
        self.assertTrue(self.flags(client) & SF_FAST_STOP)
        self.assertEqual(gcl.command("FSACK()"), "ACK FSACK")
        return client

    def start_web(self, files):
        self.start(files=files, web=True)
        self.api = self.sim.base + "/api/devices/0"

    def test_from_the_control_channel(self):
        self.start_web(FREEZES)
        for name in FREEZES:
            with self.subTest(name):
                self.ctl.send('SCRIPT_RUN("%s.lua")' % name)  # answered once it has ended
                client = self.serves_everything()
                self.assertEqual(self.ctl.read_line(), "ACK SCRIPT_RUN")
                self.assert_stopped_by_watchdog(self.script())
                self.assertEqual(self.flags(client) & (SF_SCRIPT_RUNNING | SF_SCRIPT_FAILURE),
                                 SF_SCRIPT_FAILURE)
        self.assertEqual(self.sim.drain_log().count("script error: " + WATCHDOG), len(FREEZES))

    def test_from_the_web(self):
        self.start_web(FREEZES)
        for name in FREEZES:
            with self.subTest(name):
                reply = request(self.api + "/script/run", "POST", {"file": "/user/%s.lua" % name})
                self.assertEqual(reply.status, 200, reply)
                self.assert_stopped_by_watchdog(reply.json())
                self.serves_everything()

    def test_pcall_does_not_catch_the_watchdog(self):
        caught = "local ok = pcall(function() %s end)\ncmd.register(0xB0)\nprint('caught')\n"
        self.start(files={"caught": caught % FREEZES["backtracking"].strip()})
        self.ctl('SCRIPT_RUN("caught.lua")')
        state = self.script()
        self.assert_stopped_by_watchdog(state)
        self.assertEqual(state["registered"], [])
        self.assertNotIn("script: caught", self.sim.drain_log())

    def test_a_finalizer_that_loops_when_the_user_stops_the_script(self):
        code = "setmetatable({}, {__gc = function() while true do end end})\n" \
               "while true do sleep(10) end\n"
        self.start("--start-paused", files={"stuck": code})
        self.ctl('SCRIPT_RUN("stuck.lua")')
        self.ctl.step(50)
        self.assertEqual(self.ctl("SCRIPT_STOP()"), "ACK SCRIPT_STOP")
        state = self.script()
        self.assertFalse(state["running"])
        self.assertIn("finalizers ran more than", state["error"])
        self.assertEqual(state["memory_bytes"], 0)
        self.assertEqual(state["process"]["memory_bytes"], 0)

    def test_sigterm_ends_the_process_during_a_freeze(self):
        code = "setmetatable({}, {__gc = function() while true do end end})\n" \
               "print('freezing')\ncollectgarbage()\n"
        self.start(files={"freeze": code})
        self.ctl.send('SCRIPT_RUN("freeze.lua")')
        for _ in range(6000):  # the line is logged as the freeze begins
            if "script: freezing" in self.sim.drain_log(0.01):
                break
        self.assertIn("script: freezing", "".join(self.sim.log))
        self.assertEqual(self.sim.stop(), 0)


class PowerLoss(Case):
    """A power cycle (RESET) and the process's exit drop the interpreters:
    nothing of a script runs again, as on a device that loses its power.
    Its finalizers ran there, each up to the watchdog's limit, one device
    after another: a fleet whose scripts loop in __gc took seconds to exit."""

    GC_LOOP = "setmetatable({}, {__gc = function() while true do end end})\n" \
              "while true do sleep(10) end\n"

    def test_a_power_cycle_runs_no_finalizer(self):
        self.start("--start-paused", files={"gc": self.GC_LOOP})
        self.ctl('SCRIPT_RUN("gc.lua")')
        self.assertEqual(self.ctl("RESET()"), "ACK RESET")
        state = self.script()
        self.assertFalse(state["running"])
        self.assertIsNone(state["error"])
        self.assertEqual(state["process"]["watchdog_stops"], 0)
        self.assertEqual(state["process"]["memory_bytes"], 0)

    def test_the_exit_runs_no_finalizer(self):
        devices = 8
        self.start("--start-paused", "--devices", str(devices), files={"gc": self.GC_LOOP})
        for i in range(devices):
            self.ctl("DEVICE=%d" % i)
            self.assertEqual(self.ctl('SCRIPT_RUN("gc.lua")'), "ACK SCRIPT_RUN")
        self.assertEqual(self.sim.stop(), 0)
        log = "".join(self.sim.log)
        self.assertIn("shutting down", log)
        self.assertNotIn("finalizers ran more than", log)


class Startup(Case):
    def test_a_startup_script_that_freezes_lets_the_device_become_ready(self):
        for name, code in FREEZES.items():
            with self.subTest(name):
                path = os.path.join(store(self, **{name: code}), name + ".lua")
                with Wsgsim("--sim-port", "0", "--script", path) as sim:
                    with sim.control() as ctl:
                        self.assert_stopped_by_watchdog(ctl.json("SCRIPT?"))
                    gcl = sim.tcp()
                    self.assertTrue(gcl.command("POS?").startswith("POS="))
                    gcl.close()
                self.assertEqual(sim.returncode, 0)


    def test_a_fleets_startup_scripts_start_after_it_is_ready(self):
        # each freeze ended by the watchdog before the next device's start:
        # the power-on of N devices took N times the limit (minutes for
        # thousands), now the loop starts them in turn while it serves
        devices = 8
        folder = store(self, freeze=FREEZES["backtracking"])
        config = os.path.join(folder, "fleet.ini")
        with open(config, "w") as f:
            f.write("[script]\ndir = %s\n" % folder)
            for i in range(devices):
                f.write("[device.%d]\nscript = /user/freeze.lua\n" % i)
        self.sim = Wsgsim("--sim-port", "0", "--devices", str(devices), "--config", config)
        self.sim.start()
        self.addCleanup(self.sim.stop)
        self.ctl = self.sim.control()
        self.addCleanup(self.ctl.close)
        for i in range(devices):
            self.assert_stopped_by_watchdog(self.wait_ended(i))
        log = self.sim.drain_log()
        errors = [log.index("script[%d] error: %s" % (i, WATCHDOG)) for i in range(devices)]
        self.assertLess(log.index(" ready: "), min(errors))


class Bounded(Case):
    """The calls that need no watchdog: they end at once with a result or a
    clear error (asserted inside the script), and the script ends well."""

    def test_bounded_library_calls(self):
        self.start(files=BOUNDED)
        for name in BOUNDED:
            with self.subTest(name):
                self.assertEqual(self.ctl('SCRIPT_RUN("%s.lua")' % name), "ACK SCRIPT_RUN")
                state = self.wait_ended()
                self.assertFalse(state["failure"], state["error"])

    def test_bounded_as_startup_scripts(self):
        for name, code in BOUNDED.items():
            with self.subTest(name):
                path = os.path.join(store(self, **{name: code}), name + ".lua")
                with Wsgsim("--sim-port", "0", "--script", path) as sim:
                    with sim.control() as ctl:
                        for _ in range(3000):  # it runs in the loop's passes
                            state = ctl.json("SCRIPT?")
                            if not state["running"]:
                                break
                self.assertFalse(state["running"] or state["failure"], state)


BUSY = "cmd.register(0xB0)\nlocal n = 0\nwhile true do n = n + 1 end\n"


class SharedSlice(Case):
    """Busy scripts on devices 1..N beside device 0, which runs none: each
    loop pass continues at most one of them (one shared slice budget), the
    first in turn moving on, so every one of them progresses."""

    def test_one_slice_budget_per_pass_in_rotation(self):
        busy = 8
        self.start("--devices", str(busy + 1), files={"busy": BUSY})
        for i in range(1, busy + 1):
            self.ctl("DEVICE=%d" % i)
            self.assertEqual(self.ctl('SCRIPT_RUN("busy.lua")'), "ACK SCRIPT_RUN")
        gcl = self.sim.tcp()  # device 0
        self.addCleanup(gcl.close)
        resumes = {i: self.script(i)["resumes"] for i in range(1, busy + 1)}
        for _ in range(20):
            self.assertTrue(gcl.command("POS?").startswith("POS="))
        for i in range(1, busy + 1):  # every busy script gets its turns
            for _ in range(3000):
                state = self.script(i)
                if state["resumes"] > resumes[i] + 2:
                    break
            self.assertTrue(state["running"])
            self.assertGreater(state["resumes"], resumes[i] + 2, "device %d starved" % i)
        process = state["process"]
        self.assertGreater(process["passes"], busy)
        self.assertEqual(process["most_continued_in_a_pass"], 1)


# A wake-up's work that cannot pause and stays below the watchdog: six
# times the watchdog's calibration chunk (docs/scripting.md, "Limits": the
# limit is 26 of them), in a table.sort comparator, where the script cannot
# yield. Some 4 ms here: each such wake-up spends a pass's budget.
HEAVY_WAKE = """
local function work()
  table.sort({2, 1}, function(a, b)
    for _ = 1, 6 do
      local x = 0 for i = 1, 200000 do x = x + i end
      for i = 1, 5000 do local t = {i} x = x + #t end
    end
    return a < b
  end)
end
"""


class WakeUps(Case):
    """A script that sleeps a millisecond and then works without a pause,
    below the watchdog's limit, at every wake-up. A loop pass that runs
    many simulated instants (a catch-up, a STEP) once ran every wake-up in
    it, holding the loop for seconds; a wake-up that comes once the pass's
    budget is spent now waits for a later pass, so a pass runs a few of
    them, never all."""

    def assert_few_per_pass(self, before, after):
        resumes = after["resumes"] - before["resumes"]
        passes = after["process"]["passes"] - before["process"]["passes"]
        self.assertGreater(resumes, 0)
        self.assertLessEqual(resumes, 10 * passes, "%d wake-ups in %d passes" % (resumes, passes))
        self.assertGreater(after["process"]["late_wakeups"], before["process"]["late_wakeups"])

    def test_a_step_runs_each_wake_up_at_its_instant_over_many_passes(self):
        code = HEAVY_WAKE + """
require("socket")
local last = socket.gettime()
for i = 1, 60 do
  sleep(1)
  local now = socket.gettime()
  assert(math.abs(now - last - 0.001) < 1e-9, "woke at " .. now .. " after " .. last)
  last = now
  work()
end
print("every wake-up at its instant")
"""
        self.start("--start-paused", files={"steps": code})
        self.ctl('SCRIPT_RUN("steps.lua")')
        gcl = self.sim.tcp()
        self.addCleanup(gcl.close)
        before = self.script()
        # 60 wake-ups of work each a quarter of the watchdog's limit: under
        # valgrind and beside other suites that is minutes; the bound only
        # guards against a hang
        reply = self.ctl("STEP(100)", timeout=900)
        self.assertTrue(reply.startswith("STEP="), reply)
        after = self.script()
        self.assertFalse(after["running"])
        self.assertFalse(after["failure"], after["error"])
        self.assertEqual(after["resumes"] - before["resumes"], 60)
        self.assert_few_per_pass(before, after)
        self.assertIn("script: every wake-up at its instant", self.sim.drain_log())
        self.assertEqual(gcl.command("FASTSTOP()"), "ACK FASTSTOP")

    def test_on_a_running_clock_the_loop_is_not_held(self):
        code = HEAVY_WAKE + "cmd.register(0xB0)\nwhile true do sleep(1) work() end\n"
        self.start("--devices", "2", files={"wakes": code})
        self.ctl("DEVICE=1")
        self.ctl('SCRIPT_RUN("wakes.lua")')
        gcl = self.sim.tcp()  # device 0
        self.addCleanup(gcl.close)
        before = self.script(1)
        for _ in range(50):
            self.assertEqual(gcl.command("SN?"), "SN=12345678")
        self.assertEqual(gcl.command("FASTSTOP()"), "ACK FASTSTOP")
        after = self.script(1)
        self.assertTrue(after["running"], after["error"])
        self.assert_few_per_pass(before, after)


class Memory(Case):
    def test_sixteen_hogs_stay_within_the_process_budget(self):
        # each takes a MiB more every simulated millisecond, all in step
        hog = "local t = {}\nwhile true do t[#t + 1] = string.rep('x', 1 << 20) .. #t sleep(1) end\n"
        self.start("--devices", "16", "--start-paused", files={"hog": hog})
        for i in range(16):
            self.ctl("DEVICE=%d" % i)
            self.ctl('SCRIPT_RUN("hog.lua")')
        budget = self.script(0)["process"]["memory_budget_bytes"]
        self.assertEqual(budget, 64 * 1024 * 1024)
        self.ctl.step(100)
        errors = [self.wait_ended(i)["error"] for i in range(16)]
        for error in errors:
            self.assertRegex(error, r"^not enough memory: the script(s of this process)? used "
                                    r"(its 16|their 64) MiB")
        self.assertIn("not enough memory: the scripts of this process used their 64 MiB together",
                      errors)
        process = self.script(0)["process"]
        self.assertLessEqual(process["memory_peak_bytes"], budget)
        self.assertEqual(process["memory_bytes"], 0)


class Console(Case):
    def test_the_console_keeps_its_newest_lines_within_64_kib(self):
        code = "for i = 1, 1000 do print(string.format('%04d', i) .. ('x'):rep(500)) end\n"
        self.start(files={"long": code}, web=True)
        api = self.sim.base + "/api/devices/0"
        self.assertEqual(request(api + "/script/run", "POST", {"file": "long.lua"}).status, 200)
        self.assertFalse(self.wait_ended()["failure"])
        console = request(api + "/script/console?since=0").json()
        self.assertEqual(console["next"], 1001)  # "running long.lua", then 1000 lines
        lines = console["lines"]
        self.assertLessEqual(sum(len(line) + 1 for line in lines), 64 * 1024)
        self.assertGreater(len(lines), 100)
        numbers = [int(line[:4]) for line in lines]
        self.assertEqual(numbers, list(range(1001 - len(lines), 1001)))  # the newest, in order


class Coroutines(Case):
    def test_waiting_inside_a_coroutine_of_its_own_raises(self):
        code = """
cmd.register(0xB0)
local read_ok, read_err = coroutine.resume(coroutine.create(function() local id = cmd.read() end))
local sleep_ok, sleep_err = coroutine.resume(coroutine.create(function() sleep(10) end))
assert(not read_ok and not sleep_ok)
print(read_err)
print(sleep_err)
local yielded = coroutine.wrap(function() sleep(0) return "after" end)()
assert(yielded == "after", tostring(yielded))
local n = 0
for i = 1, 3e6 do n = n + i end  -- slices end here: the main script is not parked
"""
        self.start("--start-paused", files={"co": code})
        self.ctl('SCRIPT_RUN("co.lua")')
        state = self.wait_ended()
        self.assertFalse(state["failure"], state["error"])
        log = self.sim.drain_log()
        self.assertIn("script: co.lua:3: cmd.read: only the main script can wait, "
                      "not a coroutine of its own", log)
        self.assertIn("script: co.lua:4: sleep: only the main script can wait", log)

    def test_a_wait_where_lua_cannot_yield_raises_and_leaves_no_wait(self):
        # a pcall caught Lua's "attempt to yield across a C-call boundary"
        # after the wait was set: the script then stayed parked in it
        code = """
cmd.register(0xB0)
local function inside_sort(wait)
  return pcall(table.sort, {2, 1}, function(a, b) wait() return a < b end)
end
print(select(2, inside_sort(function() sleep(0) end)))
print(select(2, inside_sort(function() cmd.read() end)))
print(select(2, inside_sort(function() sleep(1e9) end)))
local n = 0
for i = 1, 3e6 do n = n + i end  -- slices end here: the script runs on
print("after")
"""
        self.start("--start-paused", files={"nowait": code})
        self.ctl('SCRIPT_RUN("nowait.lua")')
        state = self.wait_ended()
        self.assertFalse(state["failure"], state["error"])
        log = self.sim.drain_log()
        for line, name in ((6, "sleep"), (7, "cmd.read"), (8, "sleep")):  # no wait left
            self.assertIn("script: nowait.lua:%d: %s: cannot wait inside a function called back "
                          "from C" % (line, name), log)
        self.assertIn("script: after", log)

    def test_a_slice_ending_inside_a_generator_does_not_end_it(self):
        code = """
local gen = coroutine.wrap(function()
  for i = 1, 3 do
    local n = 0
    for k = 1, 5e6 do n = n + k end
    coroutine.yield(i)
  end
end)
local got = {}
for v in gen do got[#got + 1] = v end
local co = coroutine.create(function() local n = 0 for k = 1, 5e6 do n = n + k end return "done" end)
local ok, result = coroutine.resume(co)
assert(#got == 3 and ok and result == "done", #got .. " " .. tostring(result))
local bad = coroutine.wrap(function() error("boom") end)
local ok2, e = pcall(bad)
assert(not ok2 and e:find("boom"), e)
"""
        self.start("--start-paused", files={"gen": code})
        self.ctl('SCRIPT_RUN("gen.lua")')
        state = self.wait_ended()
        self.assertFalse(state["failure"], state["error"])


class Functional(Case):
    def test_load_and_loadstring_with_one_argument(self):
        code = """
assert(load("return 40 + 2")() == 42)
assert(loadstring("return 'x'")() == "x")
assert(load("return ...", "named")(7) == 7)
local f, e = load("return +")
assert(f == nil and e:find("unexpected symbol"), e)
local env = {y = 5}
assert(load("return y", "env", "t", env)() == 5)
"""
        self.start(files={"loads": code})
        self.assertEqual(self.ctl('SCRIPT_RUN("loads.lua")'), "ACK SCRIPT_RUN")
        state = self.wait_ended()
        self.assertFalse(state["failure"], state["error"])

    def test_cmd_errors_name_the_id(self):
        code = "print(select(2, pcall(cmd.register, 0x21)))\n" \
               "print(select(2, pcall(cmd.send, 0xB9, 1)))\n"
        self.start(files={"ids": code})
        self.ctl('SCRIPT_RUN("ids.lua")')
        self.wait_ended()
        log = self.sim.drain_log()
        self.assertIn("script: cmd.register: ID 0x21 is the firmware's own", log)
        self.assertIn("script: cmd.send: ID 0xB9 is not registered", log)


if __name__ == "__main__":
    unittest.main()
