# SPDX-License-Identifier: BSD-3-Clause
"""--devices N: N independent grippers in one process.

Device i listens on TCP and UDP port (base + i), or on free ports of its own
when the base is 0; its serial number is the configured one plus i and its
tag the configured one with "-i" appended. The control channel addresses one
device per connection (DEVICE=i, default 0) and lists them (DEVICES?).
No test asserts on speed: timeouts are generous upper bounds against hangs.
"""
import os
import re
import socket
import struct
import sys
import tempfile
import unittest

from gclclient import GclTcp, GclUdp, Wsgsim

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402

DEVICE_LINE = re.compile(r"device (\d+): tcp [^ ]+:(\d+), udp [^ ]+:(\d+)(?:, binary udp (\d+))?, "
                         r"serial (\d+), tag (.*)")


def port_free(kind, port):
    s = socket.socket(socket.AF_INET, kind)
    try:
        s.bind(("127.0.0.1", port))
        return True
    except OSError:
        return False
    finally:
        s.close()


def free_port_range(count):
    """A base port with count free TCP and UDP ports from it on."""
    for base in range(20000, 60000, count + 7):
        if all(port_free(socket.SOCK_STREAM, base + i) and port_free(socket.SOCK_DGRAM, base + i)
               for i in range(count)):
            return base
    raise AssertionError("no %d free loopback ports in a row" % count)


def free_udp_range(count, start):
    """A base port from start on with count free UDP ports from it on."""
    for base in range(start, 60000, count + 3):
        if all(port_free(socket.SOCK_DGRAM, base + i) for i in range(count)):
            return base
    raise AssertionError("no %d free UDP loopback ports in a row" % count)


def device_ports(sim, count):
    """{index: (tcp, udp)} from the start-up log; device 0 from the ready line."""
    ports = {0: (sim.tcp_port, sim.udp_port)}
    for match in DEVICE_LINE.finditer("".join(sim.log)):
        ports[int(match.group(1))] = (int(match.group(2)), int(match.group(3)))
    assert len(ports) == count, "device lines: %r" % ports
    return ports


