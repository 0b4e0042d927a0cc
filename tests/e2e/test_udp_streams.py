# SPDX-License-Identifier: BSD-3-Clause
"""Streams obey the UDP budget (docs/behaviour.md, "Network hardening"):
what the device sends a UDP peer, automatic updates and AUTOSEND included,
stays within 8 times what the peer sent, so one spoofed subscription aimed
at a victim earns almost nothing; a client that talks keeps its stream;
--udp-stream-allow gives the listed addresses the real device's stream
without talking (wsg50-ros-pkg's auto_update).

A client on the same host (a loopback source: 127.0.0.0/8, ::1, or IPv4
loopback on a dual-stack socket) needs no list: no other host can send
from its address, so its streams are the real device's.

The budget needs a peer that is not on loopback: those tests run in a
network namespace of their own (netns.py) whose loopback interface also
carries VICTIM, an address of another host as the device sees it. A
spoofed sender is a socket bound to VICTIM; the victim is a socket on
VICTIM at the port the device answers. Everything timed runs on the paused
simulated clock (STEP), so nothing depends on machine speed.
"""
import os
import select
import socket
import struct
import subprocess
import sys
import tempfile
import unittest

from gclclient import Wsgsim
from netns import in_netns

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402

UDP_OVERHEAD = 28  # IPv4 + UDP headers, counted on both sides by the budget
BUDGET_MULTIPLE = 8
VICTIM = "192.0.2.9"  # a documentation address (RFC 5737): another host
STREAM_IDS = (0x40, 0x41, 0x43, 0x44, 0x45)  # every value with automatic updates
E_SUCCESS, E_CMD_PENDING = 0, 26


def free_udp_port(host="127.0.0.1"):
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind((host, 0))
        return s.getsockname()[1]


def subscribe(frame_id, period_ms, flags=1):
    return wb.encode_frame(frame_id, struct.pack("<BH", flags, period_ms))


# A reply is waited for this long at most: a bound against hangs, not a
# speed (the server may run under valgrind on a busy machine).
REPLY_TIMEOUT_S = 30.0


def drain(sock, wait=0.5):
    """Every datagram queued on sock, after waiting up to `wait` for the first."""
    got = []
    ready, _, _ = select.select([sock], [], [], wait)
    while ready:
        got.append(sock.recv(65536))
        ready, _, _ = select.select([sock], [], [], 0)
    return got


def wire_bytes(datagrams):
    return sum(len(d) + UDP_OVERHEAD for d in datagrams)


class StreamCase(unittest.TestCase):
    def start(self, *args, client_host=VICTIM):
        self.bin_port = free_udp_port()
        self.reply_port = free_udp_port(client_host)
        self.sim = Wsgsim("--start-paused", "--sim-port", "0", "--binary-udp-port",
                          str(self.bin_port), "--binary-udp-reply-port", str(self.reply_port),
                          *args)
        self.sim.start()
        self.addCleanup(self.sim.stop)
        self.ctl = self.sim.control()
        self.addCleanup(self.ctl.close)

    def step(self, ms):
        self.assertTrue(self.ctl("STEP(%d)" % ms).startswith("STEP="))

    def udp_socket(self, host, port=0):
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.addCleanup(s.close)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 22)
        s.bind((host, port))
        return s

    def forged_binary_subscription(self):
        """One datagram 'from' the victim subscribing to every stream every
        5 ms; returns the bytes sent (headers counted) and the victim's socket."""
        victim = self.udp_socket(VICTIM, self.reply_port)
        forger = self.udp_socket(VICTIM)
        datagram = b"".join(subscribe(i, 5) for i in STREAM_IDS)
        forger.sendto(datagram, ("127.0.0.1", self.bin_port))
        return len(datagram) + UDP_OVERHEAD, victim

    def silent_subscriber(self, frame_ids, host=VICTIM):
        """wsg50-ros-pkg's auto_update over UDP: subscriptions every 20 ms from
        host, then nothing."""
        ros = wb.BinUdp("127.0.0.1", self.bin_port, reply_port=self.reply_port, timeout=30.0,
                        bind_host=host)
        self.addCleanup(ros.close)
        ros.send_sock.bind((host, 0))
        for frame_id in frame_ids:
            ros.send(subscribe(frame_id, 20))
            self.assertEqual(ros.wait_for(frame_id).status, E_SUCCESS)
        return ros

    def received_over(self, sock, seconds, step_ms=1000):
        """What sock receives while the clock runs for `seconds`, a step at a
        time. While the stream flows each step waits for its first datagram;
        once a step brought none (a stream held to its budget stays quiet
        for the rest of a 70 s run), the next ones do not wait: what arrives
        late is still read, by a later step or by the last drain."""
        got = []
        wait = 0.2
        for _ in range(seconds * 1000 // step_ms):
            self.step(step_ms)
            arrived = drain(sock, wait)
            wait = 0.2 if arrived else 0
            got += arrived
        return got + drain(sock, 0.5)


class LoopbackPeers(StreamCase):
    """A client on the device's own host listens as long as it likes, past
    the peer timeout too, without --udp-stream-allow: a loopback source
    cannot come from another host, and the stream never leaves this one."""

    def silent_autosend(self, host, family=socket.AF_INET):
        client = socket.socket(family, socket.SOCK_DGRAM)
        self.addCleanup(client.close)
        client.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 22)
        client.bind((host, 0))
        client.sendto(b'AUTOSEND("POS",10)\n', (host, self.sim.udp_port))
        self.assertEqual(drain(client, REPLY_TIMEOUT_S), [b"ACK AUTOSEND\n"])
        return client

    def assert_endless(self, sock, per_second):
        got = self.received_over(sock, 65)  # past the 60 s peer timeout
        self.assertGreaterEqual(len(got), per_second * 65 - 2)
        self.assertGreaterEqual(len(self.received_over(sock, 1)), per_second - 1)
        log = self.sim.drain_log()
        self.assertNotIn("stream paused", log)
        self.assertNotIn("forgotten", log)

    def test_autosend_to_127_0_0_1_never_pauses(self):
        self.start(client_host="127.0.0.1")
        self.assert_endless(self.silent_autosend("127.0.0.1"), 100)  # every 10 ms

    def test_binary_updates_to_loopback_never_pause(self):
        """wsg50-ros-pkg's auto_update on the same host: 0x43 every 20 ms,
        then nothing."""
        self.start(client_host="127.0.0.1")
        ros = self.silent_subscriber((0x43,), host="127.0.0.1")
        self.assert_endless(ros.recv_sock, 50)

    def test_the_whole_loopback_network_and_ipv6_loopback_are_local(self):
        """127.0.0.0/8 is loopback, not 127.0.0.1 alone; on a dual-stack
        socket (--bind ::) an IPv4 client is ::ffff:127.0.0.1 and an IPv6 one
        ::1."""
        self.start("--bind", "::", client_host="127.0.0.1")
        clients = [self.silent_autosend("127.0.0.1"), self.silent_autosend("::1", socket.AF_INET6)]
        other = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.addCleanup(other.close)
        other.bind(("127.3.2.1", 0))
        other.sendto(b'AUTOSEND("POS",10)\n', ("127.0.0.1", self.sim.udp_port))
        self.assertEqual(drain(other, REPLY_TIMEOUT_S), [b"ACK AUTOSEND\n"])
        for sock in clients + [other]:
            self.assertGreaterEqual(len(self.received_over(sock, 5)), 5 * 100 - 2)
        self.assertNotIn("stream paused", self.sim.drain_log())


