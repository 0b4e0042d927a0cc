#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs tests/can/vcan_scenario.py on a real vcan0, in the first of these
that works here (--backend auto), or in the one --backend names:

  native  this kernel, where it has SocketCAN and vcan0 exists or can be made
  uml     Debian's user-mode Linux, the host's filesystem as its root; auto
          takes it only after a short probe boot of it ran a CAN socket on
          vcan0 (it panics on some hosts, depending on their CPU), and goes
          on to qemu when the guest still fails before the scenario starts
  qemu    Debian's own kernel (linux-image-amd64) in QEMU system emulation,
          the host's filesystem as its root over 9p; with KVM only after a
          short probe boot with KVM worked, TCG otherwise (--qemu-accel)

The scenario and its checks are the same in all three. Prints which backend
ran and why. Never skips: when the chosen backend cannot run, or its guest
leaves no exit status, it fails and says why, with the guest's console tail.

usage: run_vcan.py --wsgsim BIN --fingersim BIN --dbc FILE
                   [--backend auto|native|uml|qemu] [--qemu-accel auto|kvm|tcg]
"""
import argparse
import os
import re
import shutil
import socket
import subprocess
import sys
import tempfile

from vcan_guests import GuestError, Qemu, Uml

HERE = os.path.dirname(os.path.abspath(__file__))
SCENARIO = os.path.join(HERE, "vcan_scenario.py")
PYTHON = "/usr/bin/python3"  # Debian's, which has python3-canmatrix
# Against a hang only: up to three runs of the scenario (slow under TCG).
GUEST_TIMEOUT_S = {"uml": 900, "qemu": 2400}
# A probe boot only decides which backend runs: a probe killed on a busy host
# costs speed (the next backend runs the same scenario), never a verdict.
# User-mode Linux boots and runs the probe in seconds, QEMU with KVM too;
# where KVM hangs (seen: AVX-512 host, kernel 6.18) its probe waits this long.
PROBE_TIMEOUT_S = {"uml": 120, "qemu": 40}
# What a probe runs in the guest: the kernel runs Python and a CAN socket
# sends a frame on vcan0.
PROBE_COMMAND = [PYTHON, "-c",
                 "import socket; s = socket.socket(socket.AF_CAN, socket.SOCK_RAW, "
                 "socket.CAN_RAW); s.bind(('vcan0',)); s.send(bytes(16)); "
                 "print('probe: sent a frame on vcan0')"]


def af_can_available():
    try:
        s = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    except (OSError, AttributeError):
        return False
    s.close()
    return True


def native_vcan():
    """(True, '') when vcan0 is usable here, else (False, why)."""
    if not af_can_available():
        return False, "this kernel has no AF_CAN"
    if os.path.exists("/sys/class/net/vcan0"):
        return True, ""
    if os.geteuid() != 0:
        return False, "vcan0 does not exist and creating it needs root"
    for cmd in (["modprobe", "vcan"], ["ip", "link", "add", "dev", "vcan0", "type", "vcan"],
                ["ip", "link", "set", "up", "vcan0"]):
        if subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode:
            if cmd[0] != "modprobe":
                return False, "could not run: %s" % " ".join(cmd)
    return True, ""


def choose_backend(requested, native_probe, uml_probe):
    """(backend, why): backend is native, uml, qemu, or None when the
    requested one cannot run. The probes are called only when needed and
    answer (works, why not)."""
    if requested in ("uml", "qemu"):
        return requested, "VCAN_BACKEND=%s" % requested
    native_ok, native_why = native_probe()
    if requested == "native":
        if native_ok:
            return "native", "VCAN_BACKEND=native"
        return None, "VCAN_BACKEND=native, but no native vcan0: %s" % native_why
    if native_ok:
        return "native", "this kernel has vcan0"
    uml_ok, uml_why = uml_probe()
    if uml_ok:
        return "uml", "no native vcan0 (%s); the probe boot of user-mode Linux worked" % native_why
    return "qemu", ("no native vcan0 (%s); the probe boot of user-mode Linux failed: %s" %
                    (native_why, uml_why))


def choose_accel(requested, kvm_usable, kvm_probe):
    """(accel, why): kvm only when asked for, or when auto and the probe
    boot with KVM worked."""
    if requested != "auto":
        return requested, "VCAN_QEMU_ACCEL=%s" % requested
    if not kvm_usable:
        return "tcg", "no usable /dev/kvm"
    kvm_ok, kvm_why = kvm_probe()
    if kvm_ok:
        return "kvm", "the probe boot with KVM worked"
    return "tcg", "the probe boot with KVM failed: %s" % kvm_why


def probe(guest):
    """(works, why not): boots guest with PROBE_COMMAND."""
    timeout = PROBE_TIMEOUT_S[guest.name]
    workdir = tempfile.mkdtemp(prefix="wsgsim-probe-%s-" % guest.name)
    try:
        result = guest.boot(workdir, PROBE_COMMAND, timeout)
    except GuestError as e:
        shutil.rmtree(workdir, ignore_errors=True)
        return False, str(e)
    status = read_status(workdir)
    why = ""
    if result.timed_out:
        why = "it did not end within %d s (%s)" % (timeout, last_console_line(workdir))
    elif status is None:
        why = "it left no exit status (%s)" % last_console_line(workdir)
    elif status != "0":
        why = "the probe command's exit status was %s (%s)" % (status, last_guest_line(workdir))
    shutil.rmtree(workdir, ignore_errors=True)
    return why == "", why


def last_console_line(workdir):
    text = re.sub(r"\x1b\[[0-9;?]*[A-Za-z]|\x1bc|[^\x20-\x7e\n]", "", console_tail(workdir, 3000))
    lines = [line for line in text.splitlines() if line.strip()]
    return ("console: " + lines[-1].strip()) if lines else "no console output"


def last_guest_line(workdir):
    path = os.path.join(workdir, "guest.log")
    lines = []
    if os.path.exists(path):
        with open(path, errors="replace") as f:
            lines = [line for line in f.read().splitlines() if line.strip()]
    return ("guest: " + lines[-1].strip()) if lines else "no guest output"


def console_tail(workdir, size):
    path = os.path.join(workdir, "console.log")
    if not os.path.exists(path):
        return ""
    with open(path, "rb") as f:
        return f.read()[-size:].decode(errors="replace")


def read_status(workdir):
    path = os.path.join(workdir, "status")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return f.read().strip()


def scenario_command(args, workdir, guest=False):
    wsgsim = args.guest_wsgsim if guest and args.guest_wsgsim else args.wsgsim
    fingersim = args.guest_fingersim if guest and args.guest_fingersim else args.fingersim
    return [PYTHON, SCENARIO, "--wsgsim", wsgsim, "--fingersim", fingersim,
            "--dbc", args.dbc, "--iface", "vcan0", "--workdir", workdir]


def run_native(args):
    workdir = tempfile.mkdtemp(prefix="wsgsim-vcan-")
    print("vcan: native SocketCAN, work dir %s" % workdir)
    return finish(workdir, subprocess.run(scenario_command(args, workdir)).returncode)


def scenario_started(workdir):
    """Whether the guest got as far as the scenario's first line."""
    path = os.path.join(workdir, "guest.log")
    if not os.path.exists(path):
        return False
    with open(path, errors="replace") as f:
        return "vcan: finger bus on" in f.read()


