# SPDX-License-Identifier: BSD-3-Clause
"""make install DESTDIR=... gives a tree that runs; make uninstall removes
it; the units name the installed paths and pass systemd-analyze verify."""
import os
import re
import shutil
import subprocess
import tempfile
import unittest

from pkgenv import PROGRAMS, ROOT, TIMEOUT, gcl_exchange, man_named_files, run

UNITS = ("wsgsim.service", "wsgsim@.service")


def make(build, *args):
    """make in the source tree with the build directory build, as the
    calling make was run (SAN=1 ...) but without its job server, whose
    descriptors are not passed on."""
    env = dict(os.environ)
    env["MAKEFLAGS"] = re.sub(r"--jobserver-\S+|-j\d*", "", env.get("MAKEFLAGS", ""))
    env.pop("MFLAGS", None)
    result = subprocess.run(["make", "-s", "--no-print-directory", "-j%d" % (os.cpu_count() or 1),
                             "-C", ROOT, "BUILD=" + build] + list(args),
                            capture_output=True, text=True, timeout=TIMEOUT * 5, env=env)
    if result.returncode != 0:
        raise AssertionError("make %s failed:\n%s%s" % (" ".join(args), result.stdout,
                                                         result.stderr))
    return result


def files_under(root):
    return sorted(os.path.relpath(os.path.join(d, f), root)
                  for d, _, names in os.walk(root) for f in names)


class Install(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        # A build directory of this class's own: the programs name the
        # installed paths (compiled in), so an install under another prefix
        # builds them again, which must not touch build/, whose programs the
        # suites running beside this one use.
        cls.build = tempfile.mkdtemp(prefix="install-", dir=os.path.join(ROOT, "build"))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.build, ignore_errors=True)

    def make(self, *args):
        return make(self.build, *args)

    def setUp(self):
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        self.tmp = tmp.name

    def test_destdir_tree_runs_and_uninstalls(self):
        self.make("install", "DESTDIR=" + self.tmp, "PREFIX=/usr")
        files = files_under(self.tmp)
        for name in ("wsgbin", "wsgcalib", "wsgfit", "wsgcheck"):
            self.assertEqual(os.readlink(os.path.join(self.tmp, "usr/bin", name)),
                             "../share/wsgsim/" + name, "relative, so the tree runs where it lies")
        for name in PROGRAMS:
            self.assertIn("usr/bin/" + name, files)
            self.assertIn("usr/share/man/man1/%s.1" % name, files)
        for expected in ("usr/lib/systemd/system/wsgsim.service",
                         "usr/lib/systemd/system/wsgsim@.service",
                         "usr/share/doc/wsgsim/examples/wsgsim.example.ini",
                         "usr/share/doc/wsgsim/README.md", "usr/share/doc/wsgsim/simctl.md",
                         "usr/share/doc/wsgsim/testing-your-driver.md",
                         "usr/share/wsgsim/finger-bus.dbc", "usr/share/wsgsim/wsgbinproto.py",
                         "usr/share/wsgsim/timing/wsg50.ini",
                         "usr/share/wsgsim/physics/wsg-gripper.xml",
                         "usr/share/wsgsim/physics/default-scene.xml",
                         "usr/share/doc/wsgsim/physics.md",
                         "usr/share/wsgsim/wsgtwin.py", "usr/share/doc/wsgsim/calibration.md"):
            self.assertIn(expected, files)
        bindir = os.path.join(self.tmp, "usr", "bin")
        for name in PROGRAMS:
            with self.subTest(program=name):
                result = run([os.path.join(bindir, name), "--version"])
                self.assertEqual(result.returncode, 0, result.stderr)
                self.assertTrue(result.stdout.startswith(name + " "))
        replies = gcl_exchange(os.path.join(bindir, "wsgsim"))
        self.assertEqual(replies[0], "GRIPSTATE=0")
        self.assertEqual(replies[2:], ["FIN HOME", "ACK BYE"])
        for name in PROGRAMS:
            page = os.path.join(self.tmp, "usr/share/man/man1", name + ".1")
            for path in man_named_files(page):
                self.assertIn(path.lstrip("/"), files, "%s(1) names %s" % (name, path))
        unit = open(os.path.join(self.tmp, "usr/lib/systemd/system/wsgsim@.service")).read()
        self.assertIn("ExecStart=/usr/bin/wsgsim --config /etc/wsgsim/%i.ini", unit)
        self.make("uninstall", "DESTDIR=" + self.tmp, "PREFIX=/usr")
        self.assertEqual(files_under(self.tmp), [], "uninstall left files behind")

    def test_install_says_how_to_get_the_python_package(self):
        result = self.make("install", "DESTDIR=" + self.tmp, "PREFIX=/usr")
        self.assertIn("python3-wsgsim", result.stdout)
        self.assertIn("PYTHONPATH=" + os.path.join(ROOT, "python"), result.stdout)

    def test_default_prefix_is_usr_local(self):
        self.make("install", "DESTDIR=" + self.tmp)
        unit = open(os.path.join(self.tmp, "usr/local/lib/systemd/system/wsgsim.service")).read()
        self.assertIn("ExecStart=/usr/local/bin/wsgsim --save-file %S/wsgsim/saved.ini "
                      "$WSGSIM_OPTIONS", unit)
        self.assertTrue(os.access(os.path.join(self.tmp, "usr/local/bin/wsgsim"), os.X_OK))
        named = man_named_files(os.path.join(self.tmp, "usr/local/share/man/man1/wsgsim.1"))
        self.assertIn("/usr/local/share/doc/wsgsim/README.md", named)
        for path in named:
            self.assertTrue(os.path.isfile(self.tmp + path), "wsgsim(1) names " + path)

    def test_units_pass_systemd_analyze_verify(self):
        """Installed under a real prefix (no DESTDIR) so that the programs the
        units name exist: verify checks that ExecStart is executable."""
        analyze = shutil.which("systemd-analyze")
        self.assertIsNotNone(analyze, "systemd-analyze is missing: install the systemd package "
                             "(make check's dependencies, debian/control, include it)")
        prefix = os.path.join(self.tmp, "usr")
        self.make("install", "PREFIX=" + prefix, "SYSCONFDIR=" + os.path.join(self.tmp, "etc"))
        unitdir = os.path.join(prefix, "lib", "systemd", "system")
        # the template is verified through an instance, as systemd would load it
        units = [os.path.join(unitdir, "wsgsim.service"),
                 os.path.join(unitdir, "wsgsim@left.service")]
        shutil.copy(os.path.join(unitdir, "wsgsim@.service"), units[1])
        result = run([analyze, "verify", "--man=no"] + units)
        # verify exits 0 on some problems it only warns about: any output fails
        self.assertEqual((result.returncode, result.stdout + result.stderr), (0, ""))


if __name__ == "__main__":
    unittest.main()
