# SPDX-License-Identifier: BSD-3-Clause
"""The two kernels run_vcan.py runs the vcan scenario in when this kernel
has no SocketCAN: Debian's user-mode Linux (linux.uml, the host's
filesystem as its root through hostfs) and Debian's own kernel
(linux-image-amd64) in QEMU system emulation, booted with a small initramfs
that mounts the host's filesystem read-only through 9p. Both run
guest_init.sh, which leaves the command's exit status in the work dir.

A guest is booted by boot(workdir, command, timeout): the result says how
long it ran and whether it had to be killed; the work dir then holds
guest.log, status (when the guest got that far) and console.log.
"""
import glob
import gzip
import lzma
import os
import re
import shlex
import shutil
import signal
import subprocess
import time

HERE = os.path.dirname(os.path.abspath(__file__))
# The checkout (the scenario, the binaries, the DBC): shared with the QEMU
# guest on its own, since the guest's /tmp is a tmpfs over the host's and a
# checkout may be there.
CHECKOUT = os.path.dirname(os.path.dirname(HERE))
# What the initramfs loads to mount the host's filesystem (their own
# dependencies come from modules.dep).
NINEP_MODULES = ("virtio_pci", "9pnet_virtio", "9p")
QEMU_MEMORY = "512M"


class BootResult:
    def __init__(self, seconds, timed_out):
        self.seconds = seconds
        self.timed_out = timed_out


class GuestError(Exception):
    """The guest cannot be booted at all (a kernel or a file is missing)."""


def write_init(workdir, modules, command):
    """guest_init.sh for this run, as workdir/init.sh."""
    with open(os.path.join(HERE, "guest_init.sh")) as f:
        text = f.read()
    text = text.replace("@WORKDIR@", workdir).replace("@MODULES@", modules)
    text = text.replace("@COMMAND@", " ".join(shlex.quote(a) for a in command))
    path = os.path.join(workdir, "init.sh")
    with open(path, "w") as f:
        f.write(text)
    os.chmod(path, 0o755)
    return path


def run_bounded(cmd, workdir, timeout):
    """Runs cmd with its output in workdir/console.log, killed after timeout s
    with every process it started (user-mode Linux runs its guest's
    processes as host processes)."""
    started = time.monotonic()
    timed_out = False
    with open(os.path.join(workdir, "console.log"), "ab") as console:
        proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=console, stderr=console,
                                start_new_session=True)
        try:
            proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            timed_out = True
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    return BootResult(time.monotonic() - started, timed_out)


class Uml:
    name = "uml"

    def __init__(self):
        self.kernel = shutil.which("linux.uml") or shutil.which("linux")
        found = sorted(glob.glob("/usr/lib/uml/modules/*/kernel/drivers/net/can/vcan.ko*"),
                       key=version_key)
        self.modules = found[-1].rsplit("/kernel/", 1)[0] if found else None

    def check(self):
        if self.kernel is None or self.modules is None:
            raise GuestError("no user-mode Linux kernel with vcan.ko "
                             "(install user-mode-linux: make can-deps)")

    def describe(self):
        return "user-mode Linux %s" % os.path.basename(self.modules)

    def boot(self, workdir, command, timeout):
        self.check()
        init = write_init(workdir, self.modules, command)
        cmd = [self.kernel, "mem=384M", "rootfstype=hostfs", "rootflags=/", "rw",
               "init=" + init, "con=null", "con0=fd:0,fd:1"]
        return run_bounded(cmd, workdir, timeout)


def version_key(name):
    """Sorts 6.1.0-9-amd64 before 6.1.0-56-amd64."""
    return [int(part) if part.isdigit() else part for part in re.split(r"(\d+)", name)]


def module_tree():
    """(kernel image, module dir) of the newest installed Debian kernel whose
    modules include vcan, or (None, None)."""
    for moddir in sorted(glob.glob("/lib/modules/*"), key=version_key, reverse=True):
        image = "/boot/vmlinuz-" + os.path.basename(moddir)
        if (os.path.exists(image) and os.path.exists(moddir + "/modules.dep")
                and glob.glob(moddir + "/kernel/drivers/net/can/vcan.ko*")):
            return image, moddir
    return None, None


def modules_in_order(moddir, wanted):
    """Paths (relative to moddir) of wanted and their dependencies, each
    after the ones it needs, from moddir/modules.dep."""
    deps = {}
    with open(os.path.join(moddir, "modules.dep")) as f:
        for line in f:
            path, _, needs = line.partition(":")
            deps[path] = needs.split()
    by_name = {}
    for path in deps:
        name = os.path.basename(path).split(".ko")[0]
        by_name[name.replace("-", "_")] = path
    ordered = []

    def add(path):
        if path in ordered:
            return
        for need in reversed(deps.get(path, [])):  # modules.dep lists the last needed first
            add(need)
        ordered.append(path)

    for name in wanted:
        path = by_name.get(name.replace("-", "_"))
        if path is None:
            raise GuestError("the kernel in %s has no module %s" % (moddir, name))
        add(path)
    return ordered


