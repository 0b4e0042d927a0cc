# SPDX-License-Identifier: BSD-3-Clause
"""The installed package as its systemd units run it: the wsgsim binary of
the .deb (make deb), run as an unprivileged user (setpriv to nobody, as
DynamicUser= would) with the command line of the installed unit and its
paths: the configuration in a directory the user cannot write (/etc under
ProtectSystem=strict), the StateDirectory= owned by the user. Every
feature of the web interface works there: Save writes the state
directory, a restart reads it back, the chart library is Debian's
libjs-dygraphs read from its installed files. And the README's service
steps, pasted after the package was installed with dpkg into a root of
its own, work."""
import glob
import os
import pwd
import shlex
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import unittest
import urllib.request

from pkgenv import DEB_DIR, ROOT, TIMEOUT, GclError, run

sys.path.insert(0, os.path.join(ROOT, "tests", "web"))
sys.path.insert(0, os.path.join(ROOT, "tests", "docs"))
from docexamples import commands, read_blocks  # noqa: E402
from webclient import free_port, request  # noqa: E402

USER, GROUP = "nobody", "nogroup"
SETPRIV = ["setpriv", "--reuid=" + USER, "--regid=" + GROUP, "--clear-groups"]
DYGRAPHS = "/usr/share/javascript/dygraphs"
START_ATTEMPTS = 5  # a free port picked here may be taken before wsgsim binds it


def unit_settings(path):
    """The [Service] settings of a unit file, key -> value (last one wins)."""
    settings = {}
    for line in open(path):
        line = line.strip()
        if "=" in line and not line.startswith(("#", ";", "[")):
            key, value = line.split("=", 1)
            settings[key] = value
    return settings