class SpoofedStreams(StreamCase):
    @in_netns(VICTIM)
    def test_a_forged_binary_subscription_earns_at_most_eight_times_its_size(self):
        self.start()
        sent, victim = self.forged_binary_subscription()
        got = self.received_over(victim, 70)  # past the 60 s peer timeout
        self.assertGreater(len(got), len(STREAM_IDS), "not even the replies arrived")
        self.assertLessEqual(wire_bytes(got), BUDGET_MULTIPLE * sent,
                             "sent %d bytes, the victim got %d in %d datagrams"
                             % (sent, wire_bytes(got), len(got)))
        log = self.sim.drain_log()
        self.assertIn("stream paused", log)
        self.assertIn("--udp-stream-allow %s" % VICTIM, log)

    @in_netns(VICTIM)
    def test_a_forged_autosend_earns_at_most_eight_times_its_size(self):
        self.start()
        victim = self.udp_socket(VICTIM)
        datagram = b"".join(b'AUTOSEND("%s",10)\n' % name for name in
                            (b"POS", b"SPEED", b"FORCE", b"GRIPSTATE", b"TEMP", b"SYSSTATE"))
        victim.sendto(datagram, ("127.0.0.1", self.sim.udp_port))
        got = self.received_over(victim, 10)
        self.assertIn(b"ACK AUTOSEND\n", got)
        self.assertLessEqual(wire_bytes(got), BUDGET_MULTIPLE * (len(datagram) + UDP_OVERHEAD))

    @in_netns(VICTIM)
    def test_the_next_forged_datagram_earns_only_its_own_budget(self):
        self.start()
        sent, victim = self.forged_binary_subscription()
        first = self.received_over(victim, 5)
        forger = self.udp_socket(VICTIM)
        again = subscribe(0x43, 5)
        forger.sendto(again, ("127.0.0.1", self.bin_port))
        second = self.received_over(victim, 5)
        self.assertLessEqual(wire_bytes(first + second),
                             BUDGET_MULTIPLE * (sent + len(again) + UDP_OVERHEAD))


