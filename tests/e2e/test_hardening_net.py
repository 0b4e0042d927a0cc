# SPDX-License-Identifier: BSD-3-Clause
"""Network hardening: reply loops, reflection, port
sharing, UDP peer eviction, shutdown under load, idle TCP connections,
half-close, a blocked stderr and descriptor exhaustion.

Time-dependent rules run on the simulated clock (--start-paused and STEP on
the control channel), so no test waits for real timeouts; wall-clock bounds
are generous limits against hangs, never assertions on speed.
"""
import json
import os
import re
import resource
import select
import signal
import socket
import sys
import threading
import time
import unittest

from gclclient import GclError, GclTcp, GclUdp, Wsgsim, read_to_end, wait_for
from netns import in_netns

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
import wsgbinproto as wb  # noqa: E402

CONTROL = re.compile(r"ready: .*, control ([^ ,]+):(\d+)")
UDP_OVERHEAD = 28  # IPv4 + UDP headers, counted by the reply budget
UDP_REPLY_MULTIPLE = 8  # docs/behaviour.md: replies <= 8x what a peer sent
UDP_PEER_BURST = 1000  # docs/behaviour.md: datagrams per peer without refill
REPLY_TIMEOUT_S = 30.0  # a reply, at most: a bound against hangs, not a speed
# A peer on another host, as the device sees it: the peer timeout and the
# stream budget apply to it (a loopback peer's streams are endless); its
# tests run in a network namespace with this address on its loopback.
OTHER_HOST = "192.0.2.7"


class Control(GclTcp):
    """The control channel: one reply line per command."""

    def __call__(self, line, timeout=None):
        self.send(line)
        return self.read_line(timeout)

    def json(self, query):
        name, _, value = self(query).partition("=")
        if name + "?" != query:
            raise GclError("%s: unexpected reply" % query)
        return json.loads(value)

    def step(self, ms):
        reply = self("STEP(%d)" % ms, timeout=60)
        if not reply.startswith("STEP="):
            raise GclError("STEP(%d): %r" % (ms, reply))


def datagrams_waiting(sock, wait=0.0):
    """Every datagram already queued on sock (after waiting up to `wait` for the first)."""
    got = []
    ready, _, _ = select.select([sock], [], [], wait)
    while ready:
        got.append(sock.recv(65536))
        ready, _, _ = select.select([sock], [], [], 0)
    return got


def free_udp_port():
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    return s, port


def cpu_seconds(pid):
    """User + system CPU time the process has used so far."""
    with open("/proc/%d/stat" % pid) as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


class NetCase(unittest.TestCase):
    def start(self, *args, control=False):
        if control:
            args = ("--sim-port", "0") + args
        sim = Wsgsim(*args)
        sim.start()
        self.addCleanup(self.stop, sim)
        if not control:
            return sim
        match = CONTROL.search("".join(sim.log))
        self.assertIsNotNone(match, "no control channel in the ready line")
        ctl = Control("127.0.0.1", int(match.group(2)), timeout=30)
        self.addCleanup(ctl.close)
        return sim, ctl

    def stop(self, sim):
        code = sim.stop()
        self.assertEqual(code, 0, "wsgsim did not shut down cleanly:\n" + "".join(sim.log))

    def udp(self, sim, bind=None):
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.addCleanup(s.close)
        if bind is not None:
            s.bind(bind)
        s.connect(("127.0.0.1", sim.udp_port))
        return s

    def tcp(self, sim, timeout=10.0):
        c = sim.tcp(timeout)
        self.addCleanup(c.close)
        return c

    def answered(self, sim, timeout=10.0):
        """A fresh UDP peer gets its answer: the server is alive and serving."""
        u = GclUdp("127.0.0.1", sim.udp_port, timeout)
        self.addCleanup(u.close)
        self.assertTrue(u.command("SN?").startswith("SN="))


# ---- 1. reply loops ----

