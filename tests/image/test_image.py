# SPDX-License-Identifier: BSD-3-Clause
"""The OCI image (make image): its configuration, read by skopeo as
podman and docker would read it, its packages, and wsgsim
run from its root filesystem as a container runtime would run it (its
entry point as PID 1 of new mount and PID namespaces, chrooted; these
machines cannot start containers) holding a GCL exchange, saving its
settings into the image's volume and serving the page with the image's
libjs-dygraphs."""
import json
import os
import shlex
import signal
import subprocess
import sys
import tarfile
import tempfile
import time
import unittest
import urllib.request

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, os.path.join(ROOT, "tests", "web"))

from wsgsim import GclTcp  # noqa: E402
from webclient import free_port, request  # noqa: E402

IMAGE = os.environ.get("IMAGE", os.path.join(ROOT, "build", "image", "wsgsim-oci.tar"))
VERSION = os.environ.get("IMAGE_VERSION", "")
TIMEOUT = 120  # an upper bound against hangs only
ENTRYPOINT = ["/usr/bin/wsgsim", "--save-file", "/var/lib/wsgsim/saved.ini"]
START_ATTEMPTS = 5  # a free port picked here may be taken before wsgsim binds it


def blob(layout, digest):
    algorithm, value = digest.split(":", 1)
    with open(os.path.join(layout, "blobs", algorithm, value)) as f:
        return json.load(f)


