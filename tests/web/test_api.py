# SPDX-License-Identifier: BSD-3-Clause
"""The web interface's routes and errors (docs/web.md): the device list,
the state, the built-in page, and every kind of bad request, after which
nothing has changed."""
import socket
import time
import unittest

from webclient import (GclError, GclTcp, Wsgsim, WebSim, request, request_no_redirect,
                       wait_for)
from netns import start_in_netns  # noqa: E402 (tests/e2e, on the path once webclient is in)


class WebCase(unittest.TestCase):
    ARGS = ()

    def setUp(self):
        self.sim = WebSim(*self.ARGS)
        self.sim.start()
        self.addCleanup(self.sim.stop)

    def get(self, path):
        return request(self.sim.base + path)

    def call(self, method, path, body=None, raw=None):
        return request(self.sim.base + path, method=method, body=body, raw=raw)

    def assert_error(self, reply, status, name):
        self.assertEqual(reply.status, status, reply)
        self.assertEqual(reply.headers["Content-Type"], "application/json")
        j = reply.json()
        self.assertEqual(j["error"], name, j)
        self.assertIsInstance(j["code"], int)
        self.assertTrue(j["message"])
        return j


class Devices(WebCase):
    def test_ready_line_names_the_page_to_open(self):
        self.assertIn(", web page http://127.0.0.1:%d/" % self.sim.http_port,
                      "".join(self.sim.log))

    def test_a_request_from_the_page_itself_is_taken(self):
        own = request(self.sim.base + "/api/devices/0/settings", method="PUT",
                      body={"pwt_mm": 3},
                      headers={"Origin": "http://127.0.0.1:%d" % self.sim.http_port})
        self.assertEqual((own.status, own.json()["pwt_mm"]), (200, 3))

    def test_list_has_the_device_and_its_ports(self):
        reply = self.get("/api/devices")
        self.assertEqual(reply.status, 200)
        devices = reply.json()["devices"]
        self.assertEqual(len(devices), 1)
        d = devices[0]
        self.assertEqual((d["id"], d["tcp_port"], d["udp_port"]),
                         (0, self.sim.tcp_port, self.sim.udp_port))
        self.assertEqual(d["model"], "WSG 50-110")
        self.assertEqual(d["tag"], "wsgsim")
        self.assertIsInstance(d["serial"], int)

    def test_state_fields_carry_their_units(self):
        # the finger bus reports the fingers' types once it settled
        wait_for("the fingers", lambda: self.get("/api/devices/0/state").json()["fingers"][1]
                 ["type"] == "dsa")
        s = self.get("/api/devices/0/state").json()
        for key in ("time_ms", "position_mm", "speed_mm_s", "force_n", "temperature_c",
                    "stroke_mm"):
            self.assertIsInstance(s[key], (int, float), key)
        self.assertEqual(s["stroke_mm"], 110)
        self.assertEqual(s["grip_state"], {"code": 0, "name": "IDLE"})
        self.assertEqual(len(s["sysflags"]["names"]), 32)
        self.assertEqual(s["sysflags"]["names"][0], "SF_REFERENCED")
        self.assertEqual(s["sysflags"]["names"][10], "")  # reserved
        self.assertIsInstance(s["sysflags"]["value"], int)
        self.assertFalse(s["referenced"])
        self.assertEqual(s["motion"], "none")
        self.assertEqual(s["part"], {"present": False})
        self.assertEqual(s["obstacle"], {"present": False})
        self.assertIsNone(s["web_op"])
        fmf, dsa = s["fingers"]
        self.assertEqual((fmf["slot"], fmf["type"], dsa["slot"], dsa["type"]),
                         (0, "fmf", 1, "dsa"))
        self.assertIsInstance(fmf["data"], (int, float))
        self.assertEqual(len(dsa["data"]), dsa["rows"] * dsa["cols"])
        self.assertIn("FF_POWER_ON", fmf["flags"]["set"])

    def test_connections_list_peer_protocol_and_last_lines(self):
        self.get("/api/devices/0/state")  # a client looks: lines are kept from now on
        with self.sim.tcp() as gcl:
            gcl.expect("POS?", "POS=55.0")
            gcl.expect("GRIPSTATE?", "GRIPSTATE=0")
            local = "%s:%d" % gcl.sock.getsockname()[:2]
            conns = self.get("/api/devices/0/state").json()["connections"]
            self.assertEqual(len(conns), 1)
            c = conns[0]
            self.assertEqual((c["protocol"], c["transport"], c["peer"]), ("gcl", "tcp", local))
            self.assertEqual(c["last_lines"],
                             ["> POS?", "< POS=55.0", "> GRIPSTATE?", "< GRIPSTATE=0"])
            for _ in range(10):
                gcl.expect("SN?", "SN=12345678")
            lines = self.get("/api/devices/0/state").json()["connections"][0]["last_lines"]
            self.assertEqual(len(lines), 8)  # the last 8
            self.assertEqual(lines[-1], "< SN=12345678")
        with self.sim.udp() as udp:
            udp.expect("POS?", "POS=55.0")
            conns = self.get("/api/devices/0/state").json()["connections"]
            self.assertEqual([(c["transport"], c["last_lines"]) for c in conns],
                             [("udp", ["> POS?", "< POS=55.0"])])

    def test_binary_connection_is_listed_by_command_name(self):
        self.get("/api/devices/0/state")
        client = self.sim.binary_protocol()
        try:
            self.assertEqual(client.request(0x31).status, 0)  # get acceleration
            conns = self.get("/api/devices/0/state").json()["connections"]
            self.assertEqual(conns[0]["protocol"], "binary")
            self.assertRegex(conns[0]["last_lines"][0], r"^> 0x31 [\w-]+ \[\d+ bytes\]$")
            self.assertRegex(conns[0]["last_lines"][1], r"^< 0x31 ")
        finally:
            client.close()