class Service:
    """One unit's wsgsim, its system paths mapped into root (a temporary
    directory): /usr/bin from the unpacked .deb, /etc and /var/lib there.
    wrap runs it (default: setpriv to the unprivileged user)."""

    def __init__(self, package_root, root, unit, instance, wrap=SETPRIV):
        self.root = root
        self.wrap = wrap
        self.settings = unit_settings(os.path.join(package_root, "lib/systemd/system", unit))
        self.maps = {"/usr/bin/": os.path.join(package_root, "usr/bin") + "/",
                     "/etc/": os.path.join(root, "etc") + "/",
                     "/var/lib/": os.path.join(root, "var/lib") + "/"}
        expand = lambda text: text.replace("%i", instance).replace("%S", "/var/lib")  # noqa
        self.argv = []
        for arg in shlex.split(expand(self.settings["ExecStart"])):
            if arg.startswith("$"):  # $NAME: the value split into words, as systemd does
                self.argv += shlex.split(self.environment().get(arg[1:], ""))
            else:
                self.argv.append(self.host_path(arg))
        self.state_dir = self.host_path("/var/lib/" + expand(self.settings["StateDirectory"]))
        name = unit.replace("@", "@" + instance)  # several units may run in one root
        self.run_dir = os.path.join(root, "run", name)
        self.log_path = os.path.join(root, "log." + name)
        self.proc = None

    def host_path(self, path):
        for system, here in self.maps.items():
            if path.startswith(system):
                return here + path[len(system):]
        return path

    def environment(self):
        """The variables of the unit's EnvironmentFile= (-FILE: optional)."""
        path = self.settings.get("EnvironmentFile")
        if path is None:
            return {}
        optional = path.startswith("-")
        path = self.host_path(path.lstrip("-"))
        if optional and not os.path.exists(path):
            return {}
        variables = {}
        for line in open(path):
            line = line.strip()
            if line and not line.startswith("#"):
                key, _, value = line.partition("=")
                variables[key.strip()] = " ".join(shlex.split(value))
        return variables

    def option(self, name):
        return self.argv[self.argv.index(name) + 1] if name in self.argv else None

    def prepare(self, config_text=None, make_etc=True):
        """The directories as systemd leaves them: /etc root's and read-only
        to the user, the state and runtime directories the user's.
        make_etc=False: /etc/wsgsim is the package's (or missing)."""
        nobody = pwd.getpwnam(USER)
        for d in ((os.path.join(self.root, "etc", "wsgsim"),) if make_etc else ()) + \
                (self.state_dir, self.run_dir):
            os.makedirs(d, exist_ok=True)
        for d in (self.state_dir, self.run_dir):
            os.chown(d, nobody.pw_uid, nobody.pw_gid)
        config = self.option("--config")
        if config is not None and config_text is not None:
            with open(config, "w") as f:
                f.write(config_text)

    def log(self):
        with open(self.log_path) as f:
            return f.read()

    def start(self):
        """Starts it; returns the web interface's base URL."""
        ready = os.path.join(self.run_dir, "ready")
        for attempt in range(START_ATTEMPTS):
            http_port = free_port()
            argv = self.wrap + self.argv + [
                "--bind", "127.0.0.1", "--tcp-port", "0", "--udp-port", "0",
                "--binary-udp-port", "0", "--http-port", str(http_port), "--ready-file", ready]
            with open(self.log_path, "w") as log:
                self.proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=log,
                                             stderr=subprocess.STDOUT)
            deadline = time.monotonic() + TIMEOUT
            while time.monotonic() < deadline and self.proc.poll() is None \
                    and not os.path.exists(ready):
                time.sleep(0.05)
            if os.path.exists(ready):
                return "http://127.0.0.1:%d" % http_port
            self.stop()
            if attempt == START_ATTEMPTS - 1 or "Address already in use" not in self.log():
                raise GclError("%s did not start:\n%s" % (shlex.join(argv), self.log()))

    def stop(self):
        """SIGTERM, then its exit status (None when not running)."""
        if self.proc is None:
            return None
        self.proc.terminate()
        try:
            self.proc.wait(timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        code, self.proc = self.proc.returncode, None
        return code


def get_bytes(url):
    with urllib.request.urlopen(url, timeout=TIMEOUT) as reply:
        return reply.read()


class Units(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        os.chmod(cls.tmp.name, 0o755)  # the user reaches the binary and its directories
        cls.package = os.path.join(cls.tmp.name, "package")
        found = glob.glob(os.path.join(DEB_DIR, "wsgsim_*.deb"))
        if len(found) != 1:
            raise AssertionError("expected one wsgsim package in %s (make deb), found %s"
                                 % (DEB_DIR, found))
        subprocess.run(["dpkg-deb", "-x", found[0], cls.package], check=True, timeout=TIMEOUT)
        if shutil.which("setpriv") is None:
            raise AssertionError("setpriv is missing (util-linux): it runs wsgsim as " + USER)
        if os.geteuid() != 0:
            raise AssertionError("these tests run wsgsim as %s with setpriv: run them as root"
                                 % USER)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def setUp(self):
        self.root = tempfile.mkdtemp(dir=self.tmp.name)
        os.chmod(self.root, 0o755)
        self.service = None

    def tearDown(self):
        if self.service is not None:
            self.service.stop()

    def settings(self, base):
        reply = request(base + "/api/devices/0/settings")
        self.assertEqual(reply.status, 200, reply)
        return reply.json()

    def save_and_restart(self, unit, instance, config_text):
        """PUTs new settings, saves them, restarts: returns (service, saved
        file's text, settings after the restart)."""
        service = self.service = Service(self.package, self.root, unit, instance)
        self.assertEqual(service.settings.get("DynamicUser"), "yes")
        self.assertEqual(service.settings.get("ProtectSystem"), "strict")
        service.prepare(config_text)
        base = service.start()
        change = {"force_n": 33.5, "tag": "saved by the page"}
        reply = request(base + "/api/devices/0/settings", "PUT", change)
        self.assertEqual(reply.status, 200, reply)
        reply = request(base + "/api/devices/0/settings/save", "POST", {})
        self.assertEqual(reply.status, 200, reply)
        self.assertTrue(reply.json()["saved"])
        save_file = service.option("--save-file")
        self.assertEqual(reply.json()["save_file"], save_file)
        self.assertEqual(os.path.dirname(save_file), service.state_dir,
                         "the unit saves into its own StateDirectory")
        self.assertEqual(os.listdir(service.state_dir), ["saved.ini"], "no temporary left")
        self.assertEqual(os.stat(save_file).st_uid, pwd.getpwnam(USER).pw_uid)
        self.assertEqual(service.stop(), 0, service.log())
        saved = open(save_file).read()
        return service, saved, self.settings(service.start())

    def test_instance_saves_to_its_state_directory(self):
        config_text = '[device]\ntag = "left"\n[motion]\ndefault_force = 20\ndefault_speed = 50\n'
        service, saved, after = self.save_and_restart("wsgsim@.service", "left", config_text)
        config = service.option("--config")
        self.assertEqual(open(config).read(), config_text, "the configuration is not written")
        self.assertIn("default_force = 33.5\n", saved)
        self.assertIn('tag = "saved by the page"\n', saved)
        self.assertEqual((after["force_n"], after["tag"]), (33.5, "saved by the page"))
        self.assertEqual(after["speed_mm_s"], 50, "the configuration's other settings stay")
        self.assertEqual(after["config_file"], config)

    def test_plain_unit_saves_to_its_state_directory(self):
        _, saved, after = self.save_and_restart("wsgsim.service", "", None)
        self.assertIn("default_force = 33.5\n", saved)
        self.assertEqual((after["force_n"], after["tag"]), (33.5, "saved by the page"))
        self.assertIsNone(after["config_file"])

    def test_configuration_directory_is_not_writable_by_the_user(self):
        """What makes the state directory necessary: the test's /etc, like
        the unit's, refuses the user (else the tests above prove nothing)."""
        service = self.service = Service(self.package, self.root, "wsgsim@.service", "left")
        service.prepare("")
        etc = os.path.dirname(service.option("--config"))
        result = run(SETPRIV + ["sh", "-c", 'touch "$1/probe"', "sh", etc])
        self.assertNotEqual(result.returncode, 0)
        self.assertIn("Permission denied", result.stderr)

    def test_chart_library_is_debians_installed_file(self):
        service = self.service = Service(self.package, self.root, "wsgsim.service", "")
        service.prepare()
        base = service.start()
        for name in ("dygraph.min.js", "dygraph.min.css"):
            with self.subTest(file=name):
                reply = get_bytes(base + "/static/" + name)
                with open(os.path.join(DYGRAPHS, name), "rb") as f:
                    self.assertEqual(reply, f.read())
        # and not a copy built into the binary
        with open(os.path.join(DYGRAPHS, "dygraph.min.js"), "rb") as f:
            library = f.read()
        with open(service.argv[0], "rb") as f:
            binary = f.read()
        for at in range(0, len(library) - 64, len(library) // 8):
            self.assertFalse(library[at:at + 64] in binary,
                             "the binary holds dygraph.min.js's bytes at %d" % at)

    def test_chart_library_is_read_from_its_path_at_run_time(self):
        """In a mount namespace whose /usr/share/javascript/dygraphs holds
        another file, the installed wsgsim serves that file."""
        other = os.path.join(self.root, "dygraphs")
        os.makedirs(other)
        os.chmod(other, 0o755)
        marker = b"/* not dygraphs: proves the file is read from its path */\n"
        with open(os.path.join(other, "dygraph.min.js"), "wb") as f:
            f.write(marker)
        bind = ["unshare", "--mount", "sh", "-c", 'mount --bind "$0" %s && exec "$@"' % DYGRAPHS,
                other]  # then setpriv: the bind mount needs root
        service = self.service = Service(self.package, self.root, "wsgsim.service", "",
                                         wrap=bind + SETPRIV)
        service.prepare()
        base = service.start()
        self.assertEqual(get_bytes(base + "/static/dygraph.min.js"), marker)
        missing = request(base + "/static/dygraph.min.css")
        self.assertEqual((missing.status, missing.json()["error"]), (404, "E_NOT_AVAILABLE"))
        self.assertIn("install libjs-dygraphs", missing.json()["message"])


def install_into(root, deb):
    """dpkg -i into a root of its own: a dpkg database there, the
    maintainer scripts run with DPKG_ROOT (the package's dependencies are
    this machine's, not the root's)."""
    for d in ("info", "updates", "triggers"):
        os.makedirs(os.path.join(root, "var/lib/dpkg", d))
    open(os.path.join(root, "var/lib/dpkg/status"), "w").close()
    result = run(["dpkg", "--root=" + root, "--force-script-chrootless", "--force-depends",
                  "-i", deb])
    if result.returncode != 0:
        raise AssertionError("dpkg -i %s failed:\n%s%s" % (deb, result.stdout, result.stderr))


def gcl_lines(service, sent, count):
    """The first count lines a running service's GCL port answers to sent."""
    with open(os.path.join(service.run_dir, "ready")) as f:
        ready = dict(line.strip().split("=", 1) for line in f if "=" in line)
    with socket.create_connection(("127.0.0.1", int(ready["tcp_port"])), timeout=TIMEOUT) as s:
        s.sendall(sent)
        received = b""
        while received.count(b"\n") < count:
            data = s.recv(4096)
            if not data:
                break
            received += data
    return received.decode().splitlines()[:count]


def readme_service_steps():
    """The commands of README.md's block that sets up the services."""
    for block in read_blocks("README.md"):
        if "systemctl enable --now wsgsim@" in block.text:
            return commands(block.text)
    raise AssertionError("README.md has no block that enables wsgsim@NAME")


class InstalledPackage(unittest.TestCase):
    """The .deb installed into a root of its own with dpkg, the README's
    service steps pasted there: each command as a reader runs it, its
    system paths in that root (sudo left out; systemctl --root enables,
    and the unit is started as Service runs it; sudoedit is the test
    editing the file)."""

    @classmethod
    def setUpClass(cls):
        if os.geteuid() != 0:
            raise AssertionError("dpkg --root and setpriv need root: run these tests as root")
        cls.tmp = tempfile.TemporaryDirectory()
        os.chmod(cls.tmp.name, 0o755)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def setUp(self):
        self.root = tempfile.mkdtemp(dir=self.tmp.name)
        os.chmod(self.root, 0o755)
        found = glob.glob(os.path.join(DEB_DIR, "wsgsim_*.deb"))
        self.assertEqual(len(found), 1, "expected one wsgsim package in %s (make deb)" % DEB_DIR)
        install_into(self.root, found[0])
        self.services = {}
        self.addCleanup(lambda: [service.stop() for service in self.services.values()])

    def path(self, system_path):
        return os.path.join(self.root, system_path.lstrip("/"))

    def test_configuration_files_are_the_packages(self):
        self.assertTrue(os.path.isdir(self.path("/etc/wsgsim")))
        conffiles = run(["dpkg-query", "--admindir=" + self.path("/var/lib/dpkg"), "-W",
                         "-f=${Conffiles}", "wsgsim"]).stdout
        self.assertIn("/etc/default/wsgsim ", conffiles, "kept across upgrades: a conffile")
        service = Service(self.root, self.root, "wsgsim.service", "")
        self.assertEqual(service.environment(), {"WSGSIM_OPTIONS": ""})
        self.assertTrue(os.path.isfile(self.path("/usr/share/doc/wsgsim/examples/"
                                                 "wsgsim.example.ini")))

    def test_options_in_etc_default_reach_the_service(self):
        with open(self.path("/etc/default/wsgsim"), "a") as f:
            f.write("WSGSIM_OPTIONS=\"--model 'WSG 50-210' --part 40\"\n")
        service = self.start("wsgsim")
        self.assertIn("virtual WSG 50-210 ready", service.log())

    def start(self, unit_name):
        """systemctl start UNIT as systemd would run it (Service)."""
        template, _, instance = unit_name.partition("@")
        unit = template + ("@.service" if "@" in unit_name else ".service")
        service = Service(self.root, self.root, unit, instance)
        service.prepare(make_etc=False)
        service.start()
        self.services[unit_name] = service
        return service

    def test_readme_service_steps_work_when_pasted(self):
        steps = readme_service_steps()
        done = []
        for step in steps:
            words = shlex.split(step, comments=True)
            if words[0] == "sudo":
                words = words[1:]
            with self.subTest(step=step):
                self.run_step(words)
                done.append(words[0])
        self.assertEqual(sorted(set(done)), ["cp", "journalctl", "sudoedit", "systemctl"])
        self.assertEqual(sorted(self.services), ["wsgsim", "wsgsim@left"])
        for name, service in self.services.items():
            with self.subTest(serves=name):
                self.assertEqual(gcl_lines(service, b"GRIPSTATE?\nBYE()\n", 2),
                                 ["GRIPSTATE=0", "ACK BYE"])

    def run_step(self, words):
        if words[:3] == ["systemctl", "enable", "--now"]:
            result = run(["systemctl", "--root=" + self.root, "enable", words[3]])
            self.assertEqual(result.returncode, 0, result.stderr)
            self.start(words[3])
        elif words[0] == "cp":
            shutil.copy(self.path(words[1]), self.path(words[2]))
        elif words[0] == "sudoedit":  # the reader gives the instance ports of its own
            with open(self.path(words[1])) as f:
                text = f.read()
            self.assertIn("\ntcp_port = 1000\n", text)
            with open(self.path(words[1]), "w") as f:
                f.write(text.replace("\ntcp_port = 1000\n", "\ntcp_port = 11000\n"))
        elif words[:2] == ["journalctl", "-u"]:
            self.assertIn(" ready: ", self.services[words[2]].log())
        else:
            raise AssertionError("README.md's service steps hold %s, which this test cannot "
                                 "run: teach it" % shlex.join(words))


if __name__ == "__main__":
    unittest.main()