class ListedAddresses(StreamCase):
    def binary(self):
        return os.environ.get("WSGSIM", os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                     "..", "..", "build", "wsgsim"))

    @in_netns(VICTIM)
    def test_a_listed_silent_subscriber_keeps_its_stream(self):
        """wsg50-ros-pkg's auto_update over UDP: 0x43, 0x44, 0x45 every 20 ms,
        then nothing: with its address listed the stream goes on, past the
        peer timeout too, as on the real device."""
        self.start("--udp-stream-allow", "127.0.0.0/29,%s" % VICTIM)
        ros = self.silent_subscriber((0x43, 0x44, 0x45))
        self.step(100)  # the first updates
        drain(ros.recv_sock)
        got = self.received_over(ros.recv_sock, 65)
        late = self.received_over(ros.recv_sock, 1)
        self.assertGreaterEqual(len(got), 3 * 50 * 65 - 30)  # 3 values at 50 Hz
        self.assertGreaterEqual(len(late), 3 * 50 - 3)
        self.assertNotIn("stream paused", self.sim.drain_log())

    @in_netns(VICTIM)
    def test_the_configuration_file_lists_addresses_too(self):
        with tempfile.NamedTemporaryFile("w", suffix=".ini", delete=False) as f:
            f.write("[network]\nudp_stream_allow = 10.1.0.0/16, %s\n" % VICTIM)
        self.addCleanup(os.unlink, f.name)
        self.start("--config", f.name)
        ros = self.silent_subscriber((0x43,))
        self.assertGreaterEqual(len(self.received_over(ros.recv_sock, 5)), 5 * 50 - 2)

    def test_a_malformed_list_stops_the_start(self):
        bad = subprocess.run([self.binary(), "--udp-stream-allow", "127.0.0.1,10.0.0.0/33"],
                             capture_output=True, text=True, timeout=60)
        self.assertEqual(bad.returncode, 2)
        self.assertIn("--udp-stream-allow", bad.stderr)

    @in_netns(VICTIM)
    def test_an_unlisted_silent_subscriber_pauses_and_resumes_when_it_talks(self):
        self.start("--udp-stream-allow", "127.0.0.10")  # someone else
        ros = self.silent_subscriber((0x43, 0x44, 0x45))
        self.received_over(ros.recv_sock, 2)
        self.assertEqual(self.received_over(ros.recv_sock, 2), [], "a silent peer kept its stream")
        ros.send(wb.encode_frame(0x43, struct.pack("<BH", 0, 0)))  # a plain query
        self.assertGreater(len(self.received_over(ros.recv_sock, 1)), 1)


class TalkingClients(StreamCase):
    @in_netns(VICTIM)
    def test_a_client_that_recommands_keeps_every_update(self):
        """Drake's driver while it re-commands: five streams every 20 ms, a
        force limit (0x32) and a pre-position (0x21) every 50 ms. (At rest,
        with nothing to re-command, it sends nothing: then it needs
        --udp-stream-allow like a silent subscriber.)"""
        self.start()
        drake = wb.BinUdp("127.0.0.1", self.bin_port, reply_port=self.reply_port, timeout=30.0,
                          bind_host=VICTIM)
        self.addCleanup(drake.close)
        drake.send_sock.bind((VICTIM, 0))
        for frame_id in STREAM_IDS:
            drake.send(subscribe(frame_id, 20))
            self.assertEqual(drake.wait_for(frame_id).status, E_SUCCESS)
        drain(drake.recv_sock)
        updates = 0
        width = 10.0
        for _ in range(40):  # 2 s
            drake.send(wb.encode_frame(0x32, struct.pack("<f", 40.0)))
            drake.send(wb.encode_frame(0x21, struct.pack("<Bff", 0, width, 420.0)))
            width = 120.0 - width
            self.step(50)
            frames = [wb.deframe(d) for d in drain(drake.recv_sock, 0.2)]
            updates += sum(1 for fs in frames for f in fs if f.id in STREAM_IDS)
        updates += sum(1 for d in drain(drake.recv_sock) for f in wb.deframe(d)
                       if f.id in STREAM_IDS)
        self.assertGreaterEqual(updates, 5 * 100 - 5)  # 5 values at 50 Hz for 2 s
        self.assertNotIn("stream paused", self.sim.drain_log())

    @in_netns(VICTIM)
    def test_a_stream_never_starves_the_final_reply_its_client_waits_for(self):
        """Drake's calibration: five streams every 20 ms, then a homing whose
        final reply it waits for without sending anything; the updates stop
        at the reply reserve, the final reply still goes out."""
        self.start()
        drake = wb.BinUdp("127.0.0.1", self.bin_port, reply_port=self.reply_port, timeout=30.0,
                          bind_host=VICTIM)
        self.addCleanup(drake.close)
        drake.send_sock.bind((VICTIM, 0))
        for frame_id in STREAM_IDS:
            drake.send(subscribe(frame_id, 20))
            self.assertEqual(drake.wait_for(frame_id).status, E_SUCCESS)
        drake.send(wb.encode_frame(0x20, b"\x00"))  # homing, default direction
        self.assertEqual(drake.wait_for(0x20).status, E_CMD_PENDING)
        for _ in range(100):  # up to 10 s of homing, a STEP at a time
            self.step(100)
            finals = [f for d in drain(drake.recv_sock, 0.1) for f in wb.deframe(d)
                      if f.id == 0x20]
            if finals:
                self.assertEqual(finals[0].status, E_SUCCESS, wb.describe(finals[0]))
                return
        self.fail("the homing's final reply never arrived")


if __name__ == "__main__":
    unittest.main()