class Startup(unittest.TestCase):
    def hold_port(self, port=0):
        """A listening socket of this test on port (a free one for 0). When
        another program holds the port, it waits until that one lets it go:
        a port held by someone else may be freed before wsgsim starts."""
        deadline = time.monotonic() + 120
        while True:
            s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
            try:
                s.bind(("0.0.0.0", port))
                break
            except OSError:
                s.close()
                if time.monotonic() > deadline:
                    self.fail("port %d stayed taken by another program for 120 s" % port)
                time.sleep(0.1)
        s.listen(1)
        self.addCleanup(s.close)
        return s

    def test_a_port_asked_for_and_taken_stops_the_start(self):
        port = self.hold_port().getsockname()[1]
        sim = Wsgsim("--http-port", str(port))
        with self.assertRaises(GclError):
            sim.start()
        self.assertEqual(sim.returncode, 2)
        self.assertIn("cannot listen on TCP 127.0.0.1:%d" % port, "".join(sim.log))

    def test_the_default_port_taken_is_skipped_with_a_warning(self):
        # in a network namespace of its own, where 8080 is held by this test
        # and by no other program on the machine
        result = start_in_netns(Wsgsim().binary, ["--bind", "127.0.0.1", "--tcp-port", "0",
                                                  "--udp-port", "0", "--binary-udp-port", "0"],
                                hold=[("tcp", 8080)])
        err = result["stderr"]
        self.assertEqual(result["rc"], 0, err)
        self.assertTrue(result["ready"], "wsgsim did not start: " + err)
        self.assertNotIn("http_port", result["ready"])
        self.assertIn("warning: http port 8080 cannot be had (Address already in use): "
                      "no web interface", err)
        self.assertNotIn("wsgsim: ", err, "a skipped default is no error line")
        self.assertNotIn(", web page ", err)


