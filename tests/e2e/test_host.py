# SPDX-License-Identifier: BSD-3-Clause
"""End-to-end: build/wsgsim over real TCP and UDP sockets, driven the way
real drivers drive the gripper."""
import os
import socket
import tempfile
import time
import unittest

from gclclient import GclError, Wsgsim, read_record, wait_for_reply


class HostCase(unittest.TestCase):
    server_args = ()
    paused = False  # True: the clock starts paused, self.ctl steps it

    def setUp(self):
        args = self.server_args + (("--sim-port", "0", "--start-paused") if self.paused else ())
        self.sim = Wsgsim(*args)
        self.sim.start()
        self.clients = []
        if self.paused:
            self.ctl = self.sim.control()
            self.clients.append(self.ctl)

    def tearDown(self):
        for client in self.clients:
            client.close()
        code = self.sim.stop()
        self.assertEqual(code, 0, "wsgsim did not shut down cleanly:\n" + "".join(self.sim.log))

    def tcp(self):
        client = self.sim.tcp()
        self.clients.append(client)
        return client

    def udp(self):
        client = self.sim.udp()
        self.clients.append(client)
        return client

    def home(self, client):
        client.expect("FSACK()", "ACK FSACK")
        if self.paused:
            client.expect("HOME()", "ACK HOME")
            self.ctl.step_until(client, "FIN HOME")
        else:
            self.assertEqual(client.long_command("HOME()", "HOME"), "FIN HOME")


class DriverSequences(HostCase):
    def setUp(self):
        fd, self.record = tempfile.mkstemp(prefix="wsgsim_record_")
        os.close(fd)
        self.addCleanup(os.remove, self.record)
        self.server_args = ("--record", self.record)
        super().setUp()

    def sim_times(self, text):
        """Simulated seconds of each line text wsgsim sent (its --record)."""
        return [row[0] for row in read_record(self.record) if row[3:] == ("<", text)]

    def test_connect_sequence_of_common_drivers(self):
        c = self.tcp()
        c.expect("FSACK()", "ACK FSACK")
        c.expect("VERBOSE=1", "VERBOSE=1")
        c.expect("MOVE(10)", "ERR MOVE 3 Device was not initialized")
        self.assertEqual(c.long_command("HOME()", "HOME"), "FIN HOME")
        self.assertEqual(c.command("POS?"), "POS=110.0")
        self.assertEqual(c.command("SYSFLAGS[0]?"), "SYSFLAGS[0]=1")
        (ack,), (fin,) = self.sim_times("ACK HOME"), self.sim_times("FIN HOME")
        self.assertGreater(fin - ack, 0.3, "homing should take (simulated) time")

    def test_move_grip_release_cycle(self):
        c = self.tcp()
        self.home(c)
        self.assertEqual(c.long_command("MOVE(50)", "MOVE"), "FIN MOVE")
        self.assertAlmostEqual(c.query_float("POS"), 50.0, places=2)
        self.assertEqual(c.long_command("GRIP(20)", "GRIP"), "FIN GRIP")
        self.assertEqual(c.command("GRIPSTATE?"), "GRIPSTATE=4")
        self.assertEqual(c.command("GRIP()"), "ERR GRIP 16")
        self.assertEqual(c.long_command("RELEASE(20,100)", "RELEASE"), "FIN RELEASE")
        self.assertEqual(c.command("GRIPSTATE?"), "GRIPSTATE=0")
        self.assertAlmostEqual(c.query_float("POS"), 20.0, places=2)
        self.assertEqual(c.command("GRIPSTATS?"), "GRIPSTATS=[1,0,0]")

    def test_lenient_input_forms(self):
        c = self.tcp()
        self.home(c)
        c.send_raw(b"  mOvE ( 50.00 ,\t100 )\r\n")
        self.assertEqual(c.read_line(), "ACK MOVE")
        self.assertEqual(c.read_line(), "FIN MOVE")
        for chunk in (b"MO", b"VE(2", b"0.0000", b"00)", b"\n"):
            c.send_raw(chunk)
            time.sleep(0.01)
        self.assertEqual(c.read_line(), "ACK MOVE")
        self.assertEqual(c.read_line(), "FIN MOVE")
        c.send_raw(b"POS?\nGRIPSTATE?\nTEMP?\n")
        self.assertEqual(c.read_line(), "POS=20.0")
        self.assertEqual(c.read_line(), "GRIPSTATE=0")
        self.assertTrue(c.read_line().startswith("TEMP="))

    def test_manual_examples_verbatim(self):
        c = self.tcp()
        c.expect("VERBOSE=0", "VERBOSE=0")
        self.assertEqual(c.command("DEVTYPE?"), 'DEVTYPE="WSG 50-110"')
        self.assertEqual(c.command("VERSION?"), 'VERSION="4.0.0"')
        self.assertRegex(c.command("SN?"), r"^SN=\d+$")
        self.assertRegex(c.command("TAG?"), r'^TAG=".*"$')
        self.assertRegex(c.command("TEMP?"), r"^TEMP=\d+\.\d{1,3}$")
        self.home(c)
        c.expect('AUTOSEND("POS",10)', "ACK AUTOSEND")
        self.assertRegex(c.read_line(), r"^@POS=\d+\.\d{1,3}$")
        c.expect('AUTOSEND("POS",0)', "ACK AUTOSEND")
        c.expect('AUTOSEND("FORCE",50,0.1)', "ACK AUTOSEND")
        self.assertRegex(c.read_line(), r"^@FORCE=")
        c.expect('AUTOSEND("FORCE",0)', "ACK AUTOSEND")

    def test_errors_and_verbose_descriptions(self):
        c = self.tcp()
        self.assertEqual(c.command("NOSUCH()"), "ERR NOSUCH 14")
        self.assertEqual(c.command("MOVE()"), "ERR MOVE 13")
        self.assertEqual(c.command("HOME(1,2)"), "ERR HOME 12")
        self.assertEqual(c.command("MOVE(abc"), "ERR MOVE 15")
        self.assertEqual(c.command('MOVE("x")'), "ERR MOVE 24")
        c.expect("VERBOSE=1", "VERBOSE=1")
        self.assertEqual(c.command("MOVE(500)"), "ERR MOVE 28 Range error")
        self.assertEqual(c.command("SYSFLAGS[40]?"), "ERR SYSFLAGS 25 Index out of bounds")