class ReplyLoops(NetCase):
    def assert_own_reply_ignored(self, *args):
        # binary UDP replies go to the sender's address at the reply port:
        # with the reply port set to the binary port itself, the reply to a
        # local client comes back to the server from its own socket
        holder, port = free_udp_port()
        holder.close()
        sim = self.start(*args, "--binary-udp-port", str(port), "--binary-udp-reply-port", str(port))
        client = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.addCleanup(client.close)
        client.sendto(wb.encode_frame(0x06, b"loop"), ("127.0.0.1", port))
        wait_for("the server's own reply to be ignored",
                 lambda: "datagram from the server's own address ignored" in sim.drain_log(0))
        self.answered(sim)

    def test_datagram_from_own_port_is_not_answered(self):
        self.assert_own_reply_ignored()

    def test_datagram_from_own_port_is_not_answered_on_wildcard_bind(self):
        self.assert_own_reply_ignored("--bind", "0.0.0.0")

    def test_peer_on_the_tcp_ports_number_is_answered(self):
        # UDP and TCP ports are two spaces: a peer whose UDP port has the
        # number of the GCL TCP port is an ordinary peer. Before, it was taken
        # for the server itself, so a client whose ephemeral port happened to
        # get that number was never answered.
        sim = self.start()
        peer = self.udp(sim, bind=("127.0.0.1", sim.tcp_port))
        peer.send(b"SN?\n")
        replies = datagrams_waiting(peer, 30.0)
        self.assertTrue(replies and replies[0].startswith(b"SN="), replies)

    def test_ping_pong_between_two_instances_dies_out(self):
        # A streams to a port where B starts afterwards: one AUTOSEND line
        # starts A and B answering each other's error replies
        a, ctl_a = self.start("--start-paused", control=True)
        holder, b_port = free_udp_port()
        holder.connect(("127.0.0.1", a.udp_port))
        holder.send(b'AUTOSEND("POS",10)\n')
        self.assertEqual(holder.recv(100), b"ACK AUTOSEND\n")
        holder.close()
        b, ctl_b = self.start("--start-paused", "--udp-port", str(b_port), control=True)
        ctl_a.step(10)  # one @POS line from A to B
        counts = []
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            sessions = [s for s in ctl_a.json("STATE?")["sessions"] if s["transport"] == "udp"]
            counts.append(sum(s["lines_in"] for s in sessions))
            if len(counts) >= 3 and counts[-1] == counts[-3]:
                break
            time.sleep(0.25)
        self.assertTrue(len(counts) >= 3 and counts[-1] == counts[-3],
                        "the loop still runs: A received %s lines" % counts)
        self.assertLessEqual(counts[-1], 2 * UDP_PEER_BURST + 10)
        self.answered(a)
        self.answered(b)
        self.assertIn("budget", a.drain_log() + b.drain_log())


# ---- 2. reflection and amplification ----

class Reflection(NetCase):
    def test_replies_bounded_by_what_the_peer_sent(self):
        sim, _ = self.start("--start-paused", control=True)
        s = self.udp(sim)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 20)
        sent = [b"VERBOSE=1\n", b"X\n" * 60]  # 60 unknown commands, long verbose errors
        received = []
        for datagram in sent:
            s.send(datagram)
            received += datagrams_waiting(s, 2.0)
        self.answered(sim)
        received += datagrams_waiting(s)
        sent_bytes = sum(len(d) + UDP_OVERHEAD for d in sent)
        got_bytes = sum(len(d) + UDP_OVERHEAD for d in received)
        self.assertLessEqual(got_bytes, UDP_REPLY_MULTIPLE * sent_bytes,
                             "sent %d bytes, got %d in %d datagrams"
                             % (sent_bytes, got_bytes, len(received)))
        self.assertEqual(received[0], b"VERBOSE=1\n")

    def stream_after(self, ctl, s, ms):
        ctl.step(ms)
        return [d for d in datagrams_waiting(s, 0.5) if d.startswith(b"@")]

    @in_netns(OTHER_HOST)
    def test_autosend_ends_when_the_peer_is_silent_default_60_s(self):
        sim, ctl = self.start("--start-paused", control=True)
        s = self.udp(sim, bind=(OTHER_HOST, 0))
        s.send(b"\n" * 8000)  # blank lines: no reply, a full budget for the stream
        s.send(b'AUTOSEND("POS",1000)\n')
        self.assertEqual(datagrams_waiting(s, REPLY_TIMEOUT_S), [b"ACK AUTOSEND\n"])
        self.assertGreaterEqual(len(self.stream_after(ctl, s, 59000)), 58)
        late = self.stream_after(ctl, s, 2000)  # the peer has been silent for 61 s
        self.assertLessEqual(len(late), 1)
        self.assertEqual(self.stream_after(ctl, s, 5000), [], "AUTOSEND outlived a silent peer")
        self.assertIn("silent", sim.drain_log())

    @in_netns(OTHER_HOST)
    def test_a_listening_peer_keeps_its_stream(self):
        sim, ctl = self.start("--start-paused", "--udp-peer-timeout", "2", control=True)
        s = self.udp(sim, bind=(OTHER_HOST, 0))
        s.send(b'AUTOSEND("POS",500)\n')
        self.assertEqual(datagrams_waiting(s, REPLY_TIMEOUT_S), [b"ACK AUTOSEND\n"])
        for _ in range(5):  # a line every 1.5 s keeps it going (and pays for it)
            self.assertGreaterEqual(len(self.stream_after(ctl, s, 1500)), 2)
            s.send(b"POS?\n")
            self.assertTrue(datagrams_waiting(s, REPLY_TIMEOUT_S)[0].startswith(b"POS="))
        self.assertLessEqual(len(self.stream_after(ctl, s, 2500)), 5)  # ends 2 s after POS?
        self.assertEqual(self.stream_after(ctl, s, 2000), [])