class Fleet(WebCase):
    ARGS = ("--devices", "2")

    def test_each_device_has_its_entry_state_and_page(self):
        devices = self.get("/api/devices").json()["devices"]
        self.assertEqual([d["id"] for d in devices], [0, 1])
        self.assertEqual(devices[1]["tag"], "wsgsim-1")
        self.assertNotEqual(devices[0]["tcp_port"], devices[1]["tcp_port"])
        self.assertEqual(self.get("/api/devices/1/state").json()["id"], 1)
        self.assertEqual(self.get("/devices/1").status, 200)
        self.assert_error(self.get("/devices/2"), 404, "E_NOT_FOUND")
        self.assert_error(self.get("/api/devices/2/state"), 404, "E_NOT_FOUND")

    def test_an_operation_moves_only_its_device(self):
        self.assertEqual(self.call("POST", "/api/devices/1/ops/home", {}).status, 202)
        self.assertEqual(self.get("/api/devices/1/state").json()["web_op"]["op"], "home")
        self.assertIsNone(self.get("/api/devices/0/state").json()["web_op"])

    def test_lines_of_another_device_are_listed_there(self):
        self.get("/api/devices/1/state")
        port = self.get("/api/devices").json()["devices"][1]["tcp_port"]
        with GclTcp("127.0.0.1", port) as gcl:
            gcl.expect("SN?", "SN=12345679")
            conns = self.get("/api/devices/1/state").json()["connections"]
            self.assertEqual(conns[0]["last_lines"], ["> SN?", "< SN=12345679"])
            self.assertEqual(self.get("/api/devices/0/state").json()["connections"], [])


class FleetByAddress(WebCase):
    """--address-per-device: the devices share their ports; the list says
    each one's address."""
    ARGS = ("--devices", "3", "--bind", "127.1.0.1", "--address-per-device")

    def test_each_entry_names_its_address(self):
        devices = self.get("/api/devices").json()["devices"]
        self.assertEqual([d["address"] for d in devices], ["127.1.0.1", "127.1.0.2", "127.1.0.3"])
        self.assertEqual(len({d["tcp_port"] for d in devices}), 1)
        with GclTcp(devices[2]["address"], devices[2]["tcp_port"]) as gcl:
            gcl.expect("SN?", "SN=12345680")


class Page(WebCase):
    def test_root_goes_to_device_0(self):
        reply = request_no_redirect(self.sim.base + "/")
        self.assertEqual(reply.status, 302)
        self.assertEqual(reply.headers["Location"], "/devices/0")

    def test_device_page_is_html(self):
        reply = self.get("/devices/0")
        self.assertEqual(reply.status, 200)
        self.assertTrue(reply.headers["Content-Type"].startswith("text/html"))
        self.assertIn("<html", reply.body)

    def test_charting_library_is_built_in(self):
        js = self.get("/static/dygraph.min.js")
        self.assertEqual(js.status, 200)
        self.assertTrue(js.headers["Content-Type"].startswith("text/javascript"))
        self.assertIn("Dygraph", js.body)
        css = self.get("/static/dygraph.min.css")
        self.assertEqual((css.status, css.headers["Content-Type"]),
                         (200, "text/css; charset=utf-8"))

    def test_script_editor_is_debians_codemirror(self):
        files = {"codemirror.js": "/usr/share/javascript/codemirror/lib/codemirror.js",
                 "codemirror.css": "/usr/share/javascript/codemirror/lib/codemirror.css",
                 "codemirror-lua.js": "/usr/share/javascript/codemirror/mode/lua/lua.js",
                 "codemirror-matchbrackets.js":
                     "/usr/share/javascript/codemirror/addon/edit/matchbrackets.js"}
        for name, path in files.items():
            reply = self.get("/static/" + name)
            self.assertEqual(reply.status, 200, name)
            kind = "text/css" if name.endswith(".css") else "text/javascript"
            self.assertTrue(reply.headers["Content-Type"].startswith(kind), name)
            with open(path, encoding="utf-8") as f:
                self.assertEqual(reply.body, f.read(), name)  # served from the system
        page = self.get("/devices/0").body
        for name in files:
            self.assertIn('"/static/%s"' % name, page)

    def test_unknown_file_is_404(self):
        self.assert_error(self.get("/static/nothing.js"), 404, "E_NOT_FOUND")
        self.assert_error(self.get("/static/../index.html"), 404, "E_NOT_FOUND")

    def test_page_is_read_only(self):
        reply = self.call("POST", "/devices/0", {})
        self.assert_error(reply, 405, "E_CMD_UNKNOWN")
        self.assertEqual(reply.headers["Allow"], "GET")


