"""Abuse: hostile and broken clients against build/wsgsim (issue 6).

Every test first puts the device into a known state through a "keeper"
connection (homed, jaws at 42 mm, VERBOSE=1, PWT=3.5 on the keeper), abuses
the server, and then asserts that the server still answers correctly and
that neither the device nor the keeper's session lost any state.
"""
import os
import random
import socket
import struct
import time
import unittest

from gclclient import GclError, GclTcp, Wsgsim

POSITION = 42.0
MIB = 1024 * 1024


def rss_kib(pid):
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise AssertionError("no VmRSS for pid %d" % pid)


def open_fds(pid):
    return len(os.listdir("/proc/%d/fd" % pid))


class AbuseCase(unittest.TestCase):
    server_args = ()

    def setUp(self):
        self.sim = Wsgsim(*self.server_args)
        self.sim.start()
        self.clients = []
        self.keeper = self.tcp()
        k = self.keeper
        k.expect("FSACK()", "ACK FSACK")
        self.assertEqual(k.long_command("HOME()", "HOME"), "FIN HOME")
        self.assertEqual(k.long_command("MOVE(%.1f)" % POSITION, "MOVE"), "FIN MOVE")
        k.expect("VERBOSE=1", "VERBOSE=1")
        k.expect("PWT=3.5", "PWT=3.5")
        self.gripstats = k.command("GRIPSTATS[0]?")

    def tearDown(self):
        for client in self.clients:
            client.close()
        code = self.sim.stop()
        self.assertEqual(code, 0, "wsgsim did not shut down cleanly:\n" + "".join(self.sim.log))

    def tcp(self, timeout=None):
        client = self.sim.tcp(timeout or 10.0)
        self.clients.append(client)
        return client

    def forget(self, client):
        self.clients.remove(client)
        client.close()

    def assert_state_kept(self, fast_stop_expected=False):
        """The device and the keeper's session are as setUp left them."""
        k = self.keeper
        self.assertTrue(self.sim.alive(), "wsgsim died:\n" + self.sim.drain_log())
        if fast_stop_expected:
            k.expect("SYSFLAGS[12]?", "SYSFLAGS[12]=1")
            k.expect("FSACK()", "ACK FSACK")
        k.expect("SYSFLAGS[12]?", "SYSFLAGS[12]=0")  # no FAST STOP
        k.expect("SYSFLAGS[0]?", "SYSFLAGS[0]=1")  # still referenced
        self.assertAlmostEqual(k.query_float("POS"), POSITION, places=1)
        k.expect("VERBOSE?", "VERBOSE=1")
        k.expect("PWT?", "PWT=3.5")
        k.expect("GRIPSTATS[0]?", self.gripstats)
        # and the device still moves on command
        self.assertEqual(k.long_command("MOVE(60)", "MOVE"), "FIN MOVE")
        self.assertAlmostEqual(k.query_float("POS"), 60.0, places=1)
        fresh = self.tcp()
        fresh.expect("VERBOSE?", "VERBOSE=0")  # new sessions start from defaults
        fresh.expect("GRIPSTATE?", "GRIPSTATE=0")
        fresh.expect("BYE()", "ACK BYE")
        self.forget(fresh)