def module_bytes(path):
    """A module's ELF image: busybox insmod loads .ko only."""
    if path.endswith(".ko"):
        with open(path, "rb") as f:
            return f.read()
    if path.endswith(".ko.xz"):
        with lzma.open(path) as f:
            return f.read()
    raise GuestError("cannot decompress %s (only .ko and .ko.xz are handled)" % path)


def cpio_newc(entries):
    """A cpio archive (newc) of (name, mode, data) entries; directories have
    data None."""
    out = bytearray()

    def pad():
        out.extend(b"\0" * (-len(out) % 4))

    for number, (name, mode, data) in enumerate(entries + [("TRAILER!!!", 0, b"")], 1):
        data = data or b""
        fields = [number, mode, 0, 0, 1, 0, len(data), 0, 0, 0, 0, len(name) + 1, 0]
        out.extend(b"070701" + b"".join(b"%08X" % v for v in fields))
        out.extend(name.encode() + b"\0")
        pad()
        out.extend(data)
        pad()
    return bytes(out)


def static_busybox():
    path = shutil.which("busybox") or "/bin/busybox"
    if not os.path.exists(path):
        raise GuestError("no busybox (install busybox-static: make can-deps)")
    ldd = subprocess.run(["ldd", path], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         universal_newlines=True)
    if "not a dynamic executable" not in ldd.stdout:
        raise GuestError("%s is not statically linked (install busybox-static)" % path)
    return path


class Qemu:
    name = "qemu"

    def __init__(self, accel="tcg"):
        self.accel = accel
        self.binary = shutil.which("qemu-system-x86_64")
        self.kernel, self.moddir = module_tree()

    def check(self):
        if os.uname().machine != "x86_64":
            raise GuestError("the QEMU guest is built for x86_64 hosts only (this is %s)" %
                             os.uname().machine)
        if self.binary is None:
            raise GuestError("no qemu-system-x86_64 (install qemu-system-x86: make can-deps)")
        if self.kernel is None:
            raise GuestError("no Debian kernel with vcan.ko in /boot and /lib/modules "
                             "(install linux-image-amd64: make can-deps)")

    def describe(self):
        return "QEMU (%s), Debian's kernel %s" % (self.accel, os.path.basename(self.moddir))

    def initramfs(self, workdir):
        """workdir/initramfs.gz: busybox, the 9p modules and /init."""
        with open(os.path.join(HERE, "qemu_init.sh")) as f:
            init = f.read().replace("@WORKDIR@", workdir).replace("@CHECKOUT@", CHECKOUT)
            init = init.encode()
        with open(static_busybox(), "rb") as f:
            busybox = f.read()
        entries = [(d, 0o40755, None) for d in ("bin", "dev", "proc", "sys", "modules",
                                                "newroot")]
        entries += [("bin/busybox", 0o100755, busybox), ("init", 0o100755, init)]
        order = []
        for rel in modules_in_order(self.moddir, NINEP_MODULES):
            name = os.path.basename(rel).split(".ko")[0] + ".ko"
            entries.append(("modules/" + name, 0o100644,
                            module_bytes(os.path.join(self.moddir, rel))))
            order.append(name)
        entries.append(("modules/order", 0o100644, ("\n".join(order) + "\n").encode()))
        path = os.path.join(workdir, "initramfs.gz")
        with gzip.open(path, "wb", compresslevel=1) as f:
            f.write(cpio_newc(entries))
        return path

    def command(self, workdir):
        cmd = [self.binary, "-accel", self.accel, "-m", QEMU_MEMORY, "-smp", "2",
               "-nographic", "-no-reboot", "-nic", "none",
               "-kernel", self.kernel, "-initrd", self.initramfs(workdir),
               "-append", "console=ttyS0 panic=-1 quiet",
               "-virtfs", "local,path=/,mount_tag=hostroot,security_model=none,"
                          "readonly=on,multidevs=remap",
               "-virtfs", "local,path=%s,mount_tag=checkout,security_model=none,readonly=on"
                          % CHECKOUT,
               "-virtfs", "local,path=%s,mount_tag=work,security_model=none" % workdir]
        if self.accel == "kvm":
            cmd += ["-cpu", "host"]
        return cmd

    def boot(self, workdir, command, timeout):
        self.check()
        write_init(workdir, self.moddir, command)
        return run_bounded(self.command(workdir), workdir, timeout)