# ---- 3. port takeover ----

class PortSharing(NetCase):
    def test_udp_port_cannot_be_bound_twice(self):
        sim = self.start()
        other = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.addCleanup(other.close)
        other.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        with self.assertRaises(OSError, msg="another socket bound the server's UDP port"):
            other.bind(("127.0.0.1", sim.udp_port))
        self.answered(sim)


# ---- 4. eviction ----

class Eviction(NetCase):
    def test_peer_with_a_running_motion_is_not_evicted(self):
        sim, ctl = self.start("--start-paused", control=True)
        worker = GclUdp("127.0.0.1", sim.udp_port)
        self.addCleanup(worker.close)
        worker.expect("VERBOSE=1", "VERBOSE=1")
        worker.expect("HOME()", "ACK HOME")
        newcomers = []
        for _ in range(16):  # the table holds 16 peers: 15 more fit
            p = self.udp(sim)
            p.send(b"SN?\n")
            newcomers.append(p)
        # the 15 that fit are answered (waited for as replies are); the 17th
        # peer is not, which takes a wait of its own
        replies = [datagrams_waiting(p, REPLY_TIMEOUT_S) for p in newcomers[:15]]
        self.assertTrue(all(replies), "answers to the first 15 newcomers: %r" % replies)
        self.assertEqual(datagrams_waiting(newcomers[15], 1.0), [],
                         "a 17th peer pushed out a live one")
        ctl.step(5000)
        self.assertEqual(worker.read_line(), "FIN HOME")
        worker.expect("VERBOSE?", "VERBOSE=1")
        self.assertIn("refused", sim.drain_log())
        ctl.step(3000)  # everybody quiet for over 2 s: room can be made again
        self.answered(sim)


# ---- 6. shutdown under load ----

class Shutdown(NetCase):
    def test_sigterm_during_a_flood_of_blank_lines(self):
        sim = self.start()
        stop = threading.Event()

        def flood():
            try:
                s = socket.create_connection(("127.0.0.1", sim.tcp_port))
                while not stop.is_set():
                    s.sendall(b"\n" * 65536)
            except OSError:
                pass

        threads = [threading.Thread(target=flood, daemon=True) for _ in range(2)]
        for t in threads:
            t.start()
        self.addCleanup(stop.set)
        time.sleep(0.5)  # the flood is under way
        self.assertTrue(sim.alive())
        sim.proc.send_signal(signal.SIGTERM)
        try:
            sim.proc.wait(timeout=10)
        except Exception:
            pass
        exited = sim.proc.poll() is not None
        stop.set()
        self.assertTrue(exited, "wsgsim ignored SIGTERM while clients flooded it")


# ---- 7. idle connections ----

def tcp_timer(server_port, client_port):
    """The kernel timer of the server side of a loopback connection (/proc/net/tcp 'tr')."""
    with open("/proc/net/tcp") as f:
        for line in f.readlines()[1:]:
            fields = line.split()
            if fields[1].endswith(":%04X" % server_port) and \
                    fields[2].endswith(":%04X" % client_port):
                return int(fields[5].split(":")[0], 16)
    raise AssertionError("no server socket for port %d" % client_port)


