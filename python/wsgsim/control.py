# SPDX-License-Identifier: BSD-3-Clause
"""The simulation control channel of wsgsim (--sim-port; docs/simctl.md)."""
import json

from .gcl import GclError, GclTcp


class Control(GclTcp):
    """One reply line per command: control("PART(40,100)") -> "OK"."""

    def __call__(self, line, timeout=None):
        self.send(line)
        return self.read_line(timeout)

    def json(self, query):
        """The JSON value of a query such as STATE? or COVERAGE?."""
        reply = self(query)
        name, _, value = reply.partition("=")
        if name + "?" != query:
            raise GclError("%s: unexpected %r" % (query, reply))
        return json.loads(value)

    def step(self, ms):
        """Advances the paused simulated clock by ms milliseconds."""
        reply = self("STEP(%d)" % ms)
        if not reply.startswith("STEP="):
            raise GclError("STEP(%d): unexpected %r" % (ms, reply))
        return reply

    def run_until_done(self, max_ms=60000):
        """Runs the paused clock until the long command the device runs ends
        (its FIN or ERR has then been sent), at most max_ms of simulated time.
        Returns (simulated ms reached, why): why is "done", "idle" (nothing
        was running: time stands still) or "limit" (max_ms ran out first)."""
        reply = self("RUN_UNTIL_DONE(%s)" % max_ms)
        name, _, value = reply.partition("=")
        if name != "RUN_UNTIL_DONE":
            raise GclError("RUN_UNTIL_DONE(%s): unexpected %r" % (max_ms, reply))
        sim_ms, why = json.loads(value)
        return sim_ms, why

    def step_until(self, client, final, step_ms=100, limit_ms=60000):
        """STEPs the paused clock until client receives the line final
        (AUTOSEND values are skipped); returns the simulated ms stepped."""
        stepped = 0
        while stepped < limit_ms:
            self.step(step_ms)
            stepped += step_ms
            for line in client.lines_before_reply():
                if line == final:
                    return stepped
                if not line.startswith("@"):
                    raise GclError("waiting for %r: got %r" % (final, line))
        raise GclError("no %r within %d ms of simulated time" % (final, limit_ms))
