# SPDX-License-Identifier: BSD-3-Clause
"""wsgsim on its default ports, each run in a network namespace of its own
(netns.py), so the ports are free or taken exactly as the test says:
where UDP goes when only --tcp-port is given, one error
line for a taken port, and a clean debug log of the web server's start."""
import os
import tempfile
import unittest

from gclclient import ROOT
from netns import start_in_netns

WSGSIM = os.environ.get("WSGSIM", os.path.join(ROOT, "build", "wsgsim"))


def error_lines(stderr):
    """The start errors: lines 'wsgsim: ...' (log lines are 'wsgsim [t] ...')."""
    return [line for line in stderr.splitlines() if line.startswith("wsgsim:")]


class UdpPortFollowsTcpPort(unittest.TestCase):
    def ports(self, *args):
        result = start_in_netns(WSGSIM, list(args))
        self.assertEqual(result["rc"], 0, result["stderr"])
        return int(result["ready"]["tcp_port"]), int(result["ready"]["udp_port"])

    def test_both_on_1000_by_default(self):
        self.assertEqual(self.ports(), (1000, 1000))

    def test_moving_the_tcp_port_moves_udp_too(self):
        self.assertEqual(self.ports("--tcp-port", "2000"), (2000, 2000))

    def test_an_explicit_udp_port_stays(self):
        self.assertEqual(self.ports("--tcp-port", "2000", "--udp-port", "3000"), (2000, 3000))
        self.assertEqual(self.ports("--udp-port", "3000"), (1000, 3000))

    def test_the_config_files_tcp_port_moves_udp_too(self):
        with tempfile.NamedTemporaryFile("w", suffix=".ini") as config:
            config.write("[network]\ntcp_port = 2100\n")
            config.flush()
            self.assertEqual(self.ports("--config", config.name), (2100, 2100))
            self.assertEqual(self.ports("--config", config.name, "--udp-port", "3100"),
                             (2100, 3100))

    def test_the_example_config_with_another_tcp_port(self):
        example = os.path.join(ROOT, "docs", "wsgsim.example.ini")
        self.assertEqual(self.ports("--config", example, "--tcp-port", "2200"), (2200, 2200))


class TakenPorts(unittest.TestCase):
    def test_a_taken_gcl_port_is_one_error_line(self):
        """The optional defaults (web 8080, binary UDP 1500) taken as well:
        a warning each at most, never a second 'wsgsim:' line."""
        result = start_in_netns(WSGSIM, [], hold=[("tcp", 1000), ("tcp", 8080), ("udp", 1500)])
        self.assertEqual(result["rc"], 2, result["stderr"])
        errors = error_lines(result["stderr"])
        self.assertEqual(errors, ["wsgsim: cannot listen on TCP 0.0.0.0:1000: Address already "
                                  "in use (another program, perhaps another wsgsim, has it: "
                                  "choose another port, or --tcp-port 0 for a free one)"],
                         result["stderr"])

    def test_taken_optional_defaults_are_warnings(self):
        result = start_in_netns(WSGSIM, [], hold=[("tcp", 8080), ("udp", 1500)])
        self.assertEqual(result["rc"], 0, result["stderr"])
        self.assertEqual(error_lines(result["stderr"]), [], result["stderr"])
        self.assertIn("warning: http port 8080 cannot be had (Address already in use): no web "
                      "interface", result["stderr"])
        self.assertIn("warning: binary udp port 1500 cannot be had (Address already in use)",
                      result["stderr"])

    def test_a_taken_port_given_explicitly_is_one_error_line(self):
        result = start_in_netns(WSGSIM, ["--http-port", "8080"], hold=[("tcp", 8080)])
        self.assertEqual(result["rc"], 2, result["stderr"])
        self.assertEqual(error_lines(result["stderr"]),
                         ["wsgsim: cannot listen on TCP 0.0.0.0:8080: Address already in use "
                          "(another program, perhaps another wsgsim, has it: choose another "
                          "port)"])


class WebServerStart(unittest.TestCase):
    def test_debug_log_has_no_option_order_complaint(self):
        result = start_in_netns(WSGSIM, ["--log-level", "debug"])
        self.assertEqual(result["rc"], 0, result["stderr"])
        self.assertIn("web page http://127.0.0.1:8080/", result["stderr"], "the web server ran")
        self.assertNotIn("is not the first option", result["stderr"])


if __name__ == "__main__":
    unittest.main()