class IdleConnections(NetCase):
    def test_keepalive_is_enabled(self):
        sim = self.start()
        c = self.tcp(sim)
        self.assertTrue(c.command("SN?").startswith("SN="))
        # once the reply's own timers are done, an idle connection has the
        # keepalive timer (2) running, or no timer at all (0) without keepalive
        deadline = time.monotonic() + 10
        timer = tcp_timer(sim.tcp_port, c.sock.getsockname()[1])
        while timer not in (0, 2) and time.monotonic() < deadline:
            time.sleep(0.1)
            timer = tcp_timer(sim.tcp_port, c.sock.getsockname()[1])
        self.assertEqual(timer, 2, "no keepalive timer on an idle connection")

    def test_silent_connection_gives_up_its_slot_to_a_waiting_client(self):
        sim, ctl = self.start("--start-paused", "--max-clients", "2", control=True)
        speaker = self.tcp(sim)
        speaker.expect("FSACK()", "ACK FSACK")
        silent = self.tcp(sim)
        early = self.tcp(sim)
        self.assertTrue(early.closed_by_peer(5), "a third client was let in at once")
        ctl.step(31000)
        late = self.tcp(sim)
        self.assertTrue(late.command("SN?").startswith("SN="))
        self.assertTrue(silent.closed_by_peer(5), "the silent connection kept its slot")
        speaker.expect("GRIPSTATE?", "GRIPSTATE=0")  # the speaker stays
        extra = self.tcp(sim)
        self.assertTrue(extra.closed_by_peer(5), "a client that spoke was pushed out")
        self.assertIn("silent", sim.drain_log())

    def test_idle_timeout_closes_a_quiet_connection(self):
        sim, ctl = self.start("--start-paused", "--idle-timeout", "5", control=True)
        c = self.tcp(sim)
        keeper = self.tcp(sim)
        for _ in range(3):
            c.expect("GRIPSTATE?", "GRIPSTATE=0")
            keeper.expect("GRIPSTATE?", "GRIPSTATE=0")
            ctl.step(4000)
        keeper.expect("GRIPSTATE?", "GRIPSTATE=0")
        ctl.step(2000)  # c silent for 6 s
        self.assertTrue(c.closed_by_peer(5), "--idle-timeout did not close a quiet connection")
        keeper.expect("SYSFLAGS[12]?", "SYSFLAGS[12]=0")  # a timeout is not a lost link
        self.assertIn("idle", sim.drain_log())

    def test_quiet_connections_stay_by_default(self):
        sim, ctl = self.start("--start-paused", control=True)
        c = self.tcp(sim)
        c.expect("FSACK()", "ACK FSACK")
        ctl.step(3600000)
        c.expect("GRIPSTATE?", "GRIPSTATE=0")


# ---- 8. half-close ----

