#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs a public WSG driver, unchanged, against wsgsim and prints what it
achieved as JSON: rates, round trips, outcomes. wsgsim and the driver run in
a private network namespace (`unshare -rn`, loopback only), on the device's
own ports and addresses, so nothing else on the machine is touched.

    tools/drivers/run_driver.py MODE [--seconds N] [--drivers DIR]
                                [--wsgsim PATH] [--with COMMAND]
                                [-- WSGSIM_OPTION...]

MODE (`--list` prints them) is one driver in one of its modes; `all` runs
each in turn. The options after `--` go to wsgsim (`--timing wsg50`, a
`--config` file, `--record FILE`, ...); a mode adds what it needs itself
(a Lua script, a part). The drivers are built by tools/drivers/build.sh
(`make drivers`) into DIR. `--with COMMAND` starts a shell command in the
namespace once wsgsim is ready (a recording proxy on the device's ports in
front of a wsgsim moved to others, say); the driver starts once TCP port
1000 accepts again, and COMMAND gets SIGTERM at the end.
docs/testing-your-driver.md, "Real drivers
against wsgsim", says what each mode does and what the real gripper gives.
"""
import argparse
import contextlib
import fcntl
import importlib.util
import json
import os
import re
import shutil
import signal
import socket
import statistics
import struct
import subprocess
import sys
import tempfile
import time
import traceback
import xmlrpc.client

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
import wsgbinproto as proto  # noqa: E402

INSIDE = "WSGSIM_DRIVERS_IN_NETNS"
DEBIAN_PYTHON = "/usr/bin/python3"  # rospy is Debian's
ROS_NODE = "ros/devel/lib/wsg_50_driver/wsg_50_ip"
DRAKE_GRIPPER_ADDRESS = "192.168.1.20"  # drake-schunk-driver's defaults.h
STARTUP_TIMEOUT = 30  # against hangs only
# ros-grip: the node's grasp of the default scene's 40 mm box, and where
# wsgsim's control channel answers in the namespace
GRIP_FORCE_N, GRIP_WIDTH_MM, GRIP_SPEED_MM_S, GRIP_CONTROL_PORT = 40.0, 40.0, 50.0, 1100
SIOCGIFFLAGS, SIOCSIFFLAGS, SIOCSIFADDR, IFF_UP = 0x8913, 0x8914, 0x8916, 0x1


# ---------------------------------------------------------------- namespace

def loopback_up(addresses=()):
    """The namespace's loopback interface up, with extra IPv4 addresses."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        request = struct.pack("16sH14x", b"lo", 0)
        flags = struct.unpack("16sH14x", fcntl.ioctl(s, SIOCGIFFLAGS, request))[1]
        fcntl.ioctl(s, SIOCSIFFLAGS, struct.pack("16sH14x", b"lo", flags | IFF_UP))
        for i, address in enumerate(addresses, 1):
            request = struct.pack("16sHH4s8x", b"lo:%d" % i, socket.AF_INET, 0,
                                  socket.inet_aton(address))
            fcntl.ioctl(s, SIOCSIFADDR, request)


def wait_port(port, timeout=STARTUP_TIMEOUT):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with contextlib.suppress(OSError), socket.create_connection(("127.0.0.1", port), 1):
            return
        time.sleep(0.05)
    raise RuntimeError("nothing listens on port %d" % port)


