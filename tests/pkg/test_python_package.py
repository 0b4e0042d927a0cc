# SPDX-License-Identifier: BSD-3-Clause
"""The wsgsim Python package outside pytest: the launcher on a quiet
wsgsim, and the binary protocol's extension point."""
import unittest

from pkgenv import WSGSIM  # puts this tree's python/ first on the path

import wsgsim  # noqa: E402 (after pkgenv)


class Package(unittest.TestCase):
    def test_ports_come_from_the_ready_file_at_any_log_level(self):
        with wsgsim.Wsgsim("--quiet", binary=WSGSIM, control=True) as sim:
            self.assertEqual(sim.log, [], "nothing logged, and still started")
            with sim.tcp() as gcl:
                self.assertTrue(gcl.command("GRIPSTATE?").startswith("GRIPSTATE="))
            with sim.control() as control:
                self.assertTrue(control("SESSIONS?").startswith("SESSIONS="))

    def test_binary_protocol_module_and_extension_point(self):
        proto = wsgsim.protocol()
        self.assertEqual(proto.PREAMBLE, b"\xaa\xaa\xaa")
        frame = proto.encode_frame(0x40)
        decoded = proto.deframe(frame)[0]
        self.assertEqual((decoded.id, decoded.crc_ok), (0x40, True))
        with wsgsim.Wsgsim("--binary-udp-port", "0", binary=WSGSIM) as sim:
            client = sim.binary_protocol()
            try:
                self.assertEqual(client.request(0x31).status, 0)  # get acceleration
            finally:
                client.close()
        with wsgsim.Wsgsim("--protocol", "gcl", binary=WSGSIM) as sim:
            with self.assertRaisesRegex(wsgsim.BinaryProtocolUnavailable, "does not serve"):
                sim.binary_protocol()


if __name__ == "__main__":
    unittest.main()
