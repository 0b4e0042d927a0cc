#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The lwIP image's status page (hal/boards/mps2-an385/web_status.c): the
page at /, the state at /api/devices/0/state with the host API's field
names, the error pages, and the state following a MOVE sent over GCL.

usage: web_status.py HOST GCL_PORT HTTP_PORT

GCL_PORT is the board's TCP 1000 and HTTP_PORT its port 80 (both forwarded
by QEMU in tests/qemu/boot.sh). Prints PASS/FAIL lines like conversation.py;
exit status 1 on any failure. Python 3 standard library only.
"""

import http.client
import json
import os
import socket
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import conversation as gcl  # noqa: E402

HTTP_TIMEOUT_S = 30.0  # an upper bound against a hang, never a speed check
STATE_PATH = "/api/devices/0/state"
STATE_FIELDS = {"position_mm", "speed_mm_s", "force_n", "temperature_c", "grip_state",
                "sysflags"}
# Appendix D and B, as the host's state dump names them (firmware/core/names.c)
GRIP_STATES = ["IDLE", "GRASPING", "NO PART", "PART LOST", "HOLDING", "RELEASING",
               "POSITIONING", "ERROR"]
SYSFLAGS = {0: "SF_REFERENCED", 1: "SF_MOVING", 2: "SF_BLOCKED_MINUS", 3: "SF_BLOCKED_PLUS",
            4: "SF_SOFT_LIMIT_MINUS", 5: "SF_SOFT_LIMIT_PLUS", 6: "SF_AXIS_STOPPED",
            7: "SF_TARGET_POS_REACHED", 8: "SF_OVERDRIVE_MODE", 9: "SF_FORCECNTL_MODE",
            12: "SF_FAST_STOP", 13: "SF_TEMP_WARNING", 14: "SF_TEMP_FAULT",
            15: "SF_POWER_FAULT", 16: "SF_CURR_FAULT", 17: "SF_FINGER_FAULT",
            18: "SF_CMD_FAILURE", 19: "SF_SCRIPT_RUNNING", 20: "SF_SCRIPT_FAILURE"}
IDLE_CLIENTS = 3  # more than MEMP_NUM_PARALLEL_HTTPD_CONNS
WIDTHS_MM = (30.0, 42.5)  # two targets: the second proves the state is live


class WebError(Exception):
    pass


def fetch(host, port, path, method="GET"):
    """One request on its own connection -> (status, headers, body text)."""
    conn = http.client.HTTPConnection(host, port, timeout=HTTP_TIMEOUT_S)
    try:
        conn.request(method, path, body=b"x" if method == "POST" else None)
        reply = conn.getresponse()
        body = reply.read().decode("utf-8")
        return reply.status, reply.headers, body
    finally:
        conn.close()


def expect_status(status, headers, wanted_status, wanted_type):
    if status != wanted_status:
        raise WebError(f"HTTP {status}, expected {wanted_status}")
    content_type = headers.get("Content-Type", "")
    if not content_type.startswith(wanted_type):
        raise WebError(f"Content-Type '{content_type}', expected {wanted_type}")


def get_state(host, port):
    status, headers, body = fetch(host, port, STATE_PATH)
    expect_status(status, headers, 200, "application/json")
    length = headers.get("Content-Length")
    if length is None or int(length) != len(body.encode("utf-8")):
        raise WebError(f"Content-Length {length} for a body of {len(body)} bytes")
    try:
        state = json.loads(body)
    except ValueError as exc:
        raise WebError(f"not JSON ({exc}): {body!r}") from exc
    check_state_shape(state)
    return state


def check_state_shape(state):
    if set(state) != STATE_FIELDS:
        raise WebError(f"fields {sorted(state)}, expected {sorted(STATE_FIELDS)}")
    for field in ("position_mm", "speed_mm_s", "force_n", "temperature_c"):
        if not isinstance(state[field], (int, float)) or isinstance(state[field], bool):
            raise WebError(f"{field} is {state[field]!r}, not a number")
    grip = state["grip_state"]
    code = grip.get("code")
    if not isinstance(code, int) or not 0 <= code < len(GRIP_STATES) \
            or grip.get("name") != GRIP_STATES[code]:
        raise WebError(f"grip_state {grip}")
    flags = state["sysflags"]
    value = flags.get("value")
    if not isinstance(value, int):
        raise WebError(f"sysflags.value is {value!r}")
    named = [SYSFLAGS[bit] for bit in sorted(SYSFLAGS) if value & (1 << bit)]
    if flags.get("set") != named:
        raise WebError(f"sysflags.set {flags.get('set')} for value {value}, expected {named}")


def step_page(host, port):
    status, headers, body = fetch(host, port, "/")
    expect_status(status, headers, 200, "text/html")
    if f'href="{STATE_PATH}"' not in body or "fetch(" not in body:
        raise WebError("the page neither links nor polls the state")
    return f"{len(body)} bytes of HTML"


def step_state(host, port):
    state = get_state(host, port)
    return f"{len(state)} fields, grip state {state['grip_state']['name']}"


def step_errors(host, port):
    cases = (("GET", "/no/such/page", 404), ("GET", "/api/devices/1/state", 404),
             ("POST", STATE_PATH, 501))
    for method, path, wanted in cases:
        status, headers, _ = fetch(host, port, path, method)
        expect_status(status, headers, wanted, "text/plain")
    return "404 unknown path and device, 501 POST"


def step_idle_clients(link, host, port):
    """Browsers leave idle sockets open: more of them than the board has
    connection slots neither lock out the next request nor the GCL client."""
    idle = []
    try:
        for _ in range(IDLE_CLIENTS):
            idle.append(socket.create_connection((host, port), timeout=HTTP_TIMEOUT_S))
        state = get_state(host, port)
        pos = gcl.query(link, "POS", r"(-?[0-9.]+)").group(1)
    finally:
        for sock in idle:
            sock.close()
    return f"{IDLE_CLIENTS} idle sockets; state served, POS={pos} ({state['position_mm']})"


def step_moves(link, host, port):
    """After each MOVE's FIN the state shows the new width, as GCL does."""
    gcl.call(link, "HOME()", motion=True)
    seen = []
    for width in WIDTHS_MM:
        gcl.call(link, f"MOVE({width})", motion=True)
        state = get_state(host, port)
        position = state["position_mm"]
        if abs(position - width) > gcl.POS_TOLERANCE_MM:
            raise WebError(f"position_mm {position} after MOVE({width})")
        gcl_pos = float(gcl.query(link, "POS", r"(-?[0-9.]+)").group(1))
        if abs(position - gcl_pos) > gcl.POS_TOLERANCE_MM:
            raise WebError(f"position_mm {position}, but POS={gcl_pos}")
        gcl_grip = int(gcl.query(link, "GRIPSTATE", r"([0-9]+)").group(1))
        if state["grip_state"]["code"] != gcl_grip:
            raise WebError(f"grip_state {state['grip_state']}, but GRIPSTATE={gcl_grip}")
        if "SF_REFERENCED" not in state["sysflags"]["set"]:
            raise WebError(f"SF_REFERENCED not set after HOME: {state['sysflags']}")
        seen.append(position)
    return "position_mm " + ", ".join(f"{p}" for p in seen)


def main(argv):
    if len(argv) != 4:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    host, gcl_port, http_port = argv[1], int(argv[2]), int(argv[3])
    results = []

    def report(ok, step, detail):
        gcl.print_report(ok, step, detail)
        results.append(ok)

    def run(step, action):
        try:
            report(True, step, action())
        except (OSError, http.client.HTTPException, WebError, gcl.ConversationError) as exc:
            report(False, step, str(exc) or type(exc).__name__)

    try:
        link, first = gcl.open_link(gcl.StreamLink, host, gcl_port, 120.0)
    except gcl.ConversationError as exc:
        report(False, "web GCL link", str(exc))
        return 1
    try:
        report(True, "web GCL link", first)
        run("web GET /", lambda: step_page(host, http_port))
        run("web GET state", lambda: step_state(host, http_port))
        run("web errors", lambda: step_errors(host, http_port))
        run("web idle clients", lambda: step_idle_clients(link, host, http_port))
        run("web after MOVE", lambda: step_moves(link, host, http_port))
        run("web GCL still on", lambda: gcl.call(link, "BYE()"))
    finally:
        link.close()
    print(f"{results.count(True)} passed, {results.count(False)} failed")
    return 0 if all(results) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
