# SPDX-License-Identifier: BSD-3-Clause
"""Wire conditions (docs/network.md): what --net and the control channel's
NET do to what the device sends, observed on the paused simulated clock
(STEP) and counted by NET?, never timed on the wall clock.

A write the server made before it answered a control command is in the
client's socket once that answer is read (both on loopback, the write
first): "nothing yet" is read without waiting right after a STEP, and
"it came" with a blocking read bounded only against hangs.
"""
import os
import select
import socket
import subprocess
import sys
import threading
import unittest

from gclclient import ROOT, DEFAULT_TIMEOUT, GclError, GclTcp, Wsgsim

sys.path.insert(0, os.path.join(ROOT, "tools"))
import wsgbinproto as wb  # noqa: E402

HANG_LIMIT_S = 60
WIDTH_ONCE = bytes(3)  # get-width's flags and period: no automatic update


def pending_bytes(sock):
    """What the socket holds now, without waiting."""
    data = b""
    while select.select([sock], [], [], 0)[0]:
        chunk = sock.recv(65536)
        if not chunk:
            break
        data += chunk
    return data


def naive_reply(sock, line):
    """A client that takes one recv() for one reply: the bug the wire shows."""
    sock.sendall(line.encode() + b"\n")
    return sock.recv(65536).decode()


class WireBase(unittest.TestCase):
    def start(self, *args, **keywords):
        sim = Wsgsim("--fingers", "none,none", *args, **keywords)
        sim.start()
        self.addCleanup(sim.stop)
        return sim

    def control(self, sim):
        ctl = sim.control()
        self.addCleanup(ctl.close)
        return ctl

    def tcp(self, sim):
        client = sim.tcp()
        self.addCleanup(client.close)
        return client

    def raw(self, sim):
        sock = socket.create_connection((sim.host, sim.tcp_port), timeout=HANG_LIMIT_S)
        self.addCleanup(sock.close)
        return sock

    def wait_served(self, ctl, transport, served):
        """Polls NET? until the session's wire has counted served (what its
        datagrams or lines have cost so far), so the next STEP comes after
        them: input and control commands arrive on different sockets."""
        for _ in range(HANG_LIMIT_S * 20):
            stats = self.session_stats(ctl, transport)
            if stats and served(stats[0]):
                return
            select.select([], [], [], 0.05)
        self.fail("the input was not served")

    def session_stats(self, ctl, transport):
        sessions = ctl.json("NET?")["sessions"]
        return [s for s in sessions if s["transport"] == transport]