def stop(proc, sig=signal.SIGTERM, timeout=5):
    if proc.poll() is None:
        proc.send_signal(sig)
        try:
            proc.wait(timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    return proc.returncode


@contextlib.contextmanager
def wsgsim(binary, args, work):
    """wsgsim started with args, ready; yields its log's path."""
    ready, log = os.path.join(work, "ready"), os.path.join(work, "wsgsim.log")
    with open(log, "w") as out:
        proc = subprocess.Popen([binary] + args + ["--ready-file", ready, "--http-port", "0"],
                                stdin=subprocess.DEVNULL, stdout=out, stderr=out)
    deadline = time.monotonic() + STARTUP_TIMEOUT
    while not os.path.exists(ready):
        if proc.poll() is not None or time.monotonic() > deadline:
            stop(proc)
            raise RuntimeError("wsgsim did not start: " + open(log).read()[-2000:])
        time.sleep(0.02)
    try:
        yield log
    finally:
        rc = stop(proc)
        if rc != 0:
            print("run_driver: wsgsim exited with %s" % rc, file=sys.stderr)


def percentiles(values_ms):
    if not values_ms:
        return None
    ordered = sorted(values_ms)
    pick = lambda f: round(ordered[min(len(ordered) - 1, int(f * len(ordered)))], 3)  # noqa: E731
    return {"p50": pick(0.5), "p95": pick(0.95), "max": round(ordered[-1], 3),
            "mean": round(statistics.fmean(ordered), 3), "n": len(ordered)}


# ---------------------------------------------------------------- ROS 1

def ros_env(work):
    config = os.path.join(work, "rosconsole.config")
    with open(config, "w") as f:
        # the node's per-stream rates are DEBUG messages of its auto_update thread
        f.write("log4j.logger.ros=DEBUG\nlog4j.logger.ros.roscpp=INFO\n"
                "log4j.logger.ros.roscpp_internal=INFO\n")
    return dict(os.environ, ROS_MASTER_URI="http://127.0.0.1:11311", ROS_IP="127.0.0.1",
                ROS_HOME=work, ROS_LOG_DIR=work, ROSCONSOLE_CONFIG_FILE=config,
                PATH="/usr/bin:/bin", PYTHONPATH="")


def ros_node(params, seconds, drivers, work):
    """wsg50-ros-pkg's node with these parameters; its status topic's rate
    from its first message on (after the node's own homing and tare)."""
    env = ros_env(work)
    log = open(os.path.join(work, "ros.log"), "w")
    master = subprocess.Popen([DEBIAN_PYTHON, "/usr/bin/rosmaster", "--core", "-p", "11311"],
                              env=env, stdout=log, stderr=log)
    node = None
    try:
        wait_port(11311)
        node_log = os.path.join(work, "node.log")
        with open(node_log, "w") as out:
            # line-buffered: its log is read after it is killed
            node = subprocess.Popen(["stdbuf", "-oL", os.path.join(drivers, ROS_NODE),
                                     "__name:=wsg_50_driver"]
                                    + ["_%s:=%s" % kv for kv in params.items()],
                                    env=env, stdout=out, stderr=out)
        counter = subprocess.run([DEBIAN_PYTHON, os.path.join(HERE, "ros_rate.py"),
                                  "/wsg_50_driver/status", str(seconds), str(STARTUP_TIMEOUT)],
                                 env=env, capture_output=True, text=True,
                                 timeout=seconds + STARTUP_TIMEOUT + 30)
        result = {"status_topic": json.loads(counter.stdout or "{}")}
        if counter.returncode:
            result["counter_error"] = counter.stderr[-1000:]
    finally:
        if node:
            # its read thread may block in a receive: SIGINT, then SIGKILL
            stop(node, signal.SIGINT, 3)
        stop(master)
        log.close()
    result.update(node_log_summary(node_log))
    return result


def ros_service_call(service, request, timeout=STARTUP_TIMEOUT):
    """Calls a ROS 1 service of the node over TCPROS, without generated
    message classes: request is the serialized request; the response's
    serialized body, or an error. md5sum "*" is what roscpp accepts from a
    client that does not know the type's (rosservice's own way)."""
    master = xmlrpc.client.ServerProxy("http://127.0.0.1:11311")
    deadline = time.monotonic() + timeout
    while True:  # the node advertises its services after its homing
        code, _, uri = master.lookupService("/run_driver", service)
        if code == 1:
            break
        if time.monotonic() > deadline:
            raise RuntimeError("no service %s within %g s" % (service, timeout))
        time.sleep(0.1)
    host, port = uri[len("rosrpc://"):].rstrip("/").split(":")
    fields = [b"callerid=/run_driver", b"service=" + service.encode(), b"md5sum=*",
              b"persistent=0"]
    header = b"".join(struct.pack("<I", len(f)) + f for f in fields)
    with socket.create_connection((host, int(port)), timeout) as sock:
        sock.sendall(struct.pack("<I", len(header)) + header)
        reply_header = read_exactly(sock, struct.unpack("<I", read_exactly(sock, 4))[0])
        if b"error=" in reply_header:
            raise RuntimeError("%s refused the call: %r" % (service, reply_header))
        sock.sendall(struct.pack("<I", len(request)) + request)
        ok = read_exactly(sock, 1)[0]
        body = read_exactly(sock, struct.unpack("<I", read_exactly(sock, 4))[0])
    if not ok:
        raise RuntimeError("%s failed: %r" % (service, body))
    return body


def read_exactly(sock, count):
    data = b""
    while len(data) < count:
        more = sock.recv(count - len(data))
        if not more:
            raise RuntimeError("the node closed the service connection")
        data += more
    return data


def control(port, line):
    """One request on wsgsim's control channel; its reply line."""
    with socket.create_connection(("127.0.0.1", port), STARTUP_TIMEOUT) as sock:
        sock.sendall(line.encode() + b"\n")
        reply = b""
        while not reply.endswith(b"\n"):
            more = sock.recv(65536)
            if not more:
                break
            reply += more
    return reply.decode().strip()


def mode_ros_grip(ctx):
    """wsg50-ros-pkg's grasp service on the box between the jaws (--physics mujoco)."""
    env = ros_env(ctx.work)
    os.environ.update({k: env[k] for k in ("ROS_MASTER_URI", "ROS_IP")})
    log = open(os.path.join(ctx.work, "ros.log"), "w")
    master = subprocess.Popen([DEBIAN_PYTHON, "/usr/bin/rosmaster", "--core", "-p", "11311"],
                              env=env, stdout=log, stderr=log)
    node = None
    try:
        wait_port(11311)
        with open(os.path.join(ctx.work, "node.log"), "w") as out:
            node = subprocess.Popen([os.path.join(ctx.drivers, ROS_NODE), "__name:=wsg_50_driver",
                                     "_ip:=127.0.0.1", "_port:=1000", "_protocol:=tcp",
                                     "_com_mode:=polling", "_rate:=10.0"],
                                    env=env, stdout=out, stderr=out)
        ros_service_call("/wsg_50_driver/set_force", struct.pack("<f", GRIP_FORCE_N))
        start = time.monotonic()
        error = ros_service_call("/wsg_50_driver/grasp", struct.pack("<ff", GRIP_WIDTH_MM,
                                                                       GRIP_SPEED_MM_S))
        grasp_s = time.monotonic() - start
        time.sleep(ctx.seconds)  # the grip settles; the node keeps polling
        state = json.loads(control(GRIP_CONTROL_PORT, "STATE?").split("=", 1)[1])
    finally:
        if node:
            stop(node, signal.SIGINT, 3)
        stop(master)
        log.close()
    return {"grip": {"commanded_force_n": GRIP_FORCE_N, "grasp_width_mm": GRIP_WIDTH_MM,
                     "grasp_service_error": error[0], "grasp_service_s": round(grasp_s, 3),
                     "state": state["grip"]["state_name"],
                     "force_limit_n": state["grip"]["force_n"],
                     "force_n": state["axis"]["force_n"], "width_mm": state["axis"]["position_mm"]}}


def node_log_summary(path):
    text = open(path, errors="replace").read()
    rates = re.findall(r"Rates for opening: (\d+)Hz, speed: (\d+)Hz, force: (\d+)Hz", text)
    # "Message receive failed": the driver's own reader (msg.c) gave up on a
    # frame; the node then publishes without that reading or skips the tick
    summary = {"errors": len(re.findall(r"\[ERROR\]", text)),
               "receive_failures": text.count("Message receive failed"),
               "first_errors": re.findall(r"\[ERROR\][^\n]*", text)[:5]}
    if rates:
        # the node's own 5 s windows; the first one includes the start
        steady = rates[1:] or rates
        summary["node_stream_rates_hz"] = {
            name: [int(r[i]) for r in steady] for i, name in enumerate(("opening", "speed", "force"))}
    return summary


def mode_ros_polling(ctx):
    """wsg50-ros-pkg, com_mode polling, rate 100, TCP: its status rate."""
    return ros_node({"ip": "127.0.0.1", "port": 1000, "protocol": "tcp", "com_mode": "polling",
                     "rate": "100.0"}, ctx.seconds, ctx.drivers, ctx.work)


def mode_ros_script(ctx):
    """wsg50-ros-pkg, com_mode script, rate 100, its cmd_measure.lua loaded."""
    return ros_node({"ip": "127.0.0.1", "port": 1000, "protocol": "tcp", "com_mode": "script",
                     "rate": "100.0"}, ctx.seconds, ctx.drivers, ctx.work)


def ros_auto(ctx, protocol, port):
    # rate 142: the node's interval is (int)(1000 / rate) = 7 ms
    return ros_node({"ip": "127.0.0.1", "port": port, "local_port": 1501, "protocol": protocol,
                     "com_mode": "auto_update", "rate": "142.0"},
                    ctx.seconds, ctx.drivers, ctx.work)


def mode_ros_auto_tcp(ctx):
    """wsg50-ros-pkg, com_mode auto_update, three 7 ms streams over TCP."""
    return ros_auto(ctx, "tcp", 1000)


def mode_ros_auto_udp(ctx):
    """wsg50-ros-pkg, com_mode auto_update, three 7 ms streams over UDP."""
    return ros_auto(ctx, "udp", 1500)


# ---------------------------------------------------------------- GCL

def mode_gcl_pos(ctx):
    """POS? over GCL/TCP, one at a time, as a polling client asks it."""
    round_trips = []
    with socket.create_connection(("127.0.0.1", 1000), 10) as s:
        s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        lines = s.makefile("rb")
        end = time.monotonic() + ctx.seconds
        while time.monotonic() < end:
            start = time.perf_counter()
            s.sendall(b"POS?\n")
            reply = lines.readline()
            round_trips.append((time.perf_counter() - start) * 1000.0)
            if not reply.startswith(b"POS="):
                return {"error": "unexpected reply %r" % reply, "round_trip_ms": None}
        s.sendall(b"BYE()\n")
        lines.readline()
    return {"round_trip_ms": percentiles(round_trips),
            "rate_hz": round(len(round_trips) / sum(round_trips) * 1000.0, 2)}


# ---------------------------------------------------------------- UMI

def umi_module(drivers):
    path = os.path.join(drivers, "src/umi/umi/real_world/wsg_binary_driver.py")
    spec = importlib.util.spec_from_file_location("umi_wsg_binary_driver", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def logged_frames(wsg):
    """Every frame the driver reads, in order, as 'ID STATUS' (its own reader)."""
    frames, receive = [], wsg.msg_receive

    def msg_receive():
        msg = receive()
        frames.append("0x%02X %s" % (msg["command_id"], proto.status_name(msg["status_code"])))
        return msg
    wsg.msg_receive = msg_receive
    return frames


def umi_width(wsg):
    msg = wsg.cmd_submit(0x43, b"\x00\x00\x00", pending=False)
    return round(struct.unpack("<f", msg["payload_bytes"][:4])[0], 2)


def mode_umi_stop(ctx):
    """UMI's WSGBinaryDriver: its stop_cmd() during a move (0x21).

    Ack, home, the move as its pre_position sends it, stop_cmd() half a
    second in, then its stop() at exit."""
    umi = umi_module(ctx.drivers)
    wsg = umi.WSGBinaryDriver(hostname="127.0.0.1", port=1000)
    wsg.start()
    wsg.tcp_sock.settimeout(10)
    frames = logged_frames(wsg)
    wsg.ack_fault()
    wsg.homing(positive_direction=True)
    del frames[:]
    wsg.msg_send(umi.CommandId.PrePosition.value, umi.args_to_bytes(0, 0.0, 50.0))
    wsg.msg_receive()  # its E_CMD_PENDING
    time.sleep(0.5)
    start = time.perf_counter()
    reply = wsg.stop_cmd()
    stop_ms = (time.perf_counter() - start) * 1000.0
    frames_until_stop = list(frames)
    wsg.tcp_sock.settimeout(0.5)
    with contextlib.suppress(socket.timeout):
        while not any(f.startswith("0x21") and "PENDING" not in f for f in frames):
            wsg.msg_receive()  # the move's final frame, when STOP came first
    wsg.tcp_sock.settimeout(10)
    width = umi_width(wsg)
    time.sleep(0.3)  # the jaws decelerate to rest
    width_later = umi_width(wsg)
    time.sleep(0.3)
    width_at_rest = umi_width(wsg)
    wsg.stop()  # UMI's exit: stop_cmd(), then disconnect (0x07)
    return {"stop_status": reply["status_code"].name, "stop_round_trip_ms": round(stop_ms, 3),
            "frames_from_move_to_stop": frames_until_stop, "frames": frames[:6],
            "width_after_stop_mm": width, "width_300ms_later_mm": width_later,
            "width_600ms_later_mm": width_at_rest,
            "stopped": width_later == width_at_rest and 0.0 < width_at_rest < 110.0}


def mode_umi_script(ctx):
    """UMI's script_query() (0xB0, its cmd_measure.lua) as fast as answered.

    The ceiling of its 30 Hz control loop."""
    umi = umi_module(ctx.drivers)
    round_trips = []
    with umi.WSGBinaryDriver(hostname="127.0.0.1", port=1000) as wsg:
        wsg.tcp_sock.settimeout(10)
        wsg.ack_fault()
        wsg.homing(positive_direction=True)
        end = time.monotonic() + ctx.seconds
        while time.monotonic() < end:
            start = time.perf_counter()
            wsg.script_query()
            round_trips.append((time.perf_counter() - start) * 1000.0)
    return {"round_trip_ms": percentiles(round_trips),
            "rate_hz": round(len(round_trips) / sum(round_trips) * 1000.0, 2)}


# ---------------------------------------------------------------- Drake

def mode_drake_demo(ctx):
    """drake-schunk-driver's demo (built from source): its homes' 4 s bound.

    Home +, -, + (each within 4 s, asserted), preposition to 80 mm, grasp
    at 62 mm (wsgsim gets a 62 mm part)."""
    start = time.monotonic()
    run = subprocess.run([os.path.join(ctx.drivers, "drake/demo")], capture_output=True,
                         text=True, timeout=60)
    return {"rc": run.returncode, "passed": run.returncode == 0,
            "wall_s": round(time.monotonic() - start, 3), "stderr": run.stderr[-500:]}


# drake-schunk-driver's PositionForceControl::DoCalibrationSteps (src/
# position_force_control.cc, src/wsg.h): each request with its timeout.
DRAKE_CALIBRATION = [
    ("system_info", 0x50, b"", 0.1),
    ("updates_system_state", 0x40, b"\x01\x14\x00", 0.25),
    ("updates_grasp_state", 0x41, b"\x01\x14\x00", 0.25),
    ("updates_opening_width", 0x43, b"\x01\x14\x00", 0.25),
    ("updates_speed", 0x44, b"\x01\x14\x00", 0.25),
    ("updates_force", 0x45, b"\x01\x14\x00", 0.25),
    ("home_negative", 0x20, b"\x02", 4.0),
    ("home_positive", 0x20, b"\x01", 4.0),
    ("tare", 0x38, b"", 4.0),
    ("physical_limits", 0x53, b"", 0.1),
    ("clear_soft_limits", 0x35, b"", 0.1),
]


def mode_drake_calibration(ctx):
    """Drake's schunk_driver calibration steps, each within its timeout (inferred).

    What drake-schunk-driver's schunk_driver does before control (inferred
    from its source: it needs LCM and Drake to build): its requests over UDP
    1500/1501, each waited for as its SendAndAwaitResponse does (frames of
    other IDs and E_CMD_PENDING thrown away), within its timeouts, then its
    five 20 ms update streams' rates."""
    client = proto.BinUdp(DRAKE_GRIPPER_ADDRESS, 1500, 1501, bind_host=DRAKE_GRIPPER_ADDRESS)
    steps = []
    try:
        for name, frame_id, payload, timeout in DRAKE_CALIBRATION:
            start = time.perf_counter()
            try:
                reply = client.request(frame_id, payload, on_other=lambda f: None,
                                       timeout=timeout)
                status = proto.status_name(reply.status)
            except TimeoutError:
                status = "TIMEOUT"
            took = time.perf_counter() - start
            steps.append({"step": name, "status": status, "s": round(took, 4),
                          "bound_s": timeout, "within": status != "TIMEOUT" and took <= timeout})
        counts, end = {}, time.monotonic() + ctx.seconds
        while time.monotonic() < end:
            frame = client.read_frame(end - time.monotonic())
            if frame:
                counts["0x%02X" % frame.id] = counts.get("0x%02X" % frame.id, 0) + 1
    finally:
        client.close()
    return {"steps": steps, "all_within_bounds": all(s["within"] for s in steps),
            "update_rates_hz": {k: round(v / ctx.seconds, 2) for k, v in sorted(counts.items())}}


# ---------------------------------------------------------------- modes

MODES = {
    "ros-polling": (mode_ros_polling, []),
    # its script answers with two FMF fingers only (docs/scripting.md)
    "ros-script": (mode_ros_script, ["--fingers", "fmf,fmf", "--script",
                                     "{drivers}/src/wsg50-ros-pkg/wsg_50_driver/cmd_measure.lua"]),
    "ros-auto-tcp": (mode_ros_auto_tcp, []),
    "ros-auto-udp": (mode_ros_auto_udp, []),
    "gcl-pos": (mode_gcl_pos, []),
    # not in `all`: it needs --physics mujoco (docs/physics.md)
    "ros-grip": (mode_ros_grip, ["--sim-port", str(GRIP_CONTROL_PORT)]),
    "umi-stop": (mode_umi_stop, []),
    "umi-script": (mode_umi_script, ["--script", "{drivers}/src/umi/umi/real_world/"
                                     "cmd_measure.lua"]),
    # Drake's host is another machine to the device: its subscribed updates
    # stream unpaid only when its address is listed (docs/behaviour.md)
    "drake-demo": (mode_drake_demo, ["--part", "62", "--udp-stream-allow", DRAKE_GRIPPER_ADDRESS]),
    "drake-calibration": (mode_drake_calibration,
                          ["--udp-stream-allow", DRAKE_GRIPPER_ADDRESS]),
}


class Context:
    def __init__(self, args, work):
        self.seconds, self.drivers, self.work = args.seconds, args.drivers, work


@contextlib.contextmanager
def between(command, work):
    """The --with command, running while the driver does (its output in
    with.log: an inherited pipe would hold the answer's reader open)."""
    if not command:
        yield
        return
    with open(os.path.join(work, "with.log"), "w") as out:
        # exec: SIGTERM reaches the command, not a shell
        proc = subprocess.Popen("exec " + command, shell=True, stdin=subprocess.DEVNULL,
                                stdout=out, stderr=out)
    try:
        wait_port(1000)
        yield
    finally:
        stop(proc)


def run_inside(args):
    """In the namespace: wsgsim with the options, the mode, its result."""
    function, extra = MODES[args.mode]
    loopback_up([DRAKE_GRIPPER_ADDRESS])
    with tempfile.TemporaryDirectory(prefix="wsgsim-driver-") as work:
        options = args.wsgsim_args + [e.format(drivers=args.drivers) for e in extra]
        with wsgsim(args.wsgsim, options, work) as log, between(args.with_command, work):
            try:
                result = function(Context(args, work))
            except Exception as err:  # a driver that breaks is a result here
                result = {"error": "%s: %s" % (type(err).__name__, err),
                          "during": [frame.line for frame in traceback.extract_tb(
                              err.__traceback__) if frame.name.startswith("mode_")]}
            wsgsim_log = open(log, errors="replace").read()
        if args.logs:
            shutil.copytree(work, os.path.join(args.logs, args.mode), dirs_exist_ok=True)
    result.update({"mode": args.mode, "wsgsim_options": options, "seconds": args.seconds})
    if "warn" in wsgsim_log or "error" in wsgsim_log:
        result["wsgsim_log_tail"] = wsgsim_log[-800:]
    return result


def run_in_namespace(args, mode):
    command = ["unshare", "-rn", sys.executable, os.path.abspath(__file__), mode,
               "--seconds", str(args.seconds), "--drivers", args.drivers,
               "--wsgsim", args.wsgsim] + (["--with", args.with_command] if args.with_command
                                           else []) + (["--logs", os.path.abspath(args.logs)]
                                                       if args.logs else []) \
        + ["--"] + args.wsgsim_args
    try:
        run = subprocess.run(command, capture_output=True, text=True,
                             env=dict(os.environ, **{INSIDE: "1"}),
                             timeout=args.seconds * 3 + 4 * STARTUP_TIMEOUT)
    except subprocess.TimeoutExpired:
        return {"mode": mode, "error": "the run did not end (a process left running?)"}
    if run.returncode != 0 or not run.stdout.strip():
        return {"mode": mode, "error": "the run failed: " + run.stderr[-2000:]}
    return json.loads(run.stdout)


def headline(result):
    """One line of a run's main figures, for a table."""
    if "error" in result:
        return "broke: " + result["error"].strip().splitlines()[-1][:160]
    if "status_topic" in result:
        topic = result["status_topic"]
        if not topic.get("count"):
            return "no status published (%s); node errors %d, receive failures %d" % (
                topic.get("error", ""), result["errors"], result["receive_failures"])
        line = "status %.1f Hz (interval p50 %.1f ms, max %.1f ms)" % (
            topic["rate_hz"], topic["interval_ms"]["p50"], topic["interval_ms"]["max"])
        streams = result.get("node_stream_rates_hz")
        if streams:
            line += "; node's stream rates " + ", ".join(
                "%s %s Hz" % (name, "/".join(map(str, rates))) for name, rates in streams.items())
        if result["errors"] or result["receive_failures"]:
            line += "; node errors %d, receive failures %d" % (result["errors"],
                                                               result["receive_failures"])
        return line
    if "round_trip_ms" in result:
        trip = result["round_trip_ms"]
        return "round trip p50 %.3f ms, p95 %.3f ms (%d); %.1f Hz" % (
            trip["p50"], trip["p95"], trip["n"], result["rate_hz"])
    if "stop_status" in result:
        return "STOP %s in %.1f ms, frames %s, stopped at %.2f mm: %s" % (
            result["stop_status"], result["stop_round_trip_ms"],
            " ".join(f.replace(" ", ":") for f in result["frames_from_move_to_stop"]),
            result["width_600ms_later_mm"], result["stopped"])
    if "grip" in result:
        grip = result["grip"]
        return "grasp %d in %.2f s: %s, %.2f N of %g N, width %.2f mm" % (
            grip["grasp_service_error"], grip["grasp_service_s"], grip["state"],
            grip["force_n"], grip["commanded_force_n"], grip["width_mm"])
    if "steps" in result:
        homes = [s for s in result["steps"] if s["step"].startswith("home")]
        return "homes %s s (bound 4 s), every step within its bound: %s; updates %s Hz" % (
            " / ".join("%.2f" % h["s"] for h in homes), result["all_within_bounds"],
            "/".join("%g" % v for v in result["update_rates_hz"].values()))
    return "demo %s in %.2f s" % ("passed" if result["passed"] else "FAILED", result["wall_s"])


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     epilog="after --: wsgsim's options")
    parser.add_argument("mode", nargs="?", help="a driver mode (--list), or all")
    parser.add_argument("--seconds", type=float, default=10.0, help="how long (default 10)")
    parser.add_argument("--drivers", default=os.environ.get("WSGSIM_DRIVERS_DIR", ""),
                        help="where tools/drivers/build.sh built them ($WSGSIM_DRIVERS_DIR)")
    parser.add_argument("--wsgsim", default=os.environ.get("WSGSIM", "build/wsgsim"))
    parser.add_argument("--with", dest="with_command", default="",
                        help="a shell command run beside the driver (a proxy)")
    parser.add_argument("--logs", default="", help="keep each mode's logs in DIR/MODE")
    parser.add_argument("--list", action="store_true", help="list the modes")
    parser.add_argument("--table", action="store_true",
                        help="one line per mode instead of JSON")
    split = argv.index("--") if "--" in argv else len(argv)
    args = parser.parse_args(argv[:split])
    args.wsgsim_args = argv[split + 1:]
    if args.list:
        for name, (function, _) in MODES.items():
            print("%-18s %s" % (name, function.__doc__.strip().split("\n")[0]))
        sys.exit(0)
    if args.mode not in list(MODES) + ["all"]:
        parser.error("unknown mode %r (--list)" % args.mode)
    if not os.path.isdir(args.drivers):
        parser.error("no drivers built at %r: run make drivers (--drivers DIR)" % args.drivers)
    args.drivers, args.wsgsim = os.path.abspath(args.drivers), os.path.abspath(args.wsgsim)
    return args


def main(argv):
    args = parse_args(argv)
    if os.environ.get(INSIDE):
        answer_fd = os.dup(1)
        os.dup2(2, 1)  # what the drivers print goes to stderr
        result = run_inside(args)
        os.write(answer_fd, (json.dumps(result) + "\n").encode())
        return 0
    modes = [m for m in MODES if m != "ros-grip"] if args.mode == "all" else [args.mode]
    results = [run_in_namespace(args, mode) for mode in modes]
    if args.table:
        for result in results:
            print("%-18s %s" % (result["mode"], headline(result)))
    else:
        print(json.dumps(results if args.mode == "all" else results[0], indent=1))
    return 1 if any("error" in r for r in results) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
