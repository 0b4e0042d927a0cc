# SPDX-License-Identifier: BSD-3-Clause
"""Every program: -h/--help with a line per option, -V/--version, errors in
one style ('PROG: ...', exit status 2), and a man page that has every
option of --help. The versions everywhere agree."""
import os
import re
import unittest

from pkgenv import MAN_DIR, PROGRAMS, ROOT, run

OPTION_LINE = re.compile(r"^ {1,4}(-.*?)(?:  |$)", re.M)  # the option column of a help line
OPTION = re.compile(r"(?<![\w-])(--?[A-Za-z][\w-]*)")
BAD_USES = {
    "wsgsim": [["--bogus"], ["-x"], ["--tcp-port"], ["--log-level", "loud"], ["extra"]],
    "fingersim": [["--bogus"], ["-x"], ["--can"], [], ["--can", "vcan0", "--noise", "x"]],
    "wsgctl": [["--bogus"], ["--port"], ["--port", "x"], ["--timeout", "x", "--port", "1"]],
    "wsgplot": [["--bogus"], [], ["record.txt"], ["/nonexistent.txt", "-o", "x.png"]],
    "wsgbin": [["--bogus"], [], ["nosuchcommand"], ["--port", "x", "ack"]],
    "wsgprobe": [["--bogus"], [], ["--port", "x", "-o", "x.ini"], ["-o", "x.ini", "extra"]],
    "wsgproxy": [["--bogus"], [], ["--gripper"], ["--gripper", "h", "--tcp-port", "x"],
                 ["--gripper", "h", "extra"]],
    "wsgcalib": [["--bogus"], [], ["host", "--repeat", "0"], ["host", "--poll-ms", "x"]],
    "wsgfit": [["--bogus"], []],
    "wsgcheck": [["--bogus"], [], ["rec.txt", "--time-tolerance", "x"]],
}


def options_in_help(text):
    """Every option --help describes at the start of a line, short and long."""
    found = set()
    for column in OPTION_LINE.findall(text):
        found.update(OPTION.findall(column))
    return found


def man_text(name):
    """The page's text with roff's escaped hyphens as plain ones."""
    with open(os.path.join(MAN_DIR, name + ".1")) as f:
        return f.read().replace("\\-", "-").replace("\\fB", "").replace("\\fR", "")


class Programs(unittest.TestCase):
    def test_help_short_and_long(self):
        for name, path in PROGRAMS.items():
            with self.subTest(program=name):
                long, short = run([path, "--help"]), run([path, "-h"])
                self.assertEqual((long.returncode, short.returncode), (0, 0), long.stderr)
                self.assertEqual(long.stdout, short.stdout)
                self.assertTrue(long.stdout.startswith("Usage: " + name), long.stdout[:80])
                options = options_in_help(long.stdout)
                self.assertTrue({"-h", "--help", "-V", "--version"} <= options, options)
                self.assertGreater(len(options), 4)

    def test_version_short_and_long(self):
        version = read_version_h()
        for name, path in PROGRAMS.items():
            with self.subTest(program=name):
                long, short = run([path, "--version"]), run([path, "-V"])
                self.assertEqual((long.returncode, short.returncode), (0, 0))
                self.assertEqual(long.stdout, short.stdout)
                self.assertTrue(long.stdout.startswith("%s %s" % (name, version)), long.stdout)

    def test_errors_in_one_style(self):
        for name, uses in BAD_USES.items():
            for args in uses:
                with self.subTest(program=name, args=args):
                    result = run([PROGRAMS[name]] + args, env=dict(os.environ, WSGSIM_SIM_PORT=""))
                    self.assertEqual(result.returncode, 2, result.stderr)
                    lines = result.stderr.splitlines()
                    self.assertEqual(len(lines), 1, result.stderr)
                    self.assertTrue(lines[0].startswith(name + ": "), lines[0])

    def test_man_page_has_every_option_of_help(self):
        for name, path in PROGRAMS.items():
            with self.subTest(program=name):
                page = man_text(name)
                self.assertRegex(page, r'\.TH %s "?1' % name.upper())
                for option in options_in_help(run([path, "--help"]).stdout):
                    self.assertRegex(page, r"(?<![\w-])%s(?![\w-])" % re.escape(option),
                                     "%s(1) lacks %s" % (name, option))

    def test_wsgctl_documents_its_environment(self):
        page = run([PROGRAMS["wsgctl"], "--help"]).stdout
        self.assertIn("WSGSIM_SIM_PORT", page)
        self.assertIn("WSGSIM_SIM_PORT", man_text("wsgctl"))


def read_version_h():
    with open(os.path.join(ROOT, "host", "version.h")) as f:
        return re.search(r'#define WSGSIM_VERSION "([^"]+)"', f.read()).group(1)


class Versions(unittest.TestCase):
    def test_one_version_everywhere(self):
        version = read_version_h()
        with open(os.path.join(ROOT, "debian", "changelog")) as f:
            self.assertRegex(f.readline(), r"^wsgsim \(%s(-\d+)?\) " % re.escape(version))
        with open(os.path.join(ROOT, "python", "wsgsim", "__init__.py")) as f:
            self.assertIn('__version__ = "%s"' % version, f.read())
        for script in ("wsgctl", "wsgplot", "wsgbin", "wsgprobe", "wsgtwin.py"):
            with open(os.path.join(ROOT, "tools", script)) as f:
                self.assertIn('VERSION = "%s"' % version, f.read(), script)


if __name__ == "__main__":
    unittest.main()