class TcpSegments(WireBase):
    def test_a_split_reply_arrives_in_parts_as_the_clock_steps(self):
        sim = self.start(paused=True)
        ctl = self.control(sim)
        self.assertEqual(ctl('NET("split=4,gap=5")'), "ACK NET")
        sock = self.raw(sim)
        sock.sendall(b"POS?\n")
        parts = [sock.recv(65536)]  # the first part leaves at once
        for _ in range(8):
            ctl.step(5)
            more = pending_bytes(sock)
            if more:
                parts.append(more)
        self.assertEqual(b"".join(parts), b"POS=55.0\n")
        self.assertGreater(len(parts), 1, "the reply came whole: %r" % parts)
        self.assertFalse(parts[0].endswith(b"\n"))
        [stats] = self.session_stats(ctl, "tcp")
        self.assertEqual(stats["messages"], 1)
        self.assertEqual(stats["split"], 1)
        self.assertEqual(stats["writes"], len(parts))

    def test_a_client_reading_one_reply_per_recv_fails_one_buffering_lines_passes(self):
        sim = self.start(paused=True)
        ctl = self.control(sim)
        whole = "POS=55.0\n"
        self.assertEqual(naive_reply(self.raw(sim), "POS?"), whole)  # an ideal wire hides it
        ctl('NET("split=4,gap=5")')
        self.assertNotEqual(naive_reply(self.raw(sim), "POS?"), whole)
        buffering = self.tcp(sim)
        got = []
        reader = threading.Thread(target=lambda: got.append(buffering.command("POS?")))
        reader.start()
        steps = 0
        while reader.is_alive() and steps < 200:
            ctl.step(5)
            reader.join(0.05)
            steps += 1
        reader.join(HANG_LIMIT_S)
        self.assertEqual(got, ["POS=55.0"])

    def test_coalescing_joins_replies_into_one_write(self):
        sim = self.start(paused=True)
        ctl = self.control(sim)
        ctl('NET("coalesce=10")')
        sock = self.raw(sim)
        sock.sendall(b"POS?\nGRIPSTATE?\nPOS?\n")
        self.wait_served(ctl, "tcp", lambda st: st["messages"] == 3)
        ctl.step(5)
        self.assertEqual(pending_bytes(sock), b"")
        ctl.step(5)
        sock.settimeout(HANG_LIMIT_S)
        data = b""
        while data.count(b"\n") < 3:
            data += sock.recv(65536)
        self.assertEqual(data, b"POS=55.0\nGRIPSTATE=0\nPOS=55.0\n")
        [stats] = self.session_stats(ctl, "tcp")
        self.assertEqual((stats["messages"], stats["writes"], stats["joined"]), (3, 1, 1))

    def test_latency_holds_a_reply_for_its_simulated_time(self):
        sim = self.start(paused=True)
        ctl = self.control(sim)
        ctl('NET("latency=30")')
        sock = self.raw(sim)
        sock.sendall(b"POS?\n")
        self.wait_served(ctl, "tcp", lambda st: st["messages"] == 1)
        ctl.step(29)
        self.assertEqual(pending_bytes(sock), b"")
        ctl.step(1)
        sock.settimeout(HANG_LIMIT_S)
        self.assertEqual(sock.recv(65536), b"POS=55.0\n")

    def test_a_later_reply_never_overtakes_an_earlier_one(self):
        sim = self.start(paused=True)
        ctl = self.control(sim)
        ctl('NET("latency=1,jitter=40,split=3,gap=0-7,seed=3")')
        sock = self.raw(sim)
        queries = [b"POS?\n", b"GRIPSTATE?\n", b"SPEED?\n", b"FORCE?\n"] * 10
        for q in queries:
            sock.sendall(q)
        data = b""
        for _ in range(100):
            ctl.step(10)
            data += pending_bytes(sock)
        names = [line.split(b"=")[0] for line in data.split(b"\n")[:-1]]
        self.assertEqual(names, [q[:-2] for q in queries])

    def test_per_session_conditions_leave_other_sessions_whole(self):
        sim = self.start(paused=True)
        ctl = self.control(sim)
        shaped, plain = self.tcp(sim), self.raw(sim)
        shaped.expect("POS?", "POS=55.0")
        ctl('NET("split=4,gap=5",1)')
        self.assertEqual(naive_reply(plain, "POS?"), "POS=55.0\n")
        net = ctl.json("NET?")
        self.assertEqual(net["all"], "off")
        self.assertEqual([(s["session"], s["net"]) for s in net["sessions"]],
                         [(1, "split=4,gap=5")])
        ctl('NET("off",1)')
        self.assertEqual(ctl.json("NET?")["sessions"], [])


class TcpReset(WireBase):
    def test_a_reset_closes_the_connection_and_the_device_keeps_its_state(self):
        sim = self.start("--no-disconnect-faststop", paused=True)
        ctl = self.control(sim)
        c = self.tcp(sim)
        c.expect("HOME()", "ACK HOME")
        ctl.step_until(c, "FIN HOME")
        c.expect("MOVE(40)", "ACK MOVE")
        ctl.step_until(c, "FIN MOVE")
        self.assertEqual(ctl('NET("reset=50",1)'), "ACK NET")
        ctl.step(50)
        with self.assertRaises(GclError):
            c.read_line(HANG_LIMIT_S)
        self.assertIn("connection reset (wire conditions)", sim.drain_log())
        after = self.tcp(sim)
        after.expect("POS?", "POS=40.0")
        after.expect("GRIPSTATE?", "GRIPSTATE=0")
        self.assertEqual([s["id"] for s in ctl.json("SESSIONS?")], [2])