class PausedDriverSequences(HostCase):
    paused = True

    def test_every_reply_line_arrives_in_its_own_segment(self):
        c = self.tcp()
        self.home(c)
        c.send("MOVE(60)")
        first = c.sock.recv(4096)
        # the paused clock keeps FIN MOVE back until the client has read
        # the ACK, however slowly the client runs
        self.assertRegex(self.ctl("STEP(2000)"), r"^STEP=")
        second = c.sock.recv(4096)
        self.assertEqual(first, b"ACK MOVE\n")
        self.assertEqual(second, b"FIN MOVE\n")

    def test_final_reply_goes_to_the_issuing_session(self):
        mover = self.tcp()
        watcher = self.tcp()
        self.home(mover)
        mover.expect("MOVE(40)", "ACK MOVE")
        # the paused clock holds the motion: STOP always comes while it runs
        watcher.expect("STOP()", "ACK STOP")
        self.ctl.step_until(mover, "ERR MOVE 19")
        self.assertEqual(watcher.command("GRIPSTATE?"), "GRIPSTATE=0")
        self.assertEqual(watcher.command("SYSFLAGS[6]?"), "SYSFLAGS[6]=1")

    def test_streams_at_10_and_50_ms(self):
        fast = self.tcp()
        slow = self.tcp()
        fast.expect('AUTOSEND("POS",10)', "ACK AUTOSEND")
        slow.expect('AUTOSEND("SYSFLAGS",50)', "ACK AUTOSEND")
        self.assertEqual(self.ctl("STEP(1000)"), "STEP=1000.000")
        counts = []
        for client in (fast, slow):
            lines = client.lines_before_reply()
            self.assertTrue(all(line.startswith("@") for line in lines), lines)
            counts.append(len(lines))
        # the first value goes out when the stream starts, then one per
        # period: one second of simulated time is 100 and 20 periods
        self.assertEqual(counts, [101, 21])

    def test_udp_bye_then_at_once_a_command_starts_a_fresh_session(self):
        self.home(self.tcp())
        u = self.udp()
        u.expect("VERBOSE=1", "VERBOSE=1")
        u.expect('AUTOSEND("GRIPSTATE",20)', "ACK AUTOSEND")
        u.expect("MOVE(40)", "ACK MOVE")  # the paused clock holds its FIN back
        # a test rig starting over from the same port: goodbye, then at once
        # its next command, both datagrams sent before any reply is read
        u.sock.send(b"BYE()\n")
        u.sock.send(b"POS?\n")
        self.assertEqual(u.read_line_skipping_autosend(), "ACK BYE")
        self.assertRegex(u.read_line_skipping_autosend(), r"^POS=\d+\.\d+$")
        self.assertEqual(u.command("FOO()"), "ERR FOO 14")  # VERBOSE stayed behind
        self.ctl.step(5000)
        # the replies come in the order sent: what precedes POS= went out
        # during the step, where the old session's FIN and stream would be
        u.send("POS?")
        lines = []
        while not lines or not lines[-1].startswith("POS="):
            lines.append(u.read_line())
        self.assertEqual(lines, ["POS=40.0"])