class HalfClose(NetCase):
    def test_every_reply_is_delivered_after_shut_wr(self):
        sim = self.start()
        keeper = self.tcp(sim)
        keeper.expect("FSACK()", "ACK FSACK")
        count = 5000
        c = socket.create_connection(("127.0.0.1", sim.tcp_port))
        self.addCleanup(c.close)
        c.sendall(b"SN?\n" * count)
        c.shutdown(socket.SHUT_WR)
        data = b""
        c.settimeout(30)
        while True:
            chunk = c.recv(65536)
            if not chunk:
                break
            data += chunk
        lines = data.split(b"\n")[:-1]
        self.assertEqual(len(lines), count, "replies delivered after SHUT_WR")
        self.assertTrue(all(line.startswith(b"SN=") for line in lines))
        # then the manual's rule: closed without BYE raises FAST STOP
        keeper.expect("SYSFLAGS[12]?", "SYSFLAGS[12]=1")

    def test_replies_still_held_are_delivered_after_shut_wr(self):
        # replies held back inside the server (here by an injected DELAY on
        # the paused clock) are delivered before the connection closes
        sim, ctl = self.start("--start-paused", control=True)
        c = socket.create_connection(("127.0.0.1", sim.tcp_port))
        self.addCleanup(c.close)
        c.sendall(b"GRIPSTATE?\n")
        c.settimeout(30)
        self.assertEqual(c.recv(100), b"GRIPSTATE=0\n")
        session = [s["id"] for s in ctl.json("SESSIONS?") if s["transport"] == "tcp"][0]
        self.assertEqual(ctl("DELAY(500,%d)" % session), "ACK DELAY")
        c.sendall(b"SN?\n" * 5)
        c.shutdown(socket.SHUT_WR)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:  # the server has read all five
            state = ctl.json("STATE?")
            lines_in = [s["lines_in"] for s in state["sessions"] if s["id"] == session]
            if lines_in == [6]:
                break
            time.sleep(0.05)
        ctl.step(600)
        data = b""
        while True:
            chunk = c.recv(65536)
            if not chunk:
                break
            data += chunk
        self.assertEqual(data.count(b"SN="), 5, data)

    def test_half_close_after_bye_closes_cleanly(self):
        sim = self.start()
        c = socket.create_connection(("127.0.0.1", sim.tcp_port))
        self.addCleanup(c.close)
        c.sendall(b"SN?\nBYE()\n")
        c.shutdown(socket.SHUT_WR)
        c.settimeout(30)
        data = b""
        while True:
            chunk = c.recv(65536)
            if not chunk:
                break
            data += chunk
        self.assertTrue(data.endswith(b"ACK BYE\n"), data)
        keeper = self.tcp(sim)
        keeper.expect("SYSFLAGS[12]?", "SYSFLAGS[12]=0")


# ---- 9. a blocked stderr ----

class BlockedStderr(NetCase):
    def test_device_answers_while_nobody_reads_its_log(self):
        sim = self.start("--trace")  # nobody reads its stderr from here on
        c = self.tcp(sim)
        c.send_raw(b"SN?\n" * 4000)  # --trace logs 8000 lines: far beyond a pipe
        for i in range(4000):
            self.assertTrue(c.read_line(20).startswith("SN="), "reply %d" % i)
        for i in range(300):  # each connection is logged too
            s = socket.create_connection(("127.0.0.1", sim.tcp_port), timeout=10)
            s.close()
        fresh = self.tcp(sim)
        self.assertTrue(fresh.command("SN?").startswith("SN="))
        # once the log is read again, the loss is reported
        sim.drain_log(0.5)
        self.assertTrue(self.tcp(sim).command("SN?").startswith("SN="))
        self.assertRegex(sim.drain_log(1.0), r"\d+ log lines dropped")


# ---- 10. descriptor exhaustion ----