class UdpConditions(WireBase):
    def udp_round(self, seed=None, count=120, run_seed=None):
        """count queries over UDP under loss, duplication and reordering
        (their seed= item seed, None: none; the run's --seed run_seed);
        (answers in arrival order, the wire's counts)."""
        net = "loss=0.2,dup=0.2,reorder=0.2" + ("" if seed is None else ",seed=%d" % seed)
        args = () if run_seed is None else ("--seed", str(run_seed))
        sim = self.start(*args, paused=True, net=net)
        ctl = self.control(sim)
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.addCleanup(sock.close)
        sock.connect((sim.host, sim.udp_port))
        queries = [("POS?", "GRIPSTATE?", "SPEED?")[i % 3] for i in range(count)]
        for q in queries:
            sock.send(q.encode() + b"\n")
        # each datagram lost on its way in, served once, or twice (a copy)
        self.wait_served(ctl, "udp", lambda st: st["messages"] - st["dup_in"] + st["lost_in"] ==
                         count)
        ctl.step(10)  # the reordered ones
        answers = []
        while select.select([sock], [], [], 0)[0]:
            answers.append(sock.recv(65536).decode().split("=")[0])
        [stats] = self.session_stats(ctl, "udp")
        return queries, answers, stats

    def test_loss_duplication_and_reordering_are_counted_and_the_seed_repeats_them(self):
        queries, answers, stats = self.udp_round(seed=7)
        for key in ("lost_in", "dup_in", "lost_out", "dup_out", "reordered"):
            self.assertGreater(stats[key], 0, key)
        served = len(queries) - stats["lost_in"] + stats["dup_in"]
        self.assertEqual(stats["messages"], served)
        self.assertEqual(len(answers), served - stats["lost_out"] + stats["dup_out"])
        self.assertNotEqual(answers, sorted(answers, key=[q[:-1] for q in queries].index))
        again = self.udp_round(seed=7)
        self.assertEqual(again[1:], (answers, stats))
        other = self.udp_round(seed=8)
        self.assertNotEqual(other[2], stats)

    def test_the_runs_seed_seeds_the_wire_unless_the_conditions_name_one(self):
        first = self.udp_round(run_seed=5)
        self.assertEqual(self.udp_round(run_seed=5), first)
        self.assertNotEqual(self.udp_round(run_seed=6)[1:], first[1:])
        named = self.udp_round(seed=7, run_seed=5)
        self.assertEqual(self.udp_round(seed=7, run_seed=6), named)
        self.assertNotEqual(named[1:], first[1:])

    def test_net_query_shows_the_seed_the_wires_draw_from(self):
        sim = self.start("--seed", "42", net="loss=0.1", control=True)
        ctl = self.control(sim)
        self.assertEqual(ctl.json("NET?")["seed"], 42)
        ctl('NET("seed=9")')
        self.assertEqual(ctl.json("NET?")["seed"], 9)


class ClientsUnderRough(WireBase):
    """The project's clients are correct readers: a short session of each
    under --net rough on a running clock (their retries and line buffers
    do not depend on how fast the machine is; the bounds only catch hangs)."""

    def test_gcl_tcp_binary_tcp_and_gcl_udp_clients(self):
        sim = self.start("--net", "rough,seed=11", control=True)
        with sim.tcp() as gcl:
            gcl.expect("HOME()", "ACK HOME")
            self.assertEqual(gcl.read_line_skipping_autosend(HANG_LIMIT_S), "FIN HOME")
            self.assertEqual(gcl.long_command("MOVE(30)", "MOVE"), "FIN MOVE")
            for _ in range(20):
                self.assertEqual(gcl.command("POS?"), "POS=30.0")
                gcl.send("GRIPSTATE?")
                gcl.send("SPEED?")  # pipelined: replies may come joined
                self.assertEqual(gcl.read_line(), "GRIPSTATE=0")
                self.assertEqual(gcl.read_line(), "SPEED=0.0")
            [stats] = self.session_stats(self.control(sim), "tcp")
            self.assertGreater(stats["split"], 0)
            self.assertGreater(stats["joined"], 0)
        binary = wb.BinTcp(sim.host, sim.tcp_port, timeout=HANG_LIMIT_S)
        try:
            for _ in range(10):
                reply = binary.request(0x43, WIDTH_ONCE)
                self.assertEqual(reply.status, wb.E_SUCCESS)
                self.assertAlmostEqual(wb._f32(reply.values), 30.0, places=3)
        finally:
            binary.close()

    def test_gcl_udp_client_repeats_lost_queries_and_skips_copies(self):
        sim = self.start("--net", "lossy,seed=4", control=True)
        with sim.udp() as udp:
            for i in range(40):
                query, answer = (("POS?", "POS=55.0"), ("GRIPSTATE?", "GRIPSTATE=0"))[i % 2]
                self.assertEqual(udp.command(query), answer)
            [stats] = self.session_stats(self.control(sim), "udp")
        self.assertGreater(udp.repeated, 0)
        self.assertGreater(stats["lost_in"] + stats["lost_out"], 0)

    def test_binary_udp_client_repeats_lost_readings(self):
        port = free_port()
        sim = self.start("--net", "loss=0.3,seed=5", "--binary-udp-port", port,
                         "--binary-udp-reply-port", "0", control=True)
        client = wb.BinUdp(sim.host, port, reply_port=0, timeout=HANG_LIMIT_S)
        try:
            for _ in range(30):
                self.assertEqual(client.request(0x43, WIDTH_ONCE).status, wb.E_SUCCESS)
        finally:
            client.close()
        self.assertGreater(client.repeated, 0)

    def test_wsgctl_and_wsgbin_under_rough(self):
        sim = self.start("--net", "rough,seed=2", control=True)
        wsgctl = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "wsgctl"), "--port",
                                 str(sim.sim_port), "NET?"], capture_output=True, text=True,
                                timeout=HANG_LIMIT_S)
        self.assertEqual(wsgctl.returncode, 0, wsgctl.stderr)
        self.assertIn('"all":"split=4', wsgctl.stdout)
        wsgbin = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "wsgbin"), "--port",
                                 str(sim.tcp_port), "get-width", "+", "system-info", "+", "get-limits"],
                                capture_output=True, text=True, timeout=HANG_LIMIT_S)
        self.assertEqual(wsgbin.returncode, 0, wsgbin.stderr)
        self.assertIn("55.0", wsgbin.stdout)


