# SPDX-License-Identifier: BSD-3-Clause
"""Where the startup script comes from decides what a missing one does
(docs/scripting.md, "Running a script"). The saved settings (the
--save-file the web page's Save writes) boot the device whatever its store
holds: a startup script they chose that is gone, unreadable or no store
name leaves the device ready with the script failed (SF_SCRIPT_FAILURE,
SCRIPT?'s error, a warning). A file the user named (--script, a --config
file) that is not there stays a one-line start error. Everything runs on a
paused clock; nothing waits on wall time but the start itself."""
import os
import shutil
import subprocess
import tempfile
import unittest

from gclclient import Wsgsim

HERE = os.path.dirname(os.path.abspath(__file__))
BINARY = os.environ.get("WSGSIM", os.path.join(HERE, "..", "..", "build", "wsgsim"))
ECHO = "cmd.register(0xB5)\nprint('echo ready')\nwhile true do\n  local id, p = cmd.read()\n" \
       "  cmd.send(id, etob(E_SUCCESS), p)\nend\n"


class StartupSources(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="wsgsim-store-")
        self.addCleanup(shutil.rmtree, self.dir)
        self.saved = os.path.join(self.dir, "saved.ini")

    def write(self, name, text):
        path = os.path.join(self.dir, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def start(self, *args):
        sim = Wsgsim("--start-paused", "--sim-port", "0", "--script-dir", self.dir,
                     "--save-file", self.saved, *args)
        sim.start()
        self.addCleanup(sim.stop)
        ctl = sim.control()
        self.addCleanup(ctl.close)
        return sim, ctl

    def refused_start(self, *args):
        result = subprocess.run([BINARY, "--tcp-port", "0", "--udp-port", "0", "--http-port", "0",
                                 "--binary-udp-port", "0", "--script-dir", self.dir, *args],
                                capture_output=True, text=True, timeout=60)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertEqual(result.stderr.count("\n"), 1, result.stderr)
        return result.stderr

    def assert_failed_startup(self, sim, ctl, file, reason):
        """Ready, the startup script failed with reason, in every place."""
        state = ctl.json("SCRIPT?")
        self.assertEqual((state["file"], state["running"], state["failure"], state["error"]),
                         (file, False, True, "startup script %s: %s" % (file, reason)))
        with sim.tcp() as gcl:
            gcl.expect("SYSFLAGS[20]?", "SYSFLAGS[20]=1")  # SF_SCRIPT_FAILURE
            gcl.expect("SYSFLAGS[19]?", "SYSFLAGS[19]=0")
        self.assertIn("warning: script error: startup script %s: %s" % (file, reason),
                      sim.drain_log())

    def test_a_saved_startup_script_that_is_gone_starts_the_device_failed(self):
        self.write("saved.ini", "[script]\nstartup = /user/gone.lua\nautostart = yes\n")
        sim, ctl = self.start()
        self.assert_failed_startup(sim, ctl, "/user/gone.lua", "No such file or directory")
        # the file back, the next power-on runs it
        self.write("gone.lua", ECHO)
        self.assertEqual(ctl("RESET()"), "ACK RESET")
        state = ctl.json("SCRIPT?")
        self.assertEqual((state["running"], state["failure"], state["registered"]),
                         (True, False, [0xB5]))

    def test_a_saved_startup_name_that_is_no_store_file(self):
        self.write("notes.txt", "print('not a script')\n")
        self.write("saved.ini", "[script]\nstartup = /user/notes.txt\n")
        sim, ctl = self.start()
        self.assert_failed_startup(sim, ctl, "/user/notes.txt", "not a store name (/user/NAME.lua)")

    def test_a_saved_startup_script_that_cannot_be_read(self):
        os.mkdir(os.path.join(self.dir, "folder.lua"))
        self.write("saved.ini", "[script]\nstartup = /user/folder.lua\n")
        sim, ctl = self.start()
        self.assert_failed_startup(sim, ctl, "/user/folder.lua", "not a regular file")

    def test_a_saved_startup_script_without_a_store(self):
        self.write("saved.ini", "[script]\nstartup = /user/gone.lua\n")
        sim = Wsgsim("--start-paused", "--sim-port", "0", "--save-file", self.saved)
        sim.start()
        self.addCleanup(sim.stop)
        with sim.control() as ctl:
            self.assert_failed_startup(sim, ctl, "/user/gone.lua",
                                       "there is no /user/ store (--script-dir)")

    def test_a_fleet_device_whose_saved_script_is_gone(self):
        self.write("echo.lua", ECHO)
        self.write("saved.ini", "[script]\nstartup = /user/echo.lua\n\n"
                                "[device.1]\nscript = /user/gone.lua\n")
        sim, ctl = self.start("--devices", "2")
        self.assertEqual(ctl.json("SCRIPT?")["registered"], [0xB5])
        self.assertEqual(ctl("DEVICE=1"), "DEVICE=1")
        state = ctl.json("SCRIPT?")
        self.assertEqual((state["failure"], state["error"]),
                         (True, "startup script /user/gone.lua: No such file or directory"))
        self.assertIn("warning: script[1] error: startup script /user/gone.lua", sim.drain_log())

    def test_saved_autostart_off_starts_beside_a_configured_file_that_is_gone(self):
        config = self.write("wsgsim.ini", "[script]\nstartup = /user/gone.lua\n")
        self.write("saved.ini", "[script]\nautostart = no\n")
        sim, ctl = self.start("--config", config)
        state = ctl.json("SCRIPT?")
        self.assertEqual((state["running"], state["failure"]), (False, False))
        self.assertNotIn("script error", sim.drain_log())

    def test_a_configured_startup_script_that_is_gone_is_a_start_error(self):
        config = self.write("wsgsim.ini", "[script]\nstartup = /user/gone.lua\n")
        self.assertEqual(self.refused_start("--config", config),
                         "wsgsim: --script /user/gone.lua: No such file or directory\n")
        config = self.write("fleet.ini", "[device.1]\nscript = /user/gone.lua\n")
        self.assertEqual(self.refused_start("--config", config, "--devices", "2"),
                         "wsgsim: --script /user/gone.lua: No such file or directory\n")

    def test_the_command_line_script_is_a_start_error_over_a_save_file(self):
        self.write("saved.ini", "[script]\nstartup = /user/gone.lua\n")
        self.assertEqual(self.refused_start("--save-file", self.saved,
                                            "--script", "/user/gone.lua"),
                         "wsgsim: --script /user/gone.lua: No such file or directory\n")
        self.assertEqual(self.refused_start("--save-file", self.saved,
                                            "--script", "/user/other.lua"),
                         "wsgsim: --script /user/other.lua: No such file or directory\n")


if __name__ == "__main__":
    unittest.main()
