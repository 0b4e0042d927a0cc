# SPDX-License-Identifier: BSD-3-Clause
"""The event stream (GET /api/devices/{id}/events): events arrive and carry
the changing state; a client that stops reading loses events and holds up
nobody. Its rate is wall-clock and never asserted here (make bench)."""
import unittest

from test_api import WebCase
from webclient import EventStream

# Events a stalled reader's socket buffers cannot all hold: the server's
# send buffer is 32 KiB (64 KiB as the kernel counts it), the reader's is
# made small, and an event with the tactile map is about 2 KiB.
STALL_EVENTS = 120
# Streams on one device: two or three in each of the period's 40 slots.
MANY_STREAMS = 90


class Events(WebCase):
    ARGS = ("--no-disconnect-faststop",)

    def stream(self, device=0, rcvbuf=None):
        s = EventStream("127.0.0.1", self.sim.http_port, "/api/devices/%d/events" % device,
                        rcvbuf)
        self.addCleanup(s.close)
        return s

    def test_events_carry_the_changing_state(self):
        s = self.stream()
        self.assertTrue(s.status_line.startswith("HTTP/1.1 200"), s.status_line)
        self.assertIn("content-type: text/event-stream", s.headers)
        first = s.next_event()
        self.assertEqual(first[1], "state")
        self.assertEqual(first[2]["id"], 0)
        self.assertIn("position_mm", first[2])
        ids, times = [first[0]], [first[2]["time_ms"]]
        # the device time may lag the clock for a while (a busy or slow
        # host): it never goes back, and it moves on
        while len(ids) < 5 or times[-1] == times[0]:
            event_id, _, state = s.next_event()
            ids.append(event_id)
            times.append(state["time_ms"])
        self.assertEqual(ids, sorted(set(ids)), "ids increase")
        self.assertEqual(times, sorted(times), "the simulated time never goes back")

    def test_a_move_shows_in_the_stream(self):
        with self.sim.tcp() as gcl:
            s = self.stream()
            self.assertEqual(gcl.command("HOME()"), "ACK HOME")
            seen = set()
            while "home" not in seen:
                seen.add(s.next_event()[2]["motion"])
            while s.next_event()[2]["motion"] != "none":
                pass
            self.assertEqual(gcl.read_line(), "FIN HOME")
            self.assertTrue(s.next_event()[2]["referenced"])

    def test_a_stalled_reader_loses_events_and_holds_up_nobody(self):
        stalled = self.stream(rcvbuf=4096)
        last_id = stalled.next_event()[0]
        reader = self.stream()
        with self.sim.tcp() as gcl:
            # while it does not read: GCL answers, another stream flows
            while True:
                event_id = reader.next_event()[0]
                gcl.expect("GRIPSTATE?", "GRIPSTATE=0")
                if event_id > last_id + STALL_EVENTS:
                    break
        ids = []
        while not ids or ids[-1] <= event_id:
            ids.append(stalled.next_event()[0])
        gaps = [b - a for a, b in zip([last_id] + ids, ids)]
        self.assertGreater(max(gaps), 1, "the stalled reader lost the events it could not take")

    def test_many_streams_all_flow_and_closing_some_stops_none(self):
        # more streams than the period's slots: every tick queues several
        # to be resumed one by one, and streams that close may be queued
        streams = [self.stream() for _ in range(MANY_STREAMS)]
        for s in streams:
            s.next_event()
        for s in streams[::3]:
            s.close()
        survivors = [s for i, s in enumerate(streams) if i % 3 != 0]
        newest = self.stream().next_event()[0]  # the tick of a fresh stream
        for s in survivors:
            ids = [s.next_event()[0]]
            while ids[-1] < newest + 2:
                ids.append(s.next_event()[0])
            self.assertEqual(ids, sorted(set(ids)), "ids increase")


class FleetEvents(WebCase):
    ARGS = ("--devices", "2")
    stream = Events.stream

    def test_devices_have_their_own_streams(self):
        self.assertEqual(self.stream(device=1).next_event()[2]["id"], 1)
        self.assertEqual(self.stream(device=0).next_event()[2]["id"], 0)


if __name__ == "__main__":
    unittest.main()
