# SPDX-License-Identifier: BSD-3-Clause
"""The built .deb packages (make deb), unpacked with dpkg-deb -x: their
programs run, wsgsim serves GCL, and the installed python3-wsgsim's pytest
plugin loads by its entry point and passes the documented walkthrough."""
import glob
import gzip
import os
import subprocess
import tempfile
import unittest

from pkgenv import DEB_DIR, PROGRAMS, gcl_exchange, man_named_files, run
from walkthrough import run_pytest, write_example


def deb(name):
    found = glob.glob(os.path.join(DEB_DIR, name + "_*.deb"))
    if len(found) != 1:
        raise AssertionError("expected one %s package in %s (make deb), found %s"
                             % (name, DEB_DIR, found))
    return found[0]


class Packages(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.root = cls.tmp.name
        for name in ("wsgsim", "python3-wsgsim"):
            subprocess.run(["dpkg-deb", "-x", deb(name), cls.root], check=True, timeout=120)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def path(self, *parts):
        return os.path.join(self.root, *parts)

    def test_contents(self):
        for name in PROGRAMS:
            self.assertTrue(os.access(self.path("usr/bin", name), os.X_OK), name)
            self.assertTrue(os.path.exists(self.path("usr/share/man/man1", name + ".1.gz")))
        for unit in ("wsgsim.service", "wsgsim@.service"):
            text = open(self.path("lib/systemd/system", unit)).read()
            self.assertIn("Type=notify", text)
            self.assertIn("ExecStart=/usr/bin/wsgsim", text)
        for doc in ("copyright", "examples/wsgsim.example.ini", "testing-your-driver.md.gz"):
            self.assertTrue(os.path.exists(self.path("usr/share/doc/wsgsim", doc)), doc)
        self.assertTrue(os.path.exists(self.path("usr/share/wsgsim/finger-bus.dbc")))
        self.assertTrue(os.path.exists(self.path("usr/share/wsgsim/timing/wsg50.ini")))
        for model in ("wsg-gripper.xml", "default-scene.xml"):  # --physics mujoco
            self.assertTrue(os.path.exists(self.path("usr/share/wsgsim/physics", model)), model)
        entry_points = glob.glob(self.path("usr/lib/python3/dist-packages/wsgsim-*.dist-info",
                                           "entry_points.txt"))
        self.assertEqual(len(entry_points), 1)
        self.assertIn("[pytest11]\nwsgsim.pytest_plugin = wsgsim.pytest_plugin",
                      open(entry_points[0]).read())

    def test_man_pages_name_the_files_the_package_ships(self):
        """As shipped: the documents dh_compress compressed by their .gz names."""
        named = {}
        for name in PROGRAMS:
            for path in man_named_files(self.path("usr/share/man/man1", name + ".1.gz")):
                named[path] = name
        self.assertIn("/usr/share/doc/wsgsim/README.md.gz", named)
        self.assertIn("/usr/share/wsgsim/finger-bus.dbc", named)
        # the example configuration by its installed path, also where the
        # page lists the options (from --help): its reader has no source tree
        self.assertIn("/usr/share/doc/wsgsim/examples/wsgsim.example.ini", named)
        with gzip.open(self.path("usr/share/man/man1/wsgsim.1.gz"), "rt") as f:
            page = f.read()
        self.assertNotIn("docs/wsgsim.example.ini", page)
        options = page.split(".SH DESCRIPTION", 1)[1].split(".SH", 1)[0]
        self.assertIn("--config", options.replace("\\-", "-"))
        self.assertIn("/usr/share/doc/wsgsim/examples/wsgsim.example.ini", options)
        for path, page in sorted(named.items()):
            self.assertTrue(os.path.isfile(self.path(path.lstrip("/"))),
                            "%s(1) names %s, which the package does not ship" % (page, path))
        with gzip.open(self.path("usr/share/man/man1/wsgsim.1.gz"), "rt") as f:
            see_also = f.read().split("SEE ALSO", 1)[1]
        for program in ("wsgctl", "wsgbin", "fingersim", "wsgplot", "wsgcalib", "wsgfit",
                        "wsgcheck"):
            self.assertIn(".BR %s (1)" % program, see_also)

    def test_scripts_use_debians_python(self):
        for name in ("wsgctl", "wsgplot", "wsgbin", "wsgprobe", "wsgcalib", "wsgfit",
                     "wsgcheck"):
            with open(self.path("usr/bin", name)) as f:  # wsgbin: a link into /usr/share/wsgsim
                self.assertEqual(f.readline(), "#!/usr/bin/python3\n", name)

    def test_fields(self):
        depends = run(["dpkg-deb", "-f", deb("wsgsim"), "Depends"]).stdout
        for library in ("libcjson1", "libinih1", "libsystemd0", "python3", "libjs-dygraphs",
                        "libjs-codemirror"):
            self.assertIn(library, depends)
        description = run(["dpkg-deb", "-f", deb("wsgsim"), "Description"]).stdout
        for feature in ("GCL", "binary protocol", "web page"):
            self.assertIn(feature, description)
        depends = run(["dpkg-deb", "-f", deb("python3-wsgsim"), "Depends"]).stdout
        self.assertIn("wsgsim", depends)
        # the README's first GCL session is `nc localhost 1000`
        recommends = run(["dpkg-deb", "-f", deb("wsgsim"), "Recommends"]).stdout
        self.assertIn("netcat-openbsd", recommends)

    def test_programs_run(self):
        for name in PROGRAMS:
            with self.subTest(program=name):
                result = run([self.path("usr/bin", name), "--version"])
                self.assertEqual(result.returncode, 0, result.stderr)
                self.assertTrue(result.stdout.startswith(name + " "))
        replies = gcl_exchange(self.path("usr/bin/wsgsim"))
        self.assertEqual(replies[0], "GRIPSTATE=0")
        self.assertEqual(replies[2:], ["FIN HOME", "ACK BYE"])

    def test_installed_plugin_runs_the_walkthrough(self):
        env = dict(os.environ, PATH=self.path("usr/bin") + os.pathsep + os.environ["PATH"],
                   PYTHONPATH=self.path("usr/lib/python3/dist-packages"))
        env.pop("WSGSIM", None)  # found on PATH, as once installed
        # no -p: the entry point loads the plugin; with the documents' -p,
        # the same plugin is not registered twice
        for options in ((), ("-p", "wsgsim.pytest_plugin")):
            with self.subTest(options=options), tempfile.TemporaryDirectory() as tmp:
                write_example(tmp)
                result = run_pytest(tmp, env, *options)
                self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
                self.assertRegex(result.stdout, r"\b6 passed\b")
                self.assertIn("wsgsim GCL coverage", result.stdout)


if __name__ == "__main__":
    unittest.main()