class StreamAbuse(AbuseCase):
    def test_one_mib_line_without_newline(self):
        rss_before = rss_kib(self.sim.proc.pid)
        c = self.tcp()
        c.send_raw(b"A" * MIB)
        # the server keeps answering others while the line is still open
        self.assertAlmostEqual(self.keeper.query_float("POS"), POSITION, places=1)
        c.send_raw(b"\nPOS?\n")
        reply = c.read_line()
        self.assertTrue(reply.startswith("ERR ") and reply.endswith(" 15"), reply)
        self.assertLessEqual(len(reply), 300, "an overlong line must not be echoed whole")
        self.assertEqual(c.read_line(), "POS=%.1f" % POSITION)
        self.assertLess(rss_kib(self.sim.proc.pid) - rss_before, 1024, "the line was buffered")
        c.expect("BYE()", "ACK BYE")
        self.assert_state_kept()

    def test_nul_and_8bit_bytes(self):
        c = self.tcp()
        for junk in (b"PO\x00S?", b"\x00", b"\xff\xfe\x80", b"MOVE(\xe9)", b"\x1b[2J", bytes(range(256))):
            c.send_raw(junk + b"\n")
            reply = c.read_line()
            self.assertTrue(reply.startswith("ERR ") and reply.endswith(" 15"), (junk, reply))
        everything = bytes(range(256)) * 64  # 16 KiB of every byte value, newlines included
        c.send_raw(everything + b"\nPOS?\n")
        lines = []
        while True:
            line = c.read_line()
            if line.startswith("POS="):
                break
            lines.append(line)
        self.assertEqual(line, "POS=%.1f" % POSITION)
        for line in lines:
            self.assertTrue(line.startswith("ERR "), line)
            self.assertTrue(all(32 <= ord(ch) < 127 for ch in line), repr(line))
        c.expect("BYE()", "ACK BYE")
        self.assert_state_kept()

    def test_ten_thousand_commands_in_one_write(self):
        c = self.tcp()
        c.send_raw(b"POS?\n" * 10000)
        for i in range(10000):
            self.assertEqual(c.read_line(timeout=20), "POS=%.1f" % POSITION, "reply %d" % i)
        mixed = b"".join(b"SN?\nGRIPSTATE?\nVERBOSE=%d\n" % (i % 2) for i in range(3334))
        c.send_raw(mixed)
        for i in range(3334):
            self.assertTrue(c.read_line(timeout=20).startswith("SN="))
            self.assertEqual(c.read_line(timeout=20), "GRIPSTATE=0")
            self.assertEqual(c.read_line(timeout=20), "VERBOSE=%d" % (i % 2))
        c.expect("BYE()", "ACK BYE")
        self.assert_state_kept()

    def test_command_split_byte_by_byte_over_1000_writes(self):
        c = self.tcp()
        payload = b"POS?\r\n" * 100 + b"GRIPSTATE?\n" * 32 + b"SN?\n" * 12
        self.assertEqual(len(payload), 1000)
        for i in range(len(payload)):
            c.send_raw(payload[i:i + 1])
            if i % 10 == 0:
                time.sleep(0.001)  # let the server see separate reads
        for _ in range(100):
            self.assertEqual(c.read_line(), "POS=%.1f" % POSITION)
        for _ in range(32):
            self.assertEqual(c.read_line(), "GRIPSTATE=0")
        for _ in range(12):
            self.assertTrue(c.read_line().startswith("SN="))
        # a motion command split byte by byte still runs
        for byte in b"MOVE(42.0)\n":
            c.send_raw(bytes([byte]))
            time.sleep(0.002)
        self.assertEqual(c.read_line(), "ACK MOVE")
        self.assertEqual(c.read_line(), "FIN MOVE")
        c.expect("BYE()", "ACK BYE")
        self.assert_state_kept()

    def test_500_connect_disconnect_cycles(self):
        pid = self.sim.proc.pid
        fds_before = open_fds(pid)
        stalls = 0
        for i in range(500):
            started = time.monotonic()
            c = GclTcp("127.0.0.1", self.sim.tcp_port, timeout=5.0)
            stalls += time.monotonic() - started > 0.5
            if i % 50 == 0:
                self.sim.drain_log(0)  # keep the server's log pipe flowing
            if i % 2 == 0:
                c.expect("BYE()", "ACK BYE")
                self.assertTrue(c.closed_by_peer(), "BYE must close the connection")
            else:
                c.expect("GRIPSTATE?", "GRIPSTATE=0")
                c.send("BYE()")  # closes at once without reading the ACK
            c.close()
        deadline = time.monotonic() + 5
        while open_fds(pid) > fds_before and time.monotonic() < deadline:
            time.sleep(0.05)
        self.assertEqual(open_fds(pid), fds_before, "descriptors leaked")
        # regression: a listen backlog of 16 dropped a SYN every ~17 quick
        # reconnects (about 30 stalls of 1 s here); a slow server (valgrind,
        # a loaded machine) may still fall behind the client now and then
        self.assertLess(stalls, 10, "reconnecting clients waited for SYN retransmits")
        self.assert_state_kept()

    def test_peer_resets_mid_reply(self):
        for _ in range(20):
            c = self.tcp()
            c.send_raw(b"POS?\n" * 20000 + b"FDATA[0]?\n" * 100)
            # RST at once: SO_LINGER with a zero timeout
            c.sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
            self.forget(c)
        time.sleep(0.2)
        # a dropped connection without BYE raises FAST STOP by design (manual 2.1.2)
        self.assert_state_kept(fast_stop_expected=True)
        self.assertIn("without BYE", self.sim.drain_log())


class StreamAbuseNoFastStop(AbuseCase):
    server_args = ("--no-disconnect-faststop",)

    def test_500_abrupt_disconnects(self):
        pid = self.sim.proc.pid
        fds_before = open_fds(pid)
        stalls = 0
        for i in range(500):
            started = time.monotonic()
            s = socket.create_connection(("127.0.0.1", self.sim.tcp_port), timeout=5)
            stalls += time.monotonic() - started > 0.5
            if i % 50 == 0:
                self.sim.drain_log(0)  # keep the server's log pipe flowing
            if i % 3 == 1:
                s.sendall(b"POS?\nGRIPSTATE?\n")
            elif i % 3 == 2:
                s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
            s.close()
        deadline = time.monotonic() + 5
        while open_fds(pid) > fds_before and time.monotonic() < deadline:
            time.sleep(0.05)
        self.assertEqual(open_fds(pid), fds_before, "descriptors leaked")
        # regression: a listen backlog of 16 dropped a SYN every ~17 quick
        # reconnects (about 30 stalls of 1 s here); a slow server (valgrind,
        # a loaded machine) may still fall behind the client now and then
        self.assertLess(stalls, 10, "reconnecting clients waited for SYN retransmits")
        self.assert_state_kept()