class AutosendStreams(HostCase):
    # the UDP subscriber only listens: on loopback, its stream needs no budget
    def test_autosend_lines_never_break_replies(self):
        c = self.tcp()
        self.home(c)
        c.expect('AUTOSEND("POS",10)', "ACK AUTOSEND")
        self.assertEqual(c.long_command("MOVE(30)", "MOVE"), "FIN MOVE")
        for _ in range(50):
            line = c.read_line()
            self.assertRegex(line, r"^@POS=\d+\.\d{1,3}$")

    def test_udp_stream_goes_to_the_subscriber(self):
        u = self.udp()
        u.expect('AUTOSEND("GRIPSTATE",20)', "ACK AUTOSEND")
        lines = [u.read_line() for _ in range(10)]
        self.assertTrue(all(line == "@GRIPSTATE=0" for line in lines), lines)


class SessionsAndTransports(HostCase):
    def test_disconnect_without_bye_raises_fast_stop(self):
        first = self.tcp()
        self.home(first)
        first.close()
        self.clients.remove(first)
        second = self.tcp()
        # the server notices the lost connection on its own time
        wait_for_reply(second, "SYSFLAGS[12]?", "SYSFLAGS[12]=1")
        self.assertEqual(second.command("MOVE(10)"), "ERR MOVE 16")
        self.assertEqual(second.command("GRIPSTATE?"), "GRIPSTATE=7")
        second.expect("FSACK()", "ACK FSACK")
        self.assertEqual(second.command("SYSFLAGS[12]?"), "SYSFLAGS[12]=0")
        self.assertEqual(second.long_command("MOVE(10)", "MOVE"), "FIN MOVE")

    def test_bye_closes_without_fast_stop(self):
        first = self.tcp()
        first.expect("BYE()", "ACK BYE")
        self.assertTrue(first.closed_by_peer())
        second = self.tcp()
        self.assertEqual(second.command("SYSFLAGS[12]?"), "SYSFLAGS[12]=0")

    def test_session_settings_reset_on_reconnect(self):
        first = self.tcp()
        first.expect("PWT=3.5", "PWT=3.5")
        first.expect("VERBOSE=1", "VERBOSE=1")
        first.expect("BYE()", "ACK BYE")
        second = self.tcp()
        self.assertEqual(second.command("PWT?"), "PWT=10.0")
        self.assertEqual(second.command("NOSUCH()"), "ERR NOSUCH 14")

    def test_udp_commands_and_peers(self):
        u = self.udp()
        u.expect("FSACK()", "ACK FSACK")
        self.assertEqual(u.long_command("HOME()", "HOME"), "FIN HOME")
        self.assertEqual(u.command("POS?"), "POS=110.0")
        other = self.udp()
        self.assertEqual(other.command("PWT=2"), "PWT=2.0")
        self.assertEqual(u.command("PWT?"), "PWT=10.0")
        u.sock.send(b"GRIPSTATE?")  # a datagram without its newline still counts
        self.assertEqual(u.read_line(), "GRIPSTATE=0")

    def test_max_clients_refuses_extra_connections(self):
        self.sim.stop()
        self.sim = Wsgsim("--max-clients", "2")
        self.sim.start()
        a, b = self.tcp(), self.tcp()
        a.expect("FSACK()", "ACK FSACK")
        b.expect("FSACK()", "ACK FSACK")
        extra = self.tcp()
        self.assertTrue(extra.closed_by_peer())
        self.clients.remove(extra)
        extra.close()
        self.assertEqual(a.command("GRIPSTATE?"), "GRIPSTATE=0")


class CommandLine(unittest.TestCase):
    def test_port_in_use_is_one_clear_line_and_status_2(self):
        blocker = socket.socket()
        blocker.bind(("127.0.0.1", 0))
        blocker.listen(1)
        port = blocker.getsockname()[1]
        try:
            sim = Wsgsim("--tcp-port", str(port), "--no-udp")
            sim.args = ["--bind", "127.0.0.1", "--tcp-port", str(port), "--no-udp"]
            with self.assertRaises(GclError):
                sim.start()
            self.assertIn("Address already in use", "".join(sim.log))
        finally:
            blocker.close()

    def test_privileged_port_without_permission(self):
        if os.geteuid() == 0:
            # root may bind port 1000; prove the error path with an address we do not own
            sim = Wsgsim()
            sim.args = ["--bind", "192.0.2.1", "--tcp-port", "1000", "--no-udp"]
            with self.assertRaises(GclError):
                sim.start()
            self.assertIn("cannot listen on TCP 192.0.2.1:1000", "".join(sim.log))
        else:
            sim = Wsgsim()
            sim.args = ["--bind", "127.0.0.1", "--tcp-port", "1000", "--no-udp"]
            with self.assertRaises(GclError):
                sim.start()
            self.assertIn("below 1024", "".join(sim.log))


if __name__ == "__main__":
    unittest.main()