class DescriptorExhaustion(NetCase):
    def test_listener_backs_off_at_the_descriptor_limit(self):
        sim = self.start("--max-clients", "32")
        pid = sim.proc.pid
        low_fds = [int(fd) for fd in os.listdir("/proc/%d/fd" % pid) if int(fd) < 256]
        _, hard = resource.prlimit(pid, resource.RLIMIT_NOFILE)
        resource.prlimit(pid, resource.RLIMIT_NOFILE, (max(low_fds) + 3, hard))
        clients = [self.tcp(sim) for _ in range(2)]
        for c in clients:
            c.expect("GRIPSTATE?", "GRIPSTATE=0")
        waiting = [socket.create_connection(("127.0.0.1", sim.tcp_port)) for _ in range(4)]
        for w in waiting:
            self.addCleanup(w.close)
            w.sendall(b"SN?\n")
        time.sleep(0.5)  # the server has seen the waiting connections
        used_before = cpu_seconds(pid)
        time.sleep(2.0)
        used = cpu_seconds(pid) - used_before
        self.assertLess(used, 1.0, "the loop spins at the descriptor limit (%.2f s CPU in 2 s)"
                        % used)
        self.assertEqual(sim.drain_log().count("descriptors"), 1, "logged once")
        clients[0].expect("BYE()", "ACK BYE")
        self.assertTrue(clients[0].closed_by_peer(5))
        answered = 0
        for w in waiting:  # a freed descriptor serves a waiting client
            ready, _, _ = select.select([w], [], [], 0 if answered else 10)
            if ready:
                answered += w.recv(100).startswith(b"SN=")
        self.assertGreaterEqual(answered, 1, "no waiting client was served")
        clients[1].expect("GRIPSTATE?", "GRIPSTATE=0")

    def test_control_listener_backs_off_at_the_descriptor_limit(self):
        sim, ctl = self.start(control=True)
        self.assertTrue(ctl("SIMTIME?").startswith("SIMTIME="))  # ctl has its descriptor
        pid = sim.proc.pid
        low_fds = [int(fd) for fd in os.listdir("/proc/%d/fd" % pid) if int(fd) < 256]
        _, hard = resource.prlimit(pid, resource.RLIMIT_NOFILE)
        resource.prlimit(pid, resource.RLIMIT_NOFILE, (max(low_fds) + 2, hard))
        gcl = self.tcp(sim)  # takes the last free descriptor
        gcl.expect("GRIPSTATE?", "GRIPSTATE=0")
        control_port = ctl.sock.getpeername()[1]
        waiting = [socket.create_connection(("127.0.0.1", control_port)) for _ in range(3)]
        for w in waiting:
            self.addCleanup(w.close)
            w.sendall(b"SIMTIME?\n")
        self.assertTrue(wait_for_log(sim, "control: cannot accept"), "no log of the starved listener")
        used_before = cpu_seconds(pid)
        time.sleep(2.0)
        used = cpu_seconds(pid) - used_before
        self.assertLess(used, 1.0, "the loop spins at the descriptor limit (%.2f s CPU in 2 s)"
                        % used)
        self.assertTrue(ctl("SIMTIME?").startswith("SIMTIME="), "the open control client is served")
        self.assertEqual(sim.drain_log().count("control: cannot accept"), 1, "logged once")
        gcl.expect("BYE()", "ACK BYE")
        self.assertTrue(gcl.closed_by_peer(5))
        ready, _, _ = select.select(waiting, [], [], 30)
        self.assertTrue(ready, "no waiting control client was served after a descriptor freed")
        self.assertTrue(ready[0].recv(100).startswith(b"SIMTIME="))


def wait_for_log(sim, text, bound=30.0):
    """Waits (at most `bound` seconds, a hang guard) until the server logged text."""
    deadline = time.monotonic() + bound
    while time.monotonic() < deadline:
        if text in sim.drain_log():
            return True
    return False


class CrossProtocol(NetCase):
    """A web page can make a browser POST anything to the GCL port (1000 is
    on no browser's list of refused ports): the body's lines would run as
    commands (MOVE, GRIP, FASTSTOP), and the browser's close without BYE
    would raise FAST STOP. A line only HTTP sends closes the connection at
    once, unanswered and announced, before anything after it runs."""

    BODY = b"MOVE(0)\nFASTSTOP()\n"

    def attack(self, sim, *pieces):
        with socket.create_connection(("127.0.0.1", sim.tcp_port), timeout=60) as sock:
            for piece in pieces:
                sock.sendall(piece)
            sock.shutdown(socket.SHUT_WR)
            return read_to_end(sock)

    def test_a_browsers_post_to_the_gcl_port_runs_nothing(self):
        sim = self.start()
        gcl = self.tcp(sim)
        flags, position = gcl.command("SYSFLAGS?"), gcl.command("POS?")
        request = (b"POST / HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nOrigin: http://evil.example\r\n"
                   b"Content-Type: text/plain\r\nContent-Length: %d\r\n\r\n"
                   % (sim.tcp_port, len(self.BODY)) + self.BODY)
        self.assertEqual(self.attack(sim, request), b"")  # not one reply: closed at once
        self.assertEqual(self.attack(sim, b"Host: x\r\n" + self.BODY), b"")
        self.assertEqual(self.attack(sim, b"SN?\nGET /", b"?a HTTP/1.1\r\n\r\n" + self.BODY),
                         b"SN=12345678\n")
        # no FAST STOP: neither the body's nor the one a close without BYE raises
        self.assertEqual(gcl.command("SYSFLAGS?"), flags)
        self.assertEqual(gcl.command("POS?"), position)
        log = sim.drain_log()
        self.assertEqual(log.count("an HTTP request (a web page's cross-protocol request?); "
                                   "closed without running it"), 3, log)


if __name__ == "__main__":
    unittest.main()
