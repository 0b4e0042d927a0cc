# SPDX-License-Identifier: BSD-3-Clause
"""Unit tests of run_vcan.py's choice of where the vcan scenario runs: a
fallback happens only when the probe of the earlier backend failed, a forced
backend never probes, and a probe boot that panics or hangs counts as failed.
Run by make can-vcan-tests before the scenario."""
import contextlib
import glob
import gzip
import io
import lzma
import os
import shutil
import signal
import stat
import sys
import tempfile
import time
import types
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_vcan  # noqa: E402
import vcan_guests  # noqa: E402


def processes_running(cmdline):
    """The pids whose command line is cmdline (NUL-separated, as in /proc)."""
    pids = []
    for path in glob.glob("/proc/[0-9]*/cmdline"):
        try:
            with open(path, "rb") as f:
                if f.read() == cmdline:
                    pids.append(int(path.split("/")[2]))
        except OSError:  # it ended meanwhile
            pass
    return pids


class Probe:
    """A probe that answers as told and counts its calls."""

    def __init__(self, ok, why=""):
        self.answer = (ok, why)
        self.calls = 0

    def __call__(self):
        self.calls += 1
        return self.answer


class ChooseBackend(unittest.TestCase):
    def test_native_first(self):
        uml = Probe(True)
        self.assertEqual(run_vcan.choose_backend("auto", Probe(True), uml)[0], "native")
        self.assertEqual(uml.calls, 0)

    def test_uml_when_its_probe_works(self):
        backend, why = run_vcan.choose_backend("auto", Probe(False, "no AF_CAN"), Probe(True))
        self.assertEqual(backend, "uml")
        self.assertIn("no AF_CAN", why)

    def test_qemu_only_when_the_uml_probe_failed(self):
        backend, why = run_vcan.choose_backend("auto", Probe(False, "no AF_CAN"),
                                               Probe(False, "it left no exit status"))
        self.assertEqual(backend, "qemu")
        self.assertIn("it left no exit status", why)

    def test_forced_guest_never_probes(self):
        for backend in ("uml", "qemu"):
            native, uml = Probe(True), Probe(True)
            self.assertEqual(run_vcan.choose_backend(backend, native, uml)[0], backend)
            self.assertEqual(native.calls + uml.calls, 0)

    def test_forced_native_fails_without_vcan(self):
        uml = Probe(True)
        backend, why = run_vcan.choose_backend("native", Probe(False, "no AF_CAN"), uml)
        self.assertIsNone(backend)
        self.assertIn("no AF_CAN", why)
        self.assertEqual(uml.calls, 0)


class ChooseAccel(unittest.TestCase):
    def test_kvm_only_after_its_probe_worked(self):
        self.assertEqual(run_vcan.choose_accel("auto", True, Probe(True))[0], "kvm")
        accel, why = run_vcan.choose_accel("auto", True, Probe(False, "did not end"))
        self.assertEqual(accel, "tcg")
        self.assertIn("did not end", why)

    def test_no_probe_without_dev_kvm(self):
        kvm = Probe(True)
        self.assertEqual(run_vcan.choose_accel("auto", False, kvm)[0], "tcg")
        self.assertEqual(kvm.calls, 0)

    def test_forced(self):
        kvm = Probe(False)
        self.assertEqual(run_vcan.choose_accel("kvm", True, kvm)[0], "kvm")
        self.assertEqual(run_vcan.choose_accel("tcg", True, kvm)[0], "tcg")
        self.assertEqual(kvm.calls, 0)