def run_guest(args, guest, fall_back=False):
    """The scenario's exit status; with fall_back, None when the guest failed
    before the scenario started (it left no status and no scenario line)."""
    try:
        guest.check()
    except GuestError as e:
        print("vcan: FAIL: cannot boot the %s guest: %s" % (guest.name, e))
        return 1
    workdir = tempfile.mkdtemp(prefix="wsgsim-%s-" % guest.name)
    command = scenario_command(args, workdir, guest=True)
    if command[3] != args.wsgsim:
        print("vcan: the guest runs %s (the sanitized build is for native vcan only)" %
              command[3])
    print("vcan: %s, work dir %s" % (guest.describe(), workdir))
    sys.stdout.flush()
    timeout = GUEST_TIMEOUT_S[guest.name]
    try:
        result = guest.boot(workdir, command, timeout)
    except GuestError as e:
        print("vcan: FAIL: cannot boot the %s guest: %s" % (guest.name, e))
        return finish(workdir, 1)
    print("vcan: guest ran %.1f s%s" % (result.seconds, ", killed" if result.timed_out else ""))
    if fall_back and read_status(workdir) is None and not scenario_started(workdir):
        print("vcan: the %s guest failed before the scenario started (%s), logs in %s" %
              (guest.name, last_console_line(workdir), workdir))
        return None
    if result.timed_out:
        print("vcan: FAIL: the %s guest did not end within %d s" % (guest.name, timeout))
    return report_guest(workdir)


def report_guest(workdir):
    log = os.path.join(workdir, "guest.log")
    if os.path.exists(log):
        with open(log) as f:
            sys.stdout.write(f.read())
    status = read_status(workdir)
    if status is None:
        print("vcan: FAIL: the guest left no exit status; console tail:")
        sys.stdout.write(console_tail(workdir, 3000))
        return finish(workdir, 1)
    if status != "0":
        print("vcan: FAIL: scenario exit status %s" % status)
        return finish(workdir, 1)
    return finish(workdir, 0)


def finish(workdir, code):
    """Keeps the logs (candump, wsgsim, fingersim, console) only on failure."""
    if code == 0:
        shutil.rmtree(workdir, ignore_errors=True)
    else:
        print("vcan: logs kept in %s" % workdir)
    return code


def qemu_guest(requested_accel):
    kvm_usable = os.access("/dev/kvm", os.R_OK | os.W_OK)
    accel, why = choose_accel(requested_accel, kvm_usable, lambda: probe(Qemu("kvm")))
    print("vcan: QEMU accelerator %s: %s" % (accel, why))
    return Qemu(accel)


def main():
    parser = argparse.ArgumentParser()
    for name in ("--wsgsim", "--fingersim", "--dbc"):
        parser.add_argument(name, required=True)
    parser.add_argument("--guest-wsgsim", help="wsgsim for a guest kernel (default --wsgsim)")
    parser.add_argument("--guest-fingersim", help="fingersim for a guest kernel")
    parser.add_argument("--backend", choices=("auto", "native", "uml", "qemu"), default="auto")
    parser.add_argument("--qemu-accel", choices=("auto", "kvm", "tcg"), default="auto")
    args = parser.parse_args()
    for tool in ("candump", "cansend"):
        if shutil.which(tool) is None:
            print("vcan: FAIL: %s is missing (install can-utils: make can-deps)" % tool)
            return 1
    backend, why = choose_backend(args.backend, native_vcan, lambda: probe(Uml()))
    if backend is None:
        print("vcan: FAIL: %s" % why)
        return 1
    print("vcan: backend %s: %s" % (backend, why))
    sys.stdout.flush()
    if backend == "native":
        return run_native(args)
    if backend == "uml":
        # after a probe that worked, a guest that still fails before the
        # scenario starts is the backend's failure too: QEMU runs it instead
        code = run_guest(args, Uml(), fall_back=args.backend == "auto")
        if code is not None:
            return code
        print("vcan: backend qemu: user-mode Linux failed although its probe boot worked")
    return run_guest(args, qemu_guest(args.qemu_accel))


if __name__ == "__main__":
    sys.exit(main())