class Scene(WebCase):
    """The simulation panel's physics scene routes (docs/physics.md), the
    control channel's PLACE, PULL, MASS, FRICTION and LIFT."""
    ARGS = ("--physics", "mujoco", "--sim-port", "0", "--start-paused")

    def body(self, name):
        ctl = self.sim.control()
        self.addCleanup(ctl.close)
        reply = ctl("BODY(%s)" % name)
        return __import__("json").loads(reply[len("BODY="):])

    def test_scene_routes_act_as_the_commands(self):
        for route, args, said in [("mass", {"body": "box", "kg": 0.5}, "ACK MASS"),
                                  ("friction", {"body": "box", "mu": 0.3}, "ACK FRICTION"),
                                  ("place", {"body": "box", "x_mm": 0, "y_mm": 5, "z_mm": 20.1},
                                   "ACK PLACE"),
                                  ("pull", {"body": "box", "fx_n": 0, "fy_n": 0, "fz_n": 0},
                                   "ACK PULL"),
                                  ("lift", {"dz_mm": 10}, "ACK LIFT")]:
            reply = self.call("POST", "/api/devices/0/sim/" + route, args)
            self.assertEqual(reply.status, 200, reply)
            self.assertEqual(reply.json()["reply"], said)
        box = self.body("box")
        self.assertAlmostEqual(box["mass_kg"], 0.5)
        self.assertAlmostEqual(box["friction"], 0.3)
        self.assertAlmostEqual(box["pos_mm"][1], 5.0, places=3)

    def test_bad_scene_requests_change_nothing(self):
        before = self.body("box")
        self.assert_error(self.call("POST", "/api/devices/0/sim/mass", {"body": "nope", "kg": 1}),
                          422, "E_NOT_FOUND")
        self.assert_error(self.call("POST", "/api/devices/0/sim/mass", {"body": "box", "kg": -1}),
                          422, "E_RANGE_ERROR")
        self.assert_error(self.call("POST", "/api/devices/0/sim/mass", {"kg": 1}), 400,
                          "E_NOT_ENOUGH_PARAMS")
        self.assert_error(self.call("POST", "/api/devices/0/sim/pull", {"body": "box", "fx_n": 1}),
                          400, "E_NOT_ENOUGH_PARAMS")
        self.assert_error(self.call("POST", "/api/devices/0/sim/lift", {"dz_mm": 1e6}), 422,
                          "E_RANGE_ERROR")
        self.assert_error(self.call("POST", "/api/devices/0/sim/friction",
                                    {"body": "box", "mu": 1, "x": 2}), 400,
                          "E_INVALID_PARAMETER")
        self.assertEqual(self.body("box"), before)