class Fleet(unittest.TestCase):
    def start(self, *args):
        sim = Wsgsim(*args)
        sim.start()
        self.addCleanup(sim.stop)
        return sim

    def tcp(self, port):
        c = GclTcp("127.0.0.1", port)
        self.addCleanup(c.close)
        return c

    def test_devices_listen_on_base_plus_index(self):
        base = free_port_range(3)
        sim = self.start("--devices", "3", "--tcp-port", str(base), "--udp-port", str(base))
        self.assertEqual((sim.tcp_port, sim.udp_port), (base, base))
        self.assertEqual(device_ports(sim, 3), {i: (base + i, base + i) for i in range(3)})
        self.assertIn(", devices 3", sim.drain_log())
        for i in range(3):
            self.tcp(base + i).expect("SN?", "SN=%d" % (12345678 + i))
            u = GclUdp("127.0.0.1", base + i)
            self.addCleanup(u.close)
            u.expect("SN?", "SN=%d" % (12345678 + i))

    def test_binary_udp_per_device_on_base_plus_index(self):
        """Device i serves binary UDP on (port + i) and replies to (reply
        port + i): each device answers with its own serial number."""
        bin_base = free_udp_range(2, 30000)
        reply_base = free_udp_range(2, bin_base + 100)
        sim = self.start("--devices", "2", "--binary-udp-port", str(bin_base),
                         "--binary-udp-reply-port", str(reply_base))
        log = sim.drain_log()
        self.assertIn(", binary udp %d" % bin_base, log)
        self.assertIn(", binary udp %d, serial 12345679" % (bin_base + 1), log)
        for i in range(2):
            client = wb.BinUdp("127.0.0.1", bin_base + i, reply_port=reply_base + i,
                               timeout=30.0, bind_host="127.0.0.1")
            self.addCleanup(client.close)
            client.send_request(0x50)
            frame = client.wait_for(0x50)
            self.assertEqual(frame.status, 0, wb.describe(frame))
            self.assertEqual(struct.unpack("<I", frame.values[4:8])[0], 12345678 + i)

    def test_binary_udp_off_is_not_announced(self):
        """Without binary UDP the ready line and the device lines leave it
        out (they once said 'binary udp -1')."""
        sim = self.start("--devices", "2")  # the launcher turns binary UDP off
        log = sim.drain_log()
        ready = [line for line in log.splitlines() if "ready: tcp" in line]
        self.assertEqual(len(ready), 1, log)
        self.assertNotIn("binary udp", ready[0])
        self.assertNotIn("binary udp", log)

    def test_port_zero_gives_each_device_free_ports(self):
        sim = self.start("--devices", "3")
        ports = device_ports(sim, 3)
        self.assertEqual(len({p for pair in ports.values() for p in pair[:1]}), 3)
        for i, (tcp, _) in ports.items():
            self.tcp(tcp).expect("SN?", "SN=%d" % (12345678 + i))

    def test_identity_differs(self):
        sim = self.start("--devices", "3")
        ports = device_ports(sim, 3)
        tags = {self.tcp(ports[i][0]).command("TAG?") for i in range(3)}
        self.assertEqual(len(tags), 3, tags)
        first = self.tcp(ports[0][0]).command("TAG?")
        self.assertEqual(self.tcp(ports[2][0]).command("TAG?"), first[:-1] + '-2"')

    def test_home_on_one_device_moves_no_other(self):
        sim = self.start("--devices", "3", "--fingers", "none,none")
        ports = device_ports(sim, 3)
        c = [self.tcp(ports[i][0]) for i in range(3)]
        before = [c[i].command("POS?") for i in (0, 2)]
        self.assertEqual(c[1].long_command("HOME()", "HOME"), "FIN HOME")
        self.assertEqual([c[i].command("POS?") for i in (0, 2)], before)
        self.assertEqual(c[0].command("MOVE(10)"), "ERR MOVE 3")  # device 0 is not referenced

    def test_fast_stop_on_one_device_only(self):
        sim = self.start("--devices", "3", "--fingers", "none,none")
        ports = device_ports(sim, 3)
        c = [self.tcp(ports[i][0]) for i in range(3)]
        c[1].expect("FASTSTOP()", "ACK FASTSTOP")
        self.assertTrue(c[1].command("HOME()").startswith("ERR HOME"))
        self.assertEqual(c[0].long_command("HOME()", "HOME"), "FIN HOME")
        self.assertEqual(c[2].long_command("HOME()", "HOME"), "FIN HOME")

    def test_control_channel_addresses_each_device(self):
        sim = self.start("--devices", "3", "--sim-port", "0", "--fingers", "none,none")
        ports = device_ports(sim, 3)
        ctl = sim.control()
        self.addCleanup(ctl.close)
        self.assertEqual(ctl("DEVICE?"), "DEVICE=0")
        self.assertEqual(ctl("PART?"), "PART=[0,0,0,0]")
        self.assertEqual(ctl("DEVICE=2"), "DEVICE=2")
        self.assertEqual(ctl("PART(20)"), "ACK PART")
        self.assertTrue(ctl("PART?").startswith("PART=[1,20,"))
        self.assertTrue(ctl("DEVICE=3").startswith("ERR DEVICE 28"))
        self.assertEqual(ctl("DEVICE?"), "DEVICE=2")  # a bad selection changes nothing
        state = ctl.json("STATE?")
        self.assertEqual(state["device"]["serial"], 12345680)
        other = sim.control()
        self.addCleanup(other.close)
        self.assertEqual(other("PART?"), "PART=[0,0,0,0]")  # each connection selects its own
        devices = ctl.json("DEVICES?")
        self.assertEqual([(d["index"], d["tcp"], d["udp"]) for d in devices],
                         [(i, ports[i][0], ports[i][1]) for i in range(3)])
        self.assertEqual([d["serial"] for d in devices], [12345678, 12345679, 12345680])
        c2 = self.tcp(ports[2][0])
        c2.expect("GRIPSTATE?", "GRIPSTATE=0")
        self.assertEqual([s["transport"] for s in ctl.json("SESSIONS?")], ["tcp"])
        self.assertEqual(other.json("SESSIONS?"), [])
        self.assertEqual(ctl("FAULT(POWER)"), "ACK FAULT")  # device 2's own fault
        self.assertEqual([f["fault"] for f in ctl.json("FAULTS?")], ["POWER"])
        self.assertEqual(other.json("FAULTS?"), [])  # device 0 has none
        self.assertTrue(ctl('FAULT("FINGER_POWER",0)').startswith("ERR FAULT 5"))  # no finger bus
        self.assertEqual(ctl("CLEAR()"), "ACK CLEAR")
        self.assertEqual(ctl.json("FAULTS?"), [])

    def test_reset_of_one_device_closes_only_its_connections(self):
        sim = self.start("--devices", "2", "--sim-port", "0", "--fingers", "none,none")
        ports = device_ports(sim, 2)
        c0, c1 = self.tcp(ports[0][0]), self.tcp(ports[1][0])
        c0.expect("GRIPSTATE?", "GRIPSTATE=0")
        c1.expect("GRIPSTATE?", "GRIPSTATE=0")
        ctl = sim.control()
        self.addCleanup(ctl.close)
        self.assertEqual(ctl("DEVICE=1"), "DEVICE=1")
        self.assertEqual(ctl("RESET()"), "ACK RESET")
        self.assertTrue(c1.closed_by_peer(10))
        c0.expect("GRIPSTATE?", "GRIPSTATE=0")

    def test_two_hundred_devices_answer(self):
        sim = self.start("--devices", "200", "--fingers", "none,none")
        ports = device_ports(sim, 200)
        for i in (0, 1, 57, 100, 199):
            c = self.tcp(ports[i][0])
            self.assertTrue(c.command("POS?").startswith("POS="))
            c.expect("SN?", "SN=%d" % (12345678 + i))

    def test_devices_beyond_the_port_range_refuse_to_start(self):
        sim = Wsgsim("--devices", "3", "--tcp-port", "65534", "--udp-port", "0")
        with self.assertRaises(AssertionError):
            sim.start()
        self.assertIn("device 2 would need TCP port 65536", "".join(sim.log))

    def config(self, text):
        fd, path = tempfile.mkstemp(suffix=".ini")
        with os.fdopen(fd, "w") as f:
            f.write(text)
        self.addCleanup(os.remove, path)
        return path

    def test_config_file_declares_devices_one_by_one(self):
        base = free_port_range(1)
        path = self.config("[device]\nserial = 100\ntag = cell\n"
                           "[device.1]\nmodel = WSG 32-068\nserial = 777\ntag = left\n"
                           "[device.2]\nmodel = WSG 25-064\ntcp_port = %d\n" % base)
        sim = self.start("--config", path)  # three devices without --devices
        ports = device_ports(sim, 3)
        self.assertEqual(ports[2][0], base)
        c = [self.tcp(ports[i][0]) for i in range(3)]
        self.assertEqual([x.command("DEVTYPE?") for x in c],
                         ['DEVTYPE="WSG 50-110"', 'DEVTYPE="WSG 32-068"', 'DEVTYPE="WSG 25-064"'])
        self.assertEqual([x.command("SN?") for x in c], ["SN=100", "SN=777", "SN=102"])
        self.assertEqual([x.command("TAG?") for x in c], ['TAG="cell"', 'TAG="left"', 'TAG="cell-2"'])

    def test_bad_device_sections_are_refused_with_file_and_line(self):
        for text, why in (("[device.x]\nserial = 1\n", "[device.N], N 0-9999"),
                          ("[device.10000]\nserial = 1\n", "[device.N], N 0-9999"),
                          ("[device.1]\nforce = 1\n", "unknown key in a device section"),
                          ("[device.1]\nmodel = WSG 99\n", "unknown model"),
                          ("[motion]\ndefault_force = 70\n[device.1]\nmodel = WSG 25-064\n",
                           "outside")):
            path = self.config(text)
            sim = Wsgsim("--config", path)
            with self.assertRaises(AssertionError):
                sim.start()
            self.assertIn(why, "".join(sim.log), text)

    def test_device_count_is_checked(self):
        for bad in ("0", "10001", "x"):
            sim = Wsgsim("--devices", bad)
            with self.assertRaises(AssertionError):
                sim.start()


if __name__ == "__main__":
    unittest.main()