class ClientLimits(AbuseCase):
    server_args = ("--max-clients", "4")

    def test_more_clients_than_max_clients(self):
        others = [self.tcp() for _ in range(3)]  # with the keeper: 4
        for c in others:
            c.expect("GRIPSTATE?", "GRIPSTATE=0")
        refused = []
        for _ in range(20):
            extra = GclTcp("127.0.0.1", self.sim.tcp_port)
            refused.append(extra)
        for extra in refused:
            self.assertTrue(extra.closed_by_peer(), "connection beyond --max-clients accepted")
            extra.close()
        for c in others:
            c.expect("POS?", "POS=%.1f" % POSITION)
        others[0].expect("BYE()", "ACK BYE")
        self.assertTrue(others[0].closed_by_peer())
        self.forget(others[0])
        late = self.tcp()  # a slot is free again
        late.expect("POS?", "POS=%.1f" % POSITION)
        late.expect("BYE()", "ACK BYE")
        self.forget(late)
        self.assert_state_kept()


class SlowReader(AbuseCase):
    def test_autosend_subscriber_that_never_reads(self):
        pid = self.sim.proc.pid
        stalled = self.tcp()
        stalled.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        stalled.expect("AUTOSEND(\"POS\",10)", "ACK AUTOSEND")
        watchers = [self.tcp() for _ in range(3)]
        for w in watchers:
            w.expect("AUTOSEND(\"POS\",10)", "ACK AUTOSEND")
        time.sleep(1.0)  # the stalled client's socket buffers fill up
        rss_before = rss_kib(pid)
        arrivals = [[] for _ in watchers]
        end = time.monotonic() + 4.0
        while time.monotonic() < end:
            for w, times in zip(watchers, arrivals):
                while b"\n" in w.buffer or self._readable(w):
                    line = w.read_line()
                    if line.startswith("@POS="):
                        times.append(time.monotonic())
        for times in arrivals:
            times = times[10:]  # skip the backlog read at the start
            intervals = sorted(b - a for a, b in zip(times, times[1:]))
            self.assertGreater(len(intervals), 250, "a watcher lost its 10 ms stream")
            median = intervals[len(intervals) // 2]
            self.assertAlmostEqual(median, 0.010, delta=0.002)
            self.assertLess(intervals[int(len(intervals) * 0.9)], 0.02)
        self.assertLess(rss_kib(pid) - rss_before, 1024, "memory grows with a stalled reader")
        # the stalled client is still connected and gets whole lines once it reads
        stalled.send("AUTOSEND(\"POS\",0)")
        while True:
            line = stalled.read_line()
            if not line.startswith("@POS="):
                break
            float(line[5:])
        self.assertEqual(line, "ACK AUTOSEND")
        for w in watchers:
            w.send("AUTOSEND(\"POS\",0)")
            while w.read_line() != "ACK AUTOSEND":
                pass
        self.assert_state_kept()

    @staticmethod
    def _readable(client):
        import select
        ready, _, _ = select.select([client.sock], [], [], 0.001)
        if not ready:
            return False
        data = client.sock.recv(65536)
        if not data:
            raise GclError("watcher connection closed")
        client.buffer += data
        return b"\n" in client.buffer


class DatagramAbuse(AbuseCase):
    def test_udp_garbage_and_oversize_datagrams(self):
        rng = random.Random(6)
        junk = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        junk.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 1 << 20)
        target = ("127.0.0.1", self.sim.udp_port)
        junk.sendto(b"", target)
        junk.sendto(b"A" * 65507, target)  # the largest IPv4 datagram
        junk.sendto(b"POS?\n" * 13000, target)  # 65000 bytes of commands
        for _ in range(500):
            junk.sendto(bytes(rng.randrange(256) for _ in range(rng.randrange(1, 600))), target)
        # many peers: more than the server tracks
        peers = []
        for _ in range(40):
            p = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            p.sendto(b"\xff\x00garbage\n", target)
            peers.append(p)
        for p in peers:
            p.close()
        junk.close()
        u = self.sim.udp()
        self.clients.append(u)
        # the flood may still fill the server's receive buffer: a UDP client
        # retries a datagram that got no answer, as drivers do
        for _ in range(5):
            try:
                reply = u.command("POS?", timeout=1.0)
                break
            except GclError:
                continue
        self.assertEqual(reply, "POS=%.1f" % POSITION)
        u.expect("POS?", "POS=%.1f" % POSITION)
        u.expect("GRIPSTATE?", "GRIPSTATE=0")
        self.assert_state_kept()


if __name__ == "__main__":
    unittest.main()