class BadRequests(WebCase):
    # the GCL clients here leave without BYE; the clock stands still, so that
    # only a request could change the device
    ARGS = ("--no-disconnect-faststop", "--start-paused")

    def snapshot(self):
        s = self.get("/api/devices/0/state").json()
        settings = self.get("/api/devices/0/settings").json()
        return (s["position_mm"], s["grip_state"], s["sysflags"]["value"], s["web_op"],
                s["part"], settings)

    def setUp(self):
        super().setUp()
        self.before = self.snapshot()

    def tearDown(self):
        self.assertEqual(self.snapshot(), self.before, "a bad request changed the device")

    def test_unknown_paths_are_404(self):
        for path in ("/api", "/api/devicesx", "/api/devices/0", "/api/devices/0/",
                     "/api/devices/0/nothing", "/api/devices/x/state", "/api/devices/0x/state",
                     "/api/devices/0/settings/nothing", "/favicon.ico", "/devices/",
                     "/devices/00x"):
            self.assert_error(self.get(path), 404, "E_NOT_FOUND")

    def test_unknown_device_and_operation_are_404(self):
        self.assert_error(self.get("/api/devices/1/state"), 404, "E_NOT_FOUND")
        self.assert_error(self.get("/api/devices/99999999999/state"), 404, "E_NOT_FOUND")
        self.assert_error(self.call("POST", "/api/devices/0/ops/jump", {}), 404, "E_NOT_FOUND")
        self.assert_error(self.call("POST", "/api/devices/0/sim/meteor", {}), 404,
                          "E_NOT_FOUND")

    def test_wrong_methods_are_405_with_allow(self):
        cases = [("POST", "/api/devices", "GET"), ("PUT", "/api/devices/0/state", "GET"),
                 ("POST", "/api/devices/0/events", "GET"),
                 ("DELETE", "/api/devices/0/settings", "GET, PUT"),
                 ("GET", "/api/devices/0/settings/save", "POST"),
                 ("GET", "/api/devices/0/ops/move", "POST"),
                 ("PUT", "/api/devices/0/sim/part", "POST")]
        for method, path, allow in cases:
            reply = self.call(method, path, {} if method != "GET" else None)
            self.assert_error(reply, 405, "E_CMD_UNKNOWN")
            self.assertEqual(reply.headers["Allow"], allow, path)

    def test_malformed_json_is_400(self):
        for raw in (b"{", b"[1,2]", b"42", b"\"text\"", b"{\"position_mm\": }", b"\xff\xfe",
                    b"{\"position_mm\": 10}\x00"):
            self.assert_error(self.call("POST", "/api/devices/0/ops/move", raw=raw), 400,
                              "E_CMD_FORMAT_ERROR")

    def test_wrong_types_missing_and_unknown_fields_are_400(self):
        cases = [("ops/move", {"position_mm": "10"}, "E_INVALID_PARAMETER"),
                 ("ops/move", {"position_mm": None}, "E_INVALID_PARAMETER"),
                 ("ops/move", {"position_mm": [10]}, "E_INVALID_PARAMETER"),
                 ("ops/move", {}, "E_NOT_ENOUGH_PARAMS"),
                 ("ops/move", {"position_mm": 10, "speed": 5}, "E_INVALID_PARAMETER"),
                 ("ops/home", {"direction": 1}, "E_INVALID_PARAMETER"),
                 ("ops/stop", {"now": True}, "E_INVALID_PARAMETER"),
                 ("ops/tare", {"finger": "0"}, "E_INVALID_PARAMETER"),
                 ("sim/part", {}, "E_NOT_ENOUGH_PARAMS"),
                 ("sim/part", {"width_mm": True}, "E_INVALID_PARAMETER")]
        for path, body, name in cases:
            j = self.assert_error(self.call("POST", "/api/devices/0/" + path, body), 400, name)
            self.assertTrue(j["message"].split(":")[0] in str(body) or body == {}, j)
        self.assert_error(self.call("PUT", "/api/devices/0/settings", {"pwt_mm": "5"}), 400,
                          "E_INVALID_PARAMETER")
        self.assert_error(self.call("PUT", "/api/devices/0/settings", {"soft_limits": 1}), 400,
                          "E_INVALID_PARAMETER")
        self.assert_error(self.call("PUT", "/api/devices/0/settings", {"pwt": 5}), 400,
                          "E_INVALID_PARAMETER")

    def test_out_of_range_is_422_with_the_appendix_a_name(self):
        # (ranges are checked before the reference: no HOME needed)
        j = self.assert_error(self.call("POST", "/api/devices/0/ops/move", {"position_mm": 111}),
                              422, "E_RANGE_ERROR")
        self.assertEqual(j["code"], 28)
        for value in (-1, 1e300, -1e300):
            self.assert_error(self.call("POST", "/api/devices/0/ops/move",
                                        {"position_mm": 50, "speed_mm_s": value}),
                              422, "E_RANGE_ERROR")
        self.assert_error(self.call("POST", "/api/devices/0/ops/tare", {"finger": -1}), 422,
                          "E_INDEX_OUT_OF_BOUNDS")  # the core's "every finger" is no index
        self.assert_error(self.call("POST", "/api/devices/0/ops/tare", {"finger": 2}), 422,
                          "E_INDEX_OUT_OF_BOUNDS")
        self.assert_error(self.call("POST", "/api/devices/0/ops/tare", {"finger": 1e300}), 422,
                          "E_INDEX_OUT_OF_BOUNDS")
        self.assert_error(self.call("POST", "/api/devices/0/ops/home", {"direction": "up"}), 422,
                          "E_INVALID_PARAMETER")
        self.assert_error(self.call("PUT", "/api/devices/0/settings", {"pwt_mm": 1e300}), 422,
                          "E_RANGE_ERROR")
        self.assert_error(self.call("POST", "/api/devices/0/sim/part", {"width_mm": 1e300}), 422,
                          "E_RANGE_ERROR")

    def test_requests_from_another_site_change_nothing(self):
        """A foreign page can make the visitor's browser send a form or a
        plain-text POST, or a JSON one naming its own Origin: all refused."""
        url = self.sim.base + "/api/devices/0/"
        before = (self.get("/api/devices/0/settings").json(),
                  self.get("/api/devices/0/state").json()["grip_state"])
        form = request(url + "ops/home", method="POST", raw=b"direction=positive",
                       headers={"Content-Type": "application/x-www-form-urlencoded"})
        self.assert_error(form, 415, "E_CMD_FORMAT_ERROR")
        text = request(url + "settings", method="PUT", raw=b'{"pwt_mm": 3}',
                       headers={"Content-Type": "text/plain"})
        self.assert_error(text, 415, "E_CMD_FORMAT_ERROR")
        foreign = request(url + "settings", method="PUT", body={"pwt_mm": 3},
                          headers={"Origin": "http://pages.example"})
        self.assert_error(foreign, 403, "E_ACCESS_DENIED")
        after = (self.get("/api/devices/0/settings").json(),
                 self.get("/api/devices/0/state").json()["grip_state"])
        self.assertEqual(after, before)

    def test_bodies_over_4_kib_are_413(self):
        big = b"{\"position_mm\": 10, \"x\": \"" + b"a" * 5000 + b"\"}"
        self.assert_error(self.call("POST", "/api/devices/0/ops/move", raw=big), 413,
                          "E_OVERRUN")
        # without a Content-Length: chunked, counted as it arrives
        with socket.create_connection(("127.0.0.1", self.sim.http_port), timeout=60) as s:
            s.sendall(b"POST /api/devices/0/ops/move HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                      b"Transfer-Encoding: chunked\r\n\r\n")
            for _ in range(5):
                s.sendall(b"400\r\n" + b" " * 0x400 + b"\r\n")
            s.sendall(b"0\r\n\r\n")
            head = s.recv(4096).decode()
            self.assertTrue(head.startswith("HTTP/1.1 413"), head)
        exactly = b"{\"pwt_mm\": 10" + b" " * (4096 - 14) + b"}"
        self.assertEqual(len(exactly), 4096)
        reply = self.call("PUT", "/api/devices/0/settings", raw=exactly)  # the same value
        self.assertEqual((reply.status, reply.json()["pwt_mm"]), (200, 10))

    def test_a_declared_huge_body_is_refused_before_it_is_read(self):
        """A client claiming gigabytes gets its 413 at once: the server does
        not wait for (or read) a body it will refuse."""
        with socket.create_connection(("127.0.0.1", self.sim.http_port), timeout=60) as s:
            s.sendall(b"POST /api/devices/0/ops/move HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                      b"Content-Type: application/json\r\nContent-Length: 10000000000\r\n\r\n")
            head = s.recv(4096).decode()  # no body byte was sent
            self.assertTrue(head.startswith("HTTP/1.1 413"), head)

    def test_a_stalled_client_holds_up_nobody(self):
        stalled = socket.create_connection(("127.0.0.1", self.sim.http_port), timeout=60)
        self.addCleanup(stalled.close)
        stalled.sendall(b"POST /api/devices/0/ops/home HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                        b"Content-Length: 100\r\n\r\n{\"dir")
        half = socket.create_connection(("127.0.0.1", self.sim.http_port), timeout=60)
        self.addCleanup(half.close)
        half.sendall(b"GET /api/devi")
        with self.sim.tcp() as gcl:
            for _ in range(3):
                gcl.expect("POS?", "POS=55.0")
                self.assertEqual(self.get("/api/devices").status, 200)


if __name__ == "__main__":
    unittest.main()