class Image(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not os.path.isfile(IMAGE):
            raise AssertionError("%s is missing: run make image" % IMAGE)
        if os.geteuid() != 0:
            raise AssertionError("the image tests unpack and chroot into the image: run as root")
        cls.tmp = tempfile.TemporaryDirectory()
        layout = os.path.join(cls.tmp.name, "layout")
        with tarfile.open(IMAGE) as archive:
            archive.extractall(layout)
        with open(os.path.join(layout, "index.json")) as f:
            manifests = json.load(f)["manifests"]
        if len(manifests) != 1:
            raise AssertionError("expected one image in %s, found %d" % (IMAGE, len(manifests)))
        cls.ref = manifests[0]["annotations"]["org.opencontainers.image.ref.name"]
        cls.config = blob(layout, blob(layout, manifests[0]["digest"])["config"]["digest"])
        bundle = os.path.join(cls.tmp.name, "bundle")
        subprocess.run(["umoci", "unpack", "--image", "%s:%s" % (layout, cls.ref), bundle],
                       check=True, capture_output=True, timeout=TIMEOUT)
        cls.rootfs = os.path.join(bundle, "rootfs")
        with open(os.path.join(bundle, "config.json")) as f:
            cls.runtime = json.load(f)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def in_rootfs(self, path):
        return os.path.join(self.rootfs, path.lstrip("/"))

    def test_configuration(self):
        config = self.config["config"]
        self.assertEqual(config["Entrypoint"], ENTRYPOINT)
        self.assertFalse(config.get("Cmd"), "arguments given to the container follow the entry")
        self.assertLessEqual({"1000/tcp", "1000/udp", "1500/udp", "8080/tcp"},
                             set(config["ExposedPorts"]))
        self.assertIn("/var/lib/wsgsim", config["Volumes"])
        self.assertEqual(self.runtime["process"]["args"], ENTRYPOINT)
        self.assertEqual(self.ref, VERSION)
        self.assertEqual(config["Labels"]["org.opencontainers.image.version"], VERSION)

    def test_container_tools_read_the_archive(self):
        """skopeo (containers/image, podman's library) reads the archive and
        converts it to the archive docker load takes."""
        result = subprocess.run(["skopeo", "inspect", "--config", "oci-archive:" + IMAGE],
                                capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(json.loads(result.stdout)["config"]["Entrypoint"], ENTRYPOINT)
        docker = os.path.join(self.tmp.name, "docker.tar")
        result = subprocess.run(["skopeo", "copy", "--quiet", "oci-archive:" + IMAGE,
                                 "docker-archive:%s:wsgsim:%s" % (docker, VERSION)],
                                capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(result.returncode, 0, result.stderr)
        with tarfile.open(docker) as archive:
            manifest = json.load(archive.extractfile("manifest.json"))
        self.assertEqual(manifest[0]["RepoTags"], ["docker.io/library/wsgsim:" + VERSION])

    def test_installed_from_the_package(self):
        with open(self.in_rootfs("/var/lib/dpkg/status")) as f:
            status = f.read()
        for package in ("wsgsim", "libjs-dygraphs", "python3", "apt"):
            self.assertIn("Package: %s\nStatus: install ok installed\n" % package, status)
        self.assertIn("Version: %s\n" % VERSION,
                      status.split("Package: wsgsim\n", 1)[1].split("\n\n", 1)[0])
        for path in ("/usr/share/doc/wsgsim/copyright", "/usr/share/doc/libjs-dygraphs/copyright",
                     "/var/lib/wsgsim"):
            self.assertTrue(os.path.exists(self.in_rootfs(path)), path)

    def start(self, extra):
        """The entry point as PID 1 in the root filesystem; returns the
        unshare process, the ready file's keys and the web's base URL."""
        ready = self.in_rootfs("/run/wsgsim-ready")
        for attempt in range(START_ATTEMPTS):
            http_port = free_port()
            argv = ["unshare", "--mount", "--pid", "--fork", "--kill-child",
                    "--mount-proc=" + self.in_rootfs("/proc"), "chroot", self.rootfs] + \
                self.runtime["process"]["args"] + extra + [
                    "--bind", "127.0.0.1", "--tcp-port", "0", "--udp-port", "0",
                    "--binary-udp-port", "0", "--http-port", str(http_port),
                    "--ready-file", "/run/wsgsim-ready"]
            log = tempfile.TemporaryFile(mode="w+")
            proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=log,
                                    stderr=subprocess.STDOUT)
            deadline = time.monotonic() + TIMEOUT
            while time.monotonic() < deadline and proc.poll() is None \
                    and not os.path.exists(ready):
                time.sleep(0.05)
            if os.path.exists(ready):
                with open(ready) as f:
                    keys = dict(line.rstrip("\n").split("=", 1) for line in f if "=" in line)
                return proc, keys, "http://127.0.0.1:%d" % http_port, log
            stop(proc)
            log.seek(0)
            text = log.read()
            if attempt == START_ATTEMPTS - 1 or "Address already in use" not in text:
                raise AssertionError("%s did not start:\n%s" % (shlex.join(argv), text))

    def test_runs_holds_a_gcl_exchange_saves_and_serves_its_page(self):
        proc, ready, base, log = self.start([])
        try:
            self.assertEqual(ready["pid"], "1", "the entry point is the namespace's PID 1")
            with GclTcp("127.0.0.1", int(ready["tcp_port"]), TIMEOUT) as gcl:
                self.assertEqual(gcl.command("GRIPSTATE?"), "GRIPSTATE=0")
                gcl.long_command("HOME()", "HOME")
                self.assertEqual(gcl.command("BYE()"), "ACK BYE")
            reply = request(base + "/api/devices/0/settings", "PUT", {"force_n": 41})
            self.assertEqual(reply.status, 200, reply)
            reply = request(base + "/api/devices/0/settings/save", "POST", {})
            self.assertEqual(reply.status, 200, reply)
            with open(self.in_rootfs("/var/lib/wsgsim/saved.ini")) as f:
                self.assertIn("default_force = 41\n", f.read())
            with urllib.request.urlopen(base + "/static/dygraph.min.js", timeout=TIMEOUT) as r:
                served = r.read()
            with open(self.in_rootfs("/usr/share/javascript/dygraphs/dygraph.min.js"), "rb") as f:
                self.assertEqual(served, f.read(), "the image's libjs-dygraphs")
        finally:
            code = stop(proc)
            log.seek(0)
            text = log.read()
            log.close()
        self.assertEqual(code, 0, "SIGTERM to PID 1 (a container stop) ends it cleanly:\n" + text)


def stop(proc):
    """SIGTERM to the namespace's PID 1 (what a container stop sends), then
    unshare's exit status, which is its child's."""
    try:
        with open("/proc/%d/task/%d/children" % (proc.pid, proc.pid)) as f:
            children = [int(pid) for pid in f.read().split()]
    except FileNotFoundError:
        children = []
    for child in children:
        os.kill(child, signal.SIGTERM)
    try:
        return proc.wait(timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        proc.kill()
        return proc.wait()


if __name__ == "__main__":
    unittest.main()
