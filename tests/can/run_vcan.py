#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs tests/can/vcan_scenario.py on a real vcan0: natively where this
kernel has SocketCAN and vcan0 exists or can be created, otherwise inside a
user-mode Linux kernel (Debian's user-mode-linux) booted with the host's
filesystem as its root. Never skips: when neither way works it fails and
says why.

usage: run_vcan.py --wsgsim BIN --fingersim BIN --dbc FILE [--uml | --native]
"""
import argparse
import glob
import os
import shlex
import shutil
import socket
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SCENARIO = os.path.join(HERE, "vcan_scenario.py")
PYTHON = "/usr/bin/python3"  # Debian's, which has python3-canmatrix
UML_TIMEOUT_S = 900  # against a hang only: up to three runs of the scenario


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


def scenario_command(args, workdir, uml=False):
    wsgsim = args.uml_wsgsim if uml and args.uml_wsgsim else args.wsgsim
    fingersim = args.uml_fingersim if uml and args.uml_fingersim else args.fingersim
    return [PYTHON, SCENARIO, "--wsgsim", wsgsim, "--fingersim", fingersim,
            "--dbc", args.dbc, "--iface", "vcan0", "--workdir", workdir]


def run_native(args):
    workdir = tempfile.mkdtemp(prefix="wsgsim-vcan-")
    print("vcan: native SocketCAN, work dir %s" % workdir)
    return finish(workdir, subprocess.run(scenario_command(args, workdir)).returncode)


def uml_modules():
    dirs = sorted(glob.glob("/usr/lib/uml/modules/*/kernel/drivers/net/can/vcan.ko"))
    return os.path.dirname(dirs[-1]).rsplit("/kernel/", 1)[0] if dirs else None


def write_init(workdir, modules, command):
    with open(os.path.join(HERE, "uml_init.sh")) as f:
        text = f.read()
    text = text.replace("@WORKDIR@", workdir).replace("@MODULES@", modules)
    text = text.replace("@COMMAND@", " ".join(shlex.quote(a) for a in command))
    path = os.path.join(workdir, "init.sh")
    with open(path, "w") as f:
        f.write(text)
    os.chmod(path, 0o755)
    return path


def run_uml(args):
    kernel = shutil.which("linux.uml") or shutil.which("linux")
    modules = uml_modules()
    if kernel is None or modules is None:
        print("vcan: FAIL: no SocketCAN here and no user-mode Linux kernel with vcan.ko "
              "(install user-mode-linux: make can-deps)")
        return 1
    workdir = tempfile.mkdtemp(prefix="wsgsim-uml-")
    command = scenario_command(args, workdir, uml=True)
    if command[3] != args.wsgsim:
        print("vcan: the guest runs %s: ASan cannot map its shadow memory in UML" % command[3])
    init = write_init(workdir, modules, command)
    cmd = [kernel, "mem=384M", "rootfstype=hostfs", "rootflags=/", "rw", "init=" + init,
           "con=null", "con0=fd:0,fd:1"]
    print("vcan: user-mode Linux %s, work dir %s" % (os.path.basename(modules), workdir))
    sys.stdout.flush()
    started = time.monotonic()
    with open(os.path.join(workdir, "console.log"), "wb") as console:
        try:
            subprocess.run(cmd, stdin=subprocess.DEVNULL, stdout=console, stderr=console,
                           timeout=UML_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            print("vcan: FAIL: the UML guest did not halt within %d s" % UML_TIMEOUT_S)
    print("vcan: guest ran %.1f s" % (time.monotonic() - started))
    return report_guest(workdir)


def report_guest(workdir):
    log = os.path.join(workdir, "guest.log")
    if os.path.exists(log):
        with open(log) as f:
            sys.stdout.write(f.read())
    status_path = os.path.join(workdir, "status")
    if not os.path.exists(status_path):
        print("vcan: FAIL: the guest left no exit status; console tail:")
        with open(os.path.join(workdir, "console.log"), "rb") as f:
            sys.stdout.write(f.read()[-3000:].decode(errors="replace"))
        return 1
    with open(status_path) as f:
        status = f.read().strip()
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


def main():
    parser = argparse.ArgumentParser()
    for name in ("--wsgsim", "--fingersim", "--dbc"):
        parser.add_argument(name, required=True)
    parser.add_argument("--uml-wsgsim", help="wsgsim for the UML guest (default --wsgsim)")
    parser.add_argument("--uml-fingersim", help="fingersim for the UML guest")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--uml", action="store_true", help="always use user-mode Linux")
    mode.add_argument("--native", action="store_true", help="never use user-mode Linux")
    args = parser.parse_args()
    for tool in ("candump", "cansend"):
        if shutil.which(tool) is None:
            print("vcan: FAIL: %s is missing (install can-utils: make can-deps)" % tool)
            return 1
    ok, why = (False, "--uml given") if args.uml else native_vcan()
    if ok:
        return run_native(args)
    if args.native:
        print("vcan: FAIL: no native vcan0: %s" % why)
        return 1
    print("vcan: no native vcan0 (%s); booting user-mode Linux" % why)
    return run_uml(args)


if __name__ == "__main__":
    sys.exit(main())