def free_port():
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class NetControl(WireBase):
    def test_bad_conditions_are_refused_and_nothing_changes(self):
        sim = self.start(control=True)
        ctl = self.control(sim)
        ctl('NET("split=3")')
        for bad, why in (('NET("bogus")', "unknown preset bogus"),
                         ('NET("loss=2")', "bad item loss=2"),
                         ('NET("gap=5-1")', "bad item gap=5-1"),
                         ('NET("latency=1,rough")', "a preset comes first"),
                         ('NET("split=4,")', "an empty item")):
            reply = ctl(bad)
            self.assertTrue(reply.startswith("ERR NET 24"), reply)
            self.assertIn(why, reply)
        self.assertEqual(ctl('NET("rough",99)'), "ERR NET 21 no open session 99 (see SESSIONS?)")
        self.assertEqual(ctl.json("NET?")["all"], "split=3,gap=0.5-3")

    def test_a_preset_replaces_and_items_add(self):
        sim = self.start(control=True)
        ctl = self.control(sim)
        ctl('NET("rough")')
        self.assertEqual(ctl.json("NET?")["all"], "split=4,gap=0.5-3,coalesce=2,latency=1,"
                         "jitter=2,loss=0.02,dup=0.01,reorder=0.02")
        ctl('NET("reset=5000")')
        self.assertIn("reset=5000", ctl.json("NET?")["all"])
        ctl('NET("off")')
        self.assertEqual(ctl.json("NET?")["all"], "off")

    def test_bad_net_option_is_a_usage_error(self):
        proc = subprocess.run([os.environ.get("WSGSIM", os.path.join(ROOT, "build", "wsgsim")),
                               "--net", "loss=1.5"], capture_output=True, text=True,
                              timeout=HANG_LIMIT_S)
        self.assertEqual(proc.returncode, 2)
        self.assertIn("invalid --net 'loss=1.5': bad item loss=1.5", proc.stderr)

    def test_net_section_of_the_configuration(self):
        sim_dir = self.enterContext_tmp()
        path = os.path.join(sim_dir, "net.ini")
        with open(path, "w") as f:
            f.write("[net]\nconditions = lossy\n")
        sim = self.start("--config", path, "--net", "loss=0.5", control=True)
        self.assertEqual(self.control(sim).json("NET?")["all"],
                         "latency=2,jitter=4,loss=0.5,dup=0.05,reorder=0.1")
        with open(path, "w") as f:
            f.write("[net]\nconditions = split=99\n")
        proc = subprocess.run([os.environ.get("WSGSIM", os.path.join(ROOT, "build", "wsgsim")),
                               "--config", path], capture_output=True, text=True,
                              timeout=HANG_LIMIT_S)
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("[net] conditions: bad item split=99", proc.stderr)

    def enterContext_tmp(self):
        import tempfile
        d = tempfile.TemporaryDirectory()
        self.addCleanup(d.cleanup)
        return d.name


if __name__ == "__main__":
    unittest.main()