class StandInUml(unittest.TestCase):
    """User-mode Linux with a stand-in for linux.uml: a script that behaves
    like the kernel (runs init.sh, or panics, or hangs)."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="wsgsim-probe-test-")
        self.addCleanup(shutil.rmtree, self.dir, ignore_errors=True)

    def uml(self, body):
        kernel = os.path.join(self.dir, "linux.uml")
        with open(kernel, "w") as f:  # $init: the init= argument
            f.write('#!/bin/sh\nfor a; do case $a in init=*) init=${a#init=} ;; esac; done\n'
                    + body + "\n")
        os.chmod(kernel, stat.S_IRWXU)
        guest = vcan_guests.Uml()
        guest.kernel, guest.modules = kernel, self.dir
        return guest


class ProbeBoot(StandInUml):

    def test_a_guest_that_ran_the_command_works(self):
        # what the guest's init would write once it ran the probe command
        body = 'grep -q "probe: sent a frame" "$init" && echo 0 >"$(dirname "$init")/status"'
        self.assertEqual(run_vcan.probe(self.uml(body)), (True, ""))

    def test_a_panic_is_a_failed_probe(self):
        ok, why = run_vcan.probe(self.uml(
            "echo 'userspace - ptrace set fp regs failed, errno = 14'; "
            "echo 'Kernel panic - not syncing: Attempted to kill init! exitcode=0x0000000b'"))
        self.assertFalse(ok)
        self.assertIn("no exit status", why)
        self.assertIn("Kernel panic", why)

    def test_a_failed_command_is_a_failed_probe(self):
        body = 'echo 1 >"$(dirname "$init")/status"'
        ok, why = run_vcan.probe(self.uml(body))
        self.assertFalse(ok)
        self.assertIn("exit status was 1", why)

    def test_a_hang_is_a_failed_probe(self):
        saved = dict(run_vcan.PROBE_TIMEOUT_S)
        self.addCleanup(run_vcan.PROBE_TIMEOUT_S.update, saved)
        run_vcan.PROBE_TIMEOUT_S["uml"] = 1
        # the stand-in starts a process of its own, as UML does for its guest's;
        # its command line is this test's alone
        sleep = "%d.25" % (3600000000 + os.getpid())
        ok, why = run_vcan.probe(self.uml("echo booting; sleep %s & wait" % sleep))
        self.assertFalse(ok)
        # (what the console shows by then depends on the machine's speed)
        self.assertIn("did not end within 1 s (console: ", why)
        # killed, it may take a moment to be gone (bounded against a hang)
        deadline = time.monotonic() + 30
        while processes_running(b"sleep\0%s\0" % sleep.encode()) and time.monotonic() < deadline:
            time.sleep(0.05)
        left = processes_running(b"sleep\0%s\0" % sleep.encode())
        for pid in left:
            os.kill(pid, signal.SIGKILL)
        self.assertEqual(left, [], "processes of the guest left running")


class GuestRun(StandInUml):
    """run_guest() falls back only from a guest that failed before the
    scenario started, and only when asked to (auto)."""

    ARGS = types.SimpleNamespace(wsgsim="/bin/true", fingersim="/bin/true", dbc="x.dbc",
                                 guest_wsgsim=None, guest_fingersim=None)
    PANIC = "echo 'Kernel panic - not syncing: Attempted to kill init!'"
    # the scenario's first line, then the guest dies
    DIED_IN_SCENARIO = 'echo "vcan: finger bus on vcan0" >"$(dirname "$init")/guest.log"'

    def run_guest(self, body, fall_back):
        with contextlib.redirect_stdout(io.StringIO()) as out:
            code = run_vcan.run_guest(self.ARGS, self.uml(body), fall_back=fall_back)
        for path in glob.glob(out.getvalue().rpartition(" ")[2].strip()):
            shutil.rmtree(path, ignore_errors=True)  # the logs it kept
        return code, out.getvalue()

    def test_falls_back_from_a_guest_that_never_reached_the_scenario(self):
        code, out = self.run_guest(self.PANIC, fall_back=True)
        self.assertIsNone(code)
        self.assertIn("failed before the scenario started (console: Kernel panic", out)

    def test_a_forced_guest_fails_instead(self):
        code, out = self.run_guest(self.PANIC, fall_back=False)
        self.assertEqual(code, 1)
        self.assertIn("the guest left no exit status; console tail:\nKernel panic", out)

    def test_never_falls_back_from_a_scenario_that_ran(self):
        code, out = self.run_guest(self.DIED_IN_SCENARIO, fall_back=True)
        self.assertEqual(code, 1)
        self.assertIn("the guest left no exit status", out)

    def test_a_failed_scenario_is_its_status(self):
        code, out = self.run_guest('echo 1 >"$(dirname "$init")/status"', fall_back=True)
        self.assertEqual(code, 1)
        self.assertIn("scenario exit status 1", out)


class Initramfs(unittest.TestCase):
    def test_modules_come_after_what_they_need(self):
        moddir = tempfile.mkdtemp(prefix="wsgsim-moddep-test-")
        self.addCleanup(shutil.rmtree, moddir, ignore_errors=True)
        with open(os.path.join(moddir, "modules.dep"), "w") as f:
            f.write("kernel/a/9p.ko: kernel/b/9pnet.ko kernel/c/fscache.ko kernel/d/netfs.ko\n"
                    "kernel/b/9pnet.ko:\nkernel/c/fscache.ko: kernel/d/netfs.ko\n"
                    "kernel/d/netfs.ko:\nkernel/e/can-raw.ko.xz: kernel/f/can.ko.xz\n"
                    "kernel/f/can.ko.xz:\n")
        self.assertEqual(vcan_guests.modules_in_order(moddir, ["9p", "can_raw"]),
                         ["kernel/d/netfs.ko", "kernel/c/fscache.ko", "kernel/b/9pnet.ko",
                          "kernel/a/9p.ko", "kernel/f/can.ko.xz", "kernel/e/can-raw.ko.xz"])
        with self.assertRaises(vcan_guests.GuestError):
            vcan_guests.modules_in_order(moddir, ["vcan"])

    def test_compressed_modules_are_unpacked(self):
        moddir = tempfile.mkdtemp(prefix="wsgsim-modules-test-")
        self.addCleanup(shutil.rmtree, moddir, ignore_errors=True)
        image = b"\x7fELF module image"
        with lzma.open(os.path.join(moddir, "vcan.ko.xz"), "wb") as f:
            f.write(image)
        self.assertEqual(vcan_guests.module_bytes(os.path.join(moddir, "vcan.ko.xz")), image)
        with open(os.path.join(moddir, "vcan.ko.zst"), "wb") as f:
            f.write(b"(zstd)")
        with self.assertRaises(vcan_guests.GuestError):
            vcan_guests.module_bytes(os.path.join(moddir, "vcan.ko.zst"))

    def test_newest_kernel_first(self):
        names = ["6.1.0-9-amd64", "6.1.0-56-amd64", "6.10.0-1-amd64"]
        self.assertEqual(sorted(names, key=vcan_guests.version_key),
                         ["6.1.0-9-amd64", "6.1.0-56-amd64", "6.10.0-1-amd64"])

    def test_cpio_names_and_sizes(self):
        archive = vcan_guests.cpio_newc([("bin", 0o40755, None), ("init", 0o100755, b"#!x\n")])
        self.assertEqual(cpio_entries(self, archive),
                         [("bin", b""), ("init", b"#!x\n"), ("TRAILER!!!", b"")])


class GuestSeesTheCheckout(unittest.TestCase):
    def test_the_checkout_has_a_share_mounted_over_the_guests_tmp(self):
        """The guest's /tmp is a tmpfs over the host's: a checkout under /tmp
        (a clone there) is seen only through a share of its own, mounted
        after that tmpfs (before, the scenario was not found)."""
        workdir = tempfile.mkdtemp(prefix="wsgsim-qemu-test-")
        self.addCleanup(shutil.rmtree, workdir, ignore_errors=True)
        cmd = vcan_guests.Qemu("tcg").command(workdir)
        shares = [cmd[i + 1] for i, arg in enumerate(cmd) if arg == "-virtfs"]
        self.assertIn("local,path=%s,mount_tag=checkout,security_model=none,readonly=on"
                      % vcan_guests.CHECKOUT, shares)
        with gzip.open(os.path.join(workdir, "initramfs.gz")) as f:
            init = dict((name, data) for name, data in cpio_entries(self, f.read()))["init"]
        init = init.decode()
        self.assertIn('CHECKOUT="%s"' % vcan_guests.CHECKOUT, init)
        self.assertLess(init.index("tmpfs /newroot/tmp"),
                        init.index('checkout "/newroot$CHECKOUT"'))
        self.assertTrue(os.path.exists(os.path.join(vcan_guests.CHECKOUT, "tests", "can",
                                                    "vcan_scenario.py")))


def cpio_entries(test, archive):
    """The (name, data) entries of a newc archive, its trailer included."""
    entries, at = [], 0
    while True:
        header = archive[at:at + 110]
        test.assertEqual(header[:6], b"070701")
        size, namesize = int(header[54:62], 16), int(header[94:102], 16)
        name = archive[at + 110:at + 110 + namesize - 1].decode()
        at += 110 + namesize
        at += -at % 4
        entries.append((name, archive[at:at + size]))
        at += size + (-size % 4)
        if name == "TRAILER!!!":
            break
    test.assertEqual(at, len(archive))
    return entries

if __name__ == "__main__":
    unittest.main()
