# SPDX-License-Identifier: BSD-3-Clause
"""How the build talks to the person who runs it: one short line per
compiled file (V=1: the whole command), the long package and image builds
showing their stages as they go (mk/progress.py), and the package
installer waiting for another apt instead of failing (mk/deps.sh)."""
import os
import re
import stat
import subprocess
import tempfile
import textwrap
import unittest

from pkgenv import ROOT, TIMEOUT


def make(*args):
    """make in the source tree, without the calling make's job server and
    without -s: what a person sees."""
    env = dict(os.environ)
    env["MAKEFLAGS"] = re.sub(r"--jobserver-\S+|-j\d*|\bs\b", "", env.get("MAKEFLAGS", ""))
    env.pop("MFLAGS", None)
    return subprocess.run(["make", "--no-print-directory", "-C", ROOT] + list(args),
                          capture_output=True, text=True, timeout=TIMEOUT * 5, env=env,
                          stdin=subprocess.DEVNULL)


class QuietBuild(unittest.TestCase):
    def compile_one(self, *options):
        """Compiles host/os/log.c into a build directory of its own."""
        with tempfile.TemporaryDirectory(dir=os.path.join(ROOT, "build")) as build:
            target = os.path.join(build, "obj", "host", "os", "log.o")
            result = make("BUILD=" + build, target, *options)
            self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
            self.assertTrue(os.path.exists(target))
        return result.stdout

    def test_a_compiled_file_is_one_short_line(self):
        self.assertEqual(self.compile_one().splitlines(), ["  CC      host/os/log.c"])

    def test_v1_prints_the_whole_command(self):
        lines = self.compile_one("V=1").splitlines()
        self.assertEqual(len(lines), 1, lines)
        self.assertIn("-Wall", lines[0])
        self.assertTrue(lines[0].endswith("-c host/os/log.c -o %s" % lines[0].split()[-1]))


PROGRESS = os.path.join(ROOT, "mk", "progress.py")


class Progress(unittest.TestCase):
    def run_progress(self, script):
        with tempfile.TemporaryDirectory() as tmp:
            log = os.path.join(tmp, "step.log")
            result = subprocess.run(
                ["/usr/bin/python3", PROGRESS, "step", log, r"^(stage |   dh_)", "--",
                 "sh", "-c", script], capture_output=True, text=True, timeout=TIMEOUT)
            with open(log) as f:
                return result, f.read()

    def test_stages_show_as_they_come_and_the_log_has_everything(self):
        result, log = self.run_progress("echo stage one; echo detail >&2; echo '   dh_auto_build';"
                                        " echo more detail; echo stage two")
        self.assertEqual(result.returncode, 0, result.stderr)
        shown = [re.sub(r"^step: \[ *\d+s\] ", "", line) for line in result.stdout.splitlines()]
        self.assertEqual(shown[1:], ["stage one", "dh_auto_build", "stage two", "done"])
        self.assertTrue(all(line.startswith("step: [") for line in result.stdout.splitlines()))
        self.assertEqual(log, "stage one\ndetail\n   dh_auto_build\nmore detail\nstage two\n")

    def test_a_failure_shows_the_logs_end_and_keeps_the_status(self):
        result, _ = self.run_progress("echo stage one; echo 'E: what went wrong'; exit 3")
        self.assertEqual(result.returncode, 3)
        self.assertIn("E: what went wrong\n", result.stdout)
        self.assertRegex(result.stdout, r"step: \[ *\d+s\] failed \(exit status 3\), see ")


class WaitsForApt(unittest.TestCase):
    """mk/deps.sh as root with a package missing, against stand-ins for
    dpkg-query and apt-get: the package lists are locked by another apt
    for the first two tries of `apt-get update`."""

    FAKE_DPKG_QUERY = "#!/bin/sh\nexit 1\n"  # nothing is installed
    FAKE_APT_GET = textwrap.dedent("""\
        #!/bin/sh
        echo "$*" >> "$CALLS"
        case "$*" in
        *" update "*|*" update")
            tries=$(grep -c " update" "$CALLS")
            if [ "$tries" -le 2 ]; then
                echo "E: Could not get lock /var/lib/apt/lists/lock. It is held by process 1 (apt-get)" >&2
                exit 100
            fi ;;
        esac
        exit 0
        """)

    def test_update_waits_for_the_lists_and_install_for_dpkg(self):
        if os.geteuid() != 0:
            raise AssertionError("mk/deps.sh installs as root only: run the pkg tests as root")
        with tempfile.TemporaryDirectory() as tmp:
            for name, text in (("dpkg-query", self.FAKE_DPKG_QUERY),
                               ("apt-get", self.FAKE_APT_GET)):
                path = os.path.join(tmp, name)
                with open(path, "w") as f:
                    f.write(text)
                os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR)
            calls = os.path.join(tmp, "calls")
            env = dict(os.environ, PATH=tmp + os.pathsep + os.environ["PATH"], CALLS=calls,
                       APT_LOCK_WAIT="60")
            result = subprocess.run([os.path.join(ROOT, "mk", "deps.sh"), "no-such-package"],
                                    capture_output=True, text=True, timeout=TIMEOUT, env=env)
            with open(calls) as f:
                made = f.read().splitlines()
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("another apt holds the package lists; waiting for it", result.stderr)
        self.assertEqual(len(made), 4, made)
        self.assertTrue(all(call.startswith("-o DPkg::Lock::Timeout=60 update")
                            for call in made[:3]), made)
        self.assertRegex(made[3], r"^-o DPkg::Lock::Timeout=60 install .*no-such-package$")


if __name__ == "__main__":
    unittest.main()
