#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The device page (webui/) in Debian's headless Chromium, driven by
chromium-driver through python3-selenium, against build/wsgsim's HTTP
server. Run by `make browser-tests`; prints 'browser: N passed,
N failed'.

- the page loads and runs with no console error (the browser's log; every
  test checks it, allowing only the refusals it provokes);
- a MOVE sent by a GCL client shows as the new width on the page. No test
  depends on the machine's speed: the clock is paused and STEPped to the
  FIN, then the page is watched until it shows the width (WAIT_TIMEOUT_S only
  stops a hang). The time from the FIN reaching the client to the page
  showing the width is measured and printed, never asserted: headless
  Chromium on a busy CI is slow, and that is not a fault of the page;
- a GRIP pressed on the page is seen by a GCL client as GRIPSTATE=4;
- a PWT default saved on the page is what a new GCL connection reads with
  PWT?, in the same process and in a new one started with the saved file;
- refusals are shown by their Appendix A names, a setting's at its field,
  and change nothing;
- the simulation panel places a part and steps the clock; a page opened
  from a non-loopback address has it disabled after the server's 403;
- the live view reconnects to a wsgsim restarted on its port;
- with --devices 2 the selector opens the other device's page;
- the views (#live, #motion, #settings, #scripting, #system) switch by tab,
  by keyboard and by the address's hash, one at a time;
- a fault's FAST STOP shows as a banner whose FSACK clears it (refused, and
  said so, while the fault persists);
- the scripting view lists /user/, makes, edits and saves a file, runs it
  (its output in the console, the running flag in words) and stops it;
  uploads, renames and offers a download; a read-only store is shown
  without saving, the startup script in Settings;
- every input, select and textarea has a label with words in it (a DOM
  check over every view);
- the force axis spans at least the model's nominal force range when the
  force hardly changes (no autoscale to sensor noise);
- the system view shows the identity GCL reads and the log's lines;
- a physics scene is drawn from the plant's poses: the fingers close on
  the box and the grip's contacts appear; without a scene nothing is.

- MOVE takes any speed the model allows, not only up to the stroke;
- a paused clock shows on every view (header and status area) with Step and
  Resume at hand, a step says where the clock stands, a HOME waiting for
  the clock says so, and the fingers at t = 0 say they are starting;
- the status area is on every view, faults in the alarm style (red, "!"),
  warnings in amber, plain state (SF_REFERENCED) neither;
- a part around the jaws is drawn around them and named so;
- the tactile map empties when FAST STOP releases the grip;
- a page opened from a non-loopback address shows the simulation panel
  disabled from the start, without a refused request;
- a refused setting names the field in words and its range, shows the
  value in force again, and every number field shows its range;
- the script editor (Debian's CodeMirror) numbers and highlights the lines,
  marks the line of a script's error, and a failed run is not "started";
- at 420 px nothing scrolls sideways or overlaps, flag names are whole,
  the chart's legend lies outside its data; with the server gone a banner
  says so and the values shown turn grey.

It takes a screenshot of the page holding a part: $SCREENSHOT, by default
build/browser/live-view.png (`make browser-screenshot` refreshes
docs/img/live-view.png, the one README shows), and one of each state and
view beside it (fresh, homed, moving, holding, FAST STOP, paused clock,
script error, 420 px wide, server gone; shot()). Timeouts only stop a hang.
"""
import json
import os
import re
import socket
import sys
import tempfile
import time
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, os.path.join(ROOT, "tests", "web"))

from selenium import webdriver  # noqa: E402
from selenium.webdriver.chrome.service import Service  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.common.keys import Keys  # noqa: E402
from selenium.webdriver.support import expected_conditions as expected  # noqa: E402
from selenium.webdriver.support.ui import Select, WebDriverWait  # noqa: E402
from webclient import non_loopback_address, request  # noqa: E402

import wsgsim  # noqa: E402

CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"
PAGE_TIMEOUT_S = 120.0  # Chromium starting or loading a page on a busy CI
WAIT_TIMEOUT_S = 60.0  # the page showing a state the device reached
MOVE_WIDTHS_MM = (40, 75.5, 20)
VIEWS = ("motion", "settings", "scripting", "system", "live")
START_ATTEMPTS = 5  # starts on a free port that was taken meanwhile
WINDOW = "1400,1400"  # the whole live view in the screenshot
SCREENSHOT = os.environ.get("SCREENSHOT") or os.path.join(ROOT, "build", "browser",
                                                         "live-view.png")
SHOTS = os.path.join(ROOT, "build", "browser")  # every state's and view's screenshot
NARROW = (420, 1400)  # a phone's width


def free_tcp_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Wsgsim(wsgsim.Wsgsim):
    """build/wsgsim (or $WSGSIM) with its HTTP server on a free port
    (--http-port 0 turns the server off, so the port is picked here)."""

    def __init__(self, *args, http_port=None, **keywords):
        binary = os.environ.get("WSGSIM", os.path.join(ROOT, "build", "wsgsim"))
        self.fixed_http_port = http_port  # else a free one at each start
        super().__init__("--http-port", "0", *args, binary=binary, **keywords)

    def start(self, timeout=wsgsim.START_TIMEOUT):
        # another program may take the free port before wsgsim binds it
        port_at = self.args.index("--http-port") + 1
        for attempt in range(START_ATTEMPTS):
            self.args[port_at] = str(self.fixed_http_port or free_tcp_port())
            try:
                return super().start(timeout)
            except wsgsim.GclError:
                if attempt + 1 == START_ATTEMPTS or "in use" not in "".join(self.log):
                    raise
                time.sleep(0.5)  # a fixed port may be free again in a moment

    def url(self, path="/"):
        """The page's address (the --ready-file's http_port)."""
        return "http://%s:%d%s" % (self.host, self.http_port, path)


def start_chromium():
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu",
                     "--disable-dev-shm-usage", "--window-size=" + WINDOW,
                     "--no-first-run", "--disable-extensions"):
        options.add_argument(argument)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    driver.set_page_load_timeout(PAGE_TIMEOUT_S)
    driver.set_script_timeout(PAGE_TIMEOUT_S)
    return driver


class PageTest(unittest.TestCase):
    driver = None

    @classmethod
    def setUpClass(cls):
        for program in (CHROMIUM, CHROMEDRIVER):
            if not os.path.exists(program):
                raise AssertionError("%s is missing: make deps-check installs Debian's chromium "
                                     "and chromium-driver" % program)
        cls.driver = start_chromium()

    @classmethod
    def tearDownClass(cls):
        if cls.driver is not None:
            cls.driver.quit()

    def tearDown(self):
        # leave the page, whose wsgsim has stopped, so that it stops trying
        # to reconnect, and drop what it logged meanwhile
        self.driver.get("about:blank")
        self.driver.get_log("browser")

    # ------------------------------------------------------------ helpers

    def open_page(self, sim):
        self.driver.get("about:blank")
        self.driver.get_log("browser")  # only this page's messages count
        self.driver.get(sim.url("/devices/0"))
        self.wait_for("the event stream", lambda d: d.find_element(By.ID, "link").text == "live")

    def wait_for(self, what, condition, timeout=WAIT_TIMEOUT_S):
        try:
            return WebDriverWait(self.driver, timeout, poll_frequency=0.05).until(condition)
        except Exception as exc:
            raise AssertionError("page: gave up after %.0f s waiting for %s (%s)" %
                                 (timeout, what, type(exc).__name__)) from None

    def text(self, element_id):
        """The element's text, also in a view not shown (Selenium's .text
        is "" there)."""
        return self.driver.find_element(By.ID, element_id).get_attribute("textContent")

    def wait_for_text(self, element_id, expected, timeout=WAIT_TIMEOUT_S):
        try:
            self.wait_for("#%s to show %r" % (element_id, expected),
                          lambda d: self.text(element_id) == expected, timeout)
        except AssertionError as exc:
            raise AssertionError("%s; it shows %r" % (exc, self.text(element_id))) from None

    def wait_for_flag(self, name):
        self.wait_for("flag %s lit" % name, lambda d: d.execute_script(
            "return [...document.querySelectorAll('#flags li.set')]"
            ".some((item) => item.dataset.name === arguments[0])", name))

    def show_view(self, name):
        """Clicks the view's tab and waits until it is the one shown."""
        self.click("#tab-" + name)
        self.wait_for_view(name)

    def wait_for_view(self, name):
        self.wait_for("the %s view" % name, lambda d: d.execute_script(
            "return [...document.querySelectorAll('.view')]"
            ".filter((view) => !view.hidden).map((view) => view.dataset.view)") == [name])

    def fill(self, selector, value):
        field = self.driver.find_element(By.CSS_SELECTOR, selector)
        field.clear()
        field.send_keys(str(value))

    def click(self, selector):
        self.driver.find_element(By.CSS_SELECTOR, selector).click()

    def shot(self, name):
        """A screenshot of the page as it is, build/browser/NAME.png."""
        os.makedirs(SHOTS, exist_ok=True)
        path = os.path.join(SHOTS, name + ".png")
        self.assertTrue(self.driver.save_screenshot(path), path)

    def js(self, script, *args):
        return self.driver.execute_script(script, *args)

    def set_editor(self, text):
        """The script editor's text, set as CodeMirror takes it."""
        self.js("document.querySelector('.CodeMirror').CodeMirror.setValue(arguments[0])", text)

    def editor_text(self):
        return self.js("return document.querySelector('.CodeMirror').CodeMirror.getValue()")

    def status_chips(self):
        """The status area's chips: [(name, kind), ...]."""
        return self.js("return [...document.querySelectorAll('#status-flags li')]"
                       ".map((li) => [li.dataset.name || li.textContent, li.className])")

    def wait_for_chip(self, name):
        self.wait_for("%s in the status area" % name, lambda d: any(
            chip == name for chip, _ in self.status_chips()))

    def home_paused(self, client, control):
        """FSACK and HOME to their FIN on a paused clock."""
        control.step(100)  # the fingers start
        client.expect("FSACK()", "ACK FSACK")
        client.expect("HOME()", "ACK HOME")
        control.step_until(client, "FIN HOME")

    def assert_no_console_errors(self, refused=0):
        """No error in the browser's log but the refused requests expected
        (the browser logs each 4xx reply; the page shows them itself)."""
        errors = [entry["message"] for entry in self.driver.get_log("browser")
                  if entry["level"] == "SEVERE"]
        refusals = [e for e in errors if re.search(r"status of 4\d\d ", e)]
        if len(refusals) == refused:
            errors = [e for e in errors if e not in refusals]
        if errors:
            self.fail("the page logged errors:\n" + "\n".join(errors))

    # -------------------------------------------------------------- tests

    def test_page_loads_and_shows_the_device(self):
        with Wsgsim() as sim, sim.tcp() as client:
            self.open_page(sim)
            self.wait_for_text("width", "%.1f" % client.query_float("POS"))
            # the 32 system flags by name, the fingers, the settings form
            flags = self.driver.find_elements(By.CSS_SELECTOR, "#flags li")
            self.assertEqual(len(flags), 32)
            self.assertIn("SF_REFERENCED", [flag.get_attribute("data-name") for flag in flags])
            # set or clear in words, not only by colour
            self.assertEqual(flags[0].get_attribute("textContent"), "○SF_REFERENCED: clear")
            self.wait_for("the finger views",
                          lambda d: len(d.find_elements(By.CSS_SELECTOR, "#fingers .finger")) == 2)
            self.wait_for("the settings", lambda d: d.find_elements(By.ID, "setting-pwt_mm"))
            self.wait_for("the chart", lambda d: d.find_elements(By.CSS_SELECTOR, "#chart canvas"))
            self.assert_no_console_errors()

    def test_gcl_move_shows_as_the_new_width(self):
        with Wsgsim(paused=True) as sim, sim.tcp() as client, sim.control() as control:
            client.expect("FSACK()", "ACK FSACK")
            client.expect("HOME()", "ACK HOME")
            control.step_until(client, "FIN HOME")
            self.open_page(sim)
            self.wait_for_text("width", "%.1f" % client.query_float("POS"))

            latencies_ms = [self.move_and_watch(client, control, width)
                            for width in MOVE_WIDTHS_MM]
            print("\nbrowser: GCL FIN MOVE to the page showing the new width: %s ms "
                  "(measured, not asserted)" % ", ".join("%.0f" % ms for ms in latencies_ms),
                  flush=True)
            self.assert_no_console_errors()

    def move_and_watch(self, client, control, width_mm):
        """MOVE(width_mm) run to its FIN on the paused clock; the wall-clock
        ms from the FIN reaching the client to the page showing the width
        (0 when the page showed it first: the stream and the FIN race)."""
        client.expect("MOVE(%g)" % width_mm, "ACK MOVE")
        control.step_until(client, "FIN MOVE", step_ms=20)
        fin_ms = time.time() * 1000  # the clock the page's Date.now() reads
        self.wait_for_text("width", "%.1f" % width_mm, timeout=WAIT_TIMEOUT_S)
        shown_ms = float(self.driver.execute_script(
            "return document.getElementById('width').dataset.shownAt"))
        return max(shown_ms - fin_ms, 0.0)

    def test_grip_on_the_page_is_holding_for_gcl(self):
        with Wsgsim("--part", "40") as sim, sim.tcp() as client:
            client.expect("FSACK()", "ACK FSACK")
            self.open_page(sim)
            self.show_view("motion")
            self.click("#op-home button")
            self.wait_for_flag("SF_REFERENCED")
            self.wait_for_text("motion-text", "none")
            self.fill("#op-grip input[name=force_n]", 20)
            self.click("#op-grip button")
            wsgsim.wait_for_reply(client, "GRIPSTATE?", "GRIPSTATE=4", WAIT_TIMEOUT_S)
            self.wait_for_text_start("op-result", "GRIP: E_SUCCESS")
            self.wait_for_text("grip-state", "HOLDING (4)")
            self.take_screenshot()
            self.assert_no_console_errors()

    def take_screenshot(self):
        self.show_view("live")
        # the chart drawn on to 1.5 s after the grip force came (> 10 N)
        self.wait_for("the chart of the grip", lambda d: d.execute_script(
            "const held = live.chartData.find((point) => point[2] > 10);"
            "return Boolean(live.chart && held && live.chart.xAxisRange()[1] - held[0] > 1.5)"))
        os.makedirs(os.path.dirname(SCREENSHOT), exist_ok=True)
        self.assertTrue(self.driver.save_screenshot(SCREENSHOT), SCREENSHOT)

    def test_pwt_saved_on_the_page_is_read_by_gcl(self):
        with tempfile.TemporaryDirectory(prefix="wsgsim-browser-") as tmp:
            config = os.path.join(tmp, "wsgsim.ini")
            with open(config, "w") as f:
                f.write("; written by the page's Save\n")
            with Wsgsim("--config", config) as sim:
                self.open_page(sim)
                self.show_view("settings")
                self.wait_for("the settings", lambda d: d.find_elements(By.ID, "setting-pwt_mm"))
                self.fill("#setting-pwt_mm", "7.5")
                self.click("#settings-save")
                self.wait_for("the save", lambda d: d.find_element(
                    By.ID, "settings-result").text.startswith("saved to"))
                with sim.tcp() as client:
                    self.assertEqual(client.query_float("PWT"), 7.5)
                self.assert_no_console_errors()
            with Wsgsim("--config", config) as sim, sim.tcp() as client:
                self.assertEqual(client.query_float("PWT"), 7.5)

    def test_refusals_are_shown_by_their_manual_names(self):
        with Wsgsim() as sim, sim.tcp() as client:
            start_mm = client.query_float("POS")
            defaults = (client.query_float("PWT"), client.query_float("CLT"))
            self.open_page(sim)
            self.show_view("motion")
            self.fill("#op-move input[name=position_mm]", 20)
            self.click("#op-move button")
            self.wait_for_text_start("op-result", "MOVE: E_NOT_INITIALIZED (3)")
            self.show_view("settings")
            self.wait_for("the settings", lambda d: d.find_elements(By.ID, "setting-pwt_mm"))
            self.fill("#setting-pwt_mm", 500)
            self.fill("#setting-clt_mm", 5)
            self.click("#settings-apply")
            self.wait_for_text_start("setting-error-pwt_mm",
                                     "part width tolerance (PWT) 500 mm is out of range")
            self.assertIn("(E_RANGE_ERROR)", self.text("settings-result"))
            self.assertEqual(self.text("setting-error-clt_mm"), "")
            self.assertEqual(client.query_float("POS"), start_mm)  # nothing moved,
            with sim.tcp() as fresh:  # nothing of the PUT applied
                self.assertEqual((fresh.query_float("PWT"), fresh.query_float("CLT")), defaults)
            self.assert_no_console_errors(refused=2)

    def wait_for_text_start(self, element_id, start):
        try:
            self.wait_for("#%s to start with %r" % (element_id, start),
                          lambda d: self.text(element_id).startswith(start))
        except AssertionError as exc:
            raise AssertionError("%s; it shows %r" % (exc, self.text(element_id))) from None

    def test_simulation_panel_acts_on_the_world(self):
        with Wsgsim(paused=True) as sim, sim.control() as control:
            self.open_page(sim)
            self.fill("#sim-part input[name=width_mm]", 30)
            self.click("#sim-part button[type=submit]")
            self.wait_for_text("sim-result", "part: ACK PART")
            self.assertTrue(control("PART?").startswith("PART=[1,30"), control("PART?"))
            self.wait_for("the part drawn", lambda d: d.find_element(
                By.ID, "part").get_attribute("hidden") is None)
            self.assertFalse(self.driver.find_element(By.ID, "sim-scene").is_displayed())
            before_ms = control.json("SIMTIME?")[0]
            self.fill("#sim-clock input[name=ms]", 250)
            self.click("#sim-clock button[data-action=step]")
            wsgsim.wait_for("the STEP from the page", lambda: control.json(
                "SIMTIME?")[0] == before_ms + 250, WAIT_TIMEOUT_S)
            self.assert_no_console_errors()

    def test_scene_forms_steer_a_physics_scene(self):
        with Wsgsim("--physics", "mujoco", paused=True) as sim, sim.control() as control:
            self.open_page(sim)
            self.wait_for("the scene's forms", lambda d: d.find_element(
                By.ID, "sim-scene").is_displayed())
            self.fill("#sim-mass input[name=kg]", 0.75)
            self.click("#sim-mass button[type=submit]")
            self.wait_for_text("sim-result", "mass: ACK MASS")
            self.assertAlmostEqual(json.loads(control("BODY(box)").partition("=")[2])["mass_kg"], 0.75)
            self.fill("#sim-mass input[name=body]", "nope")
            self.click("#sim-mass button[type=submit]")
            self.wait_for_text("sim-result", 'mass: E_NOT_FOUND (21): no body "nope" in the scene '
                               "(BODIES? lists them)")
            self.assert_no_console_errors(refused=1)

    def test_simulation_panel_disabled_for_a_remote_page(self):
        with Wsgsim("--http-bind", "0.0.0.0", control=True) as sim, sim.control() as control:
            self.driver.get("about:blank")
            self.driver.get("http://%s:%d/devices/0" % (non_loopback_address(), sim.http_port))
            self.wait_for("the event stream",
                          lambda d: d.find_element(By.ID, "link").text == "live")
            # said from the start (sim_allowed), not after a refused click
            self.wait_for("the note", lambda d: d.find_element(
                By.ID, "sim-unavailable").is_displayed())
            for selector in ("#sim-part button[type=submit]", "#sim-clock button[type=submit]",
                             "#sim-fault select", "#clock-pause"):
                self.assertFalse(self.driver.find_element(By.CSS_SELECTOR, selector).is_enabled(),
                                 selector)
            self.click("#sim-part button[type=submit]")  # a disabled button sends nothing
            self.assertEqual(self.text("sim-result"), "")
            self.assertEqual(control("PART?").split(",")[0], "PART=[0")
            # scripts are run and stored under the same rule: said, not tried
            self.show_view("scripting")
            self.wait_for("the scripting note", lambda d: d.find_element(
                By.ID, "script-unavailable").is_displayed())
            self.wait_for("the note of no store", lambda d: d.find_element(
                By.ID, "store-missing").is_displayed())
            self.assertFalse(self.driver.find_element(By.ID, "script-stop").is_enabled())
            self.assert_no_console_errors()

    def test_live_view_reconnects_to_a_restarted_server(self):
        with Wsgsim() as first:
            self.open_page(first)
            self.wait_for_text("part-text", "none")
            port = first.http_port
        self.wait_for("the page to notice", lambda d: d.find_element(
            By.ID, "link").text == "reconnecting")
        with Wsgsim("--part", "25", http_port=port):
            self.wait_for("the event stream again",
                          lambda d: d.find_element(By.ID, "link").text == "live")
            self.wait_for_text("part-text", "25.0 mm, between the jaws")

    def test_device_selector_opens_another_device(self):
        with Wsgsim("--devices", "2") as sim:
            self.open_page(sim)
            picker = self.driver.find_element(By.ID, "device-select")
            self.wait_for("the device selector", lambda d: picker.is_displayed())
            self.driver.find_element(By.CSS_SELECTOR, "#device-select option[value='1']").click()
            self.wait_for("device 1's page", lambda d: d.current_url.endswith("/devices/1"))
            self.wait_for("the event stream",
                          lambda d: d.find_element(By.ID, "link").text == "live")
            self.wait_for_text_start("identity", "WSG 50-110 · wsgsim-1 · device 1")
            self.assert_no_console_errors()

    def test_views_switch_by_tab_keyboard_and_address(self):
        with Wsgsim() as sim:
            self.open_page(sim)
            self.wait_for_view("live")
            for name in VIEWS:
                self.show_view(name)
                self.assertEqual(self.driver.find_element(By.ID, "tab-" + name)
                                 .get_attribute("aria-current"), "page")
                self.assertTrue(self.driver.current_url.endswith("#" + name))
            # the tabs are links: Enter on a focused one opens its view
            tab = self.driver.find_element(By.ID, "tab-motion")
            tab.send_keys(Keys.ENTER)
            self.wait_for_view("motion")
            self.driver.back()  # the browser's history follows the views
            self.wait_for_view("live")
            self.driver.get(sim.url("/devices/0#settings"))  # a bookmark
            self.wait_for_view("settings")
            # the "skip to the view" link moves the focus, not the view
            self.driver.execute_script("document.querySelector('a.skip').focus()")
            self.driver.switch_to.active_element.send_keys(Keys.ENTER)
            self.wait_for("the focus on the view", lambda d: d.execute_script(
                "return document.activeElement.id") == "views")
            self.wait_for_view("settings")
            self.driver.get("about:blank")  # a page opened with an unknown hash
            self.driver.get(sim.url("/devices/0#nonsense"))
            self.wait_for_view("live")
            self.assert_no_console_errors()

    def test_fast_stop_banner_and_its_fsack(self):
        with Wsgsim(control=True) as sim, sim.control() as control, sim.tcp() as client:
            client.expect("FSACK()", "ACK FSACK")
            self.open_page(sim)
            self.show_view("scripting")  # the banner shows on every view
            self.wait_for_text("width", "%.1f" % client.query_float("POS"))
            banner = self.driver.find_element(By.ID, "faststop-banner")
            self.assertFalse(banner.is_displayed())
            self.assertEqual(control('FAULT("POWER")'), "ACK FAULT")
            self.wait_for("the FAST STOP banner", lambda d: banner.is_displayed())
            self.assertEqual(banner.get_attribute("role"), "alert")
            self.wait_for_text_start("faststop-cause", "while SF_POWER_FAULT persists")
            self.click("#banner-fsack")  # refused while the cause persists
            self.wait_for_text_start("banner-result", "FSACK: E_ACCESS_DENIED (16)")
            self.assertTrue(banner.is_displayed())
            self.assertEqual(control('CLEAR("POWER")'), "ACK CLEAR")
            self.wait_for_text_start("faststop-cause", "the drive is off")
            self.click("#banner-fsack")
            self.wait_for("the banner to go", lambda d: not banner.is_displayed())
            client.expect("SYSFLAGS[12]?", "SYSFLAGS[12]=0")  # SF_FAST_STOP
            self.assert_no_console_errors(refused=1)

    def test_scripting_view_edits_runs_and_stops_a_script(self):
        with tempfile.TemporaryDirectory(prefix="wsgsim-store-") as store:
            with open(os.path.join(store, "hello.lua"), "w") as f:
                f.write("print('hello')\n")
            with Wsgsim("--script-dir", store) as sim:
                self.open_page(sim)
                self.show_view("scripting")
                self.wait_for("the file list", lambda d: d.execute_script(
                    "return [...document.querySelectorAll('#file-list tr')]"
                    ".map((row) => row.dataset.name)") == ["hello.lua"])
                # a new file, written, saved, run: its output in the console
                self.fill("#file-new input[name=name]", "loop.lua")
                self.click("#file-new button")
                self.wait_for_text("editor-file", "/user/loop.lua")
                self.assertTrue(os.path.exists(os.path.join(store, "loop.lua")))
                self.set_editor("print('from the page')\nwhile true do sleep(50) end\n")
                self.click("#script-save")
                self.wait_for_text_start("script-result", "saved loop.lua")
                with open(os.path.join(store, "loop.lua")) as f:
                    self.assertEqual(f.read(),
                                     "print('from the page')\nwhile true do sleep(50) end\n")
                # a second "new" loop.lua does not empty the first
                self.click("#file-new button")
                self.wait_for_text("files-result", "loop.lua exists: open it from the list")
                with open(os.path.join(store, "loop.lua")) as f:
                    self.assertTrue(f.read().startswith("print('from the page')"))
                self.click("#script-run")
                self.wait_for("the console line", lambda d: "from the page" in d.find_element(
                    By.ID, "console").text)
                self.wait_for_text("script-flag-running", "SF_SCRIPT_RUNNING ✔ set")
                self.wait_for_text("script-file", "/user/loop.lua")
                self.click("#script-stop")
                self.wait_for_text("script-flag-running", "SF_SCRIPT_RUNNING ○ clear")
                self.wait_for_text_start("script-file", "no script runs")
                with sim.tcp() as client:
                    client.expect("SYSFLAGS[19]?", "SYSFLAGS[19]=0")  # SF_SCRIPT_RUNNING
                # Run saves the open file first; typed as a user types it
                self.set_editor("")
                self.driver.find_element(By.CSS_SELECTOR, ".CodeMirror-code").send_keys(
                    "print('edited, then run')" + Keys.ENTER)
                self.click("#script-run")
                self.wait_for("the edited script's line", lambda d: "edited, then run" in
                              d.find_element(By.ID, "console").text)
                with open(os.path.join(store, "loop.lua")) as f:
                    self.assertEqual(f.read(), "print('edited, then run')\n")
                # delete, after the browser's confirmation
                self.click("#file-list button[aria-label='Delete hello.lua']")
                self.wait_for("the confirmation", expected.alert_is_present()).accept()
                self.wait_for("the list without it", lambda d: not d.find_elements(
                    By.CSS_SELECTOR, "#file-list tr[data-name='hello.lua']"))
                self.assertFalse(os.path.exists(os.path.join(store, "hello.lua")))
                self.assert_no_console_errors()

    def test_file_manager_uploads_renames_and_downloads(self):
        with tempfile.TemporaryDirectory(prefix="wsgsim-store-") as store, \
                tempfile.TemporaryDirectory(prefix="wsgsim-upload-") as home:
            upload = os.path.join(home, "up.lua")
            with open(upload, "w") as f:
                f.write("print('uploaded')\n")
            with Wsgsim("--script-dir", store) as sim:
                self.open_page(sim)
                self.show_view("scripting")
                self.wait_for("the empty list", lambda d: d.find_element(
                    By.ID, "file-new").find_element(By.TAG_NAME, "button").is_enabled())
                self.driver.find_element(By.CSS_SELECTOR, "#file-upload input").send_keys(upload)
                self.wait_for_text_start("files-result", "saved up.lua (18 bytes)")
                self.wait_for("up.lua listed", lambda d: d.find_elements(
                    By.CSS_SELECTOR, "#file-list tr[data-name='up.lua']"))
                with open(os.path.join(store, "up.lua")) as f:
                    self.assertEqual(f.read(), "print('uploaded')\n")
                self.click("#file-list button[aria-label='Rename up.lua']")
                prompt = self.wait_for("the new name's prompt", expected.alert_is_present())
                prompt.send_keys("moved.lua")
                prompt.accept()
                self.wait_for_text("files-result", "renamed up.lua to moved.lua")
                self.assertEqual(sorted(os.listdir(store)), ["moved.lua"])
                link = self.driver.find_element(
                    By.CSS_SELECTOR, "#file-list a[aria-label='Download moved.lua']")
                self.assertEqual(link.get_attribute("download"), "moved.lua")
                self.assertTrue(link.get_attribute("href").endswith(
                    "/api/devices/0/files/moved.lua"))
                self.assert_no_console_errors()

    def test_new_file_names_end_in_lua(self):
        """The store holds NAME.lua files only: the new-file field says so
        beside it, refuses another name in the browser with the rule in
        words, and sends nothing; a Lua name is made."""
        with tempfile.TemporaryDirectory(prefix="wsgsim-store-") as store:
            with Wsgsim("--script-dir", store) as sim:
                self.open_page(sim)
                self.show_view("scripting")
                self.wait_for("the empty list", lambda d: d.find_element(
                    By.CSS_SELECTOR, "#file-new button").is_enabled())
                self.assertIn("NAME.lua", self.text("file-new-rule"))
                field = "#file-new input[name=name]"
                for name in ("notes.txt", "two words.lua", "up..lua", "a/b.lua", "x" * 61 + ".lua"):
                    self.fill(field, name)
                    self.click("#file-new button")
                    self.wait_for_text("files-result", "new file: a script's name ends in .lua "
                                       "(NAME.lua: at most 64 characters, no spaces, '/', '\\' "
                                       "or '..')")
                    self.assertFalse(self.js("return document.querySelector(arguments[0])"
                                             ".checkValidity()", field), name)
                    self.js("document.getElementById('files-result').textContent = ''")
                self.assertEqual(os.listdir(store), [])
                self.fill(field, "grip_2.lua")
                self.click("#file-new button")
                self.wait_for_text("editor-file", "/user/grip_2.lua")
                self.assertEqual(os.listdir(store), ["grip_2.lua"])
                self.assert_no_console_errors()  # nothing was sent and refused

    def test_the_startup_script_keeps_its_name(self):
        """Delete and rename of a device's startup script are refused with
        the reason (another device's too: the fleet shares the store); the
        files and the choices stay, and a refused rename leaves no copy."""
        with tempfile.TemporaryDirectory(prefix="wsgsim-store-") as store:
            for name in ("hello.lua", "other.lua"):
                with open(os.path.join(store, name), "w") as f:
                    f.write("print('hello')\n")
            with Wsgsim("--script-dir", store, "--devices", "2") as sim:
                for device, name in ((0, "hello.lua"), (1, "other.lua")):
                    self.assertEqual(request(sim.url("/api/devices/%d/script/startup" % device),
                                             "PUT", {"file": "/user/" + name}).status, 200)
                self.open_page(sim)
                self.show_view("scripting")
                self.wait_for("the files listed", lambda d: len(d.find_elements(
                    By.CSS_SELECTOR, "#file-list tr")) == 2)
                self.click("#file-list button[aria-label='Delete hello.lua']")
                self.wait_for("the confirmation", expected.alert_is_present()).accept()
                self.wait_for_text_start("files-result", "delete hello.lua: E_NOT_AVAILABLE")
                self.assertTrue(self.text("files-result").endswith(
                    ": hello.lua is device 0's startup script: choose another startup script "
                    "or none first"), self.text("files-result"))
                self.click("#file-list button[aria-label='Rename hello.lua']")
                self.wait_for_text("files-result", "rename hello.lua: it is the startup script: "
                                   "choose another or none first (Settings → System)")
                self.click("#file-list button[aria-label='Rename other.lua']")
                prompt = self.wait_for("the new name's prompt", expected.alert_is_present())
                prompt.send_keys("moved.lua")
                prompt.accept()
                self.wait_for_text_start("files-result", "rename other.lua: E_NOT_AVAILABLE")
                self.assertIn("device 1's startup script", self.text("files-result"))
                self.wait_for("the list as it was", lambda d: d.execute_script(
                    "return [...document.querySelectorAll('#file-list tr')]"
                    ".map((row) => row.dataset.name).sort()") == ["hello.lua", "other.lua"])
                self.assertEqual(sorted(os.listdir(store)), ["hello.lua", "other.lua"])
                self.assert_no_console_errors(refused=2)

    def test_read_only_store_and_the_startup_script(self):
        with tempfile.TemporaryDirectory(prefix="wsgsim-startup-") as tmp:
            startup = os.path.join(tmp, "hello.lua")
            with open(startup, "w") as f:
                f.write("print('started at power-on')\n")
            with Wsgsim("--script", startup) as sim:
                self.open_page(sim)
                self.show_view("settings")  # Settings -> System names it
                self.wait_for_text("startup-script", startup + " (runs at power-on)")
                self.show_view("scripting")
                self.wait_for("the read-only note", lambda d: d.find_element(
                    By.ID, "store-readonly").is_displayed())
                self.wait_for("the startup script's line", lambda d: "started at power-on" in
                              d.find_element(By.ID, "console").text)
                self.assertFalse(self.driver.find_element(
                    By.CSS_SELECTOR, "#file-new button").is_enabled())
                self.click("#file-list button[aria-label='Open hello.lua']")
                self.wait_for_text("editor-file", "/user/hello.lua")
                self.assertEqual(self.editor_text(), "print('started at power-on')\n")
                self.assertIs(self.js("return document.querySelector('.CodeMirror')"
                                      ".CodeMirror.getOption('readOnly')"), True)
                self.assertFalse(self.driver.find_element(By.ID, "script-save").is_enabled())
                self.assertFalse(self.driver.find_element(
                    By.CSS_SELECTOR, "#file-list button[aria-label='Delete hello.lua']")
                    .is_enabled())
                self.click("#script-run")  # runs without saving, prints and ends
                self.wait_for_text("script-result", "run /user/hello.lua: finished")
                self.assert_no_console_errors()

    def test_settings_choose_the_startup_script(self):
        with tempfile.TemporaryDirectory(prefix="wsgsim-store-") as store:
            with open(os.path.join(store, "hello.lua"), "w") as f:
                f.write("print('hello at power-on')\nwhile true do sleep(50) end\n")
            with Wsgsim("--script-dir", store, control=True) as sim:
                self.open_page(sim)
                self.show_view("settings")
                self.wait_for("the store's files to choose from", lambda d: d.execute_script(
                    "return [...document.querySelectorAll('#startup-choice option')]"
                    ".map((o) => o.value)") == ["", "/user/hello.lua"])
                Select(self.driver.find_element(By.ID, "startup-choice")).select_by_value(
                    "/user/hello.lua")
                self.click("#startup-apply")
                self.wait_for_text("startup-script", "/user/hello.lua (runs at power-on)")
                with sim.tcp() as client:
                    client.expect("SYSFLAGS[19]?", "SYSFLAGS[19]=0")  # not at once
                with sim.control() as ctl:
                    self.assertEqual(ctl("RESET()"), "ACK RESET")
                with sim.tcp() as client:
                    wsgsim.wait_for_reply(client, "SYSFLAGS[19]?", "SYSFLAGS[19]=1",
                                          WAIT_TIMEOUT_S)
                self.assert_no_console_errors()

    def test_every_field_has_a_label(self):
        with tempfile.TemporaryDirectory(prefix="wsgsim-store-") as store:
            with Wsgsim("--script-dir", store, "--devices", "2") as sim:
                self.open_page(sim)
                self.wait_for("the settings", lambda d: d.find_elements(By.ID, "setting-pwt_mm"))
                self.wait_for("the device selector", lambda d: d.find_element(
                    By.ID, "device-select").find_elements(By.TAG_NAME, "option"))
                fields, unlabelled = self.driver.execute_script("""
                    // but those never shown (dygraphs' hidden "roller" box)
                    const fields = [...document.querySelectorAll('input, select, textarea')]
                      .filter((field) => field.type !== 'hidden' && field.style.display !== 'none');
                    const named = (field) => [...field.labels].some(
                      (label) => /[A-Za-z]/.test(label.textContent));
                    return [fields.length, fields.filter((field) => !named(field))
                      .map((field) => field.outerHTML)];""")
                self.assertGreater(fields, 35)  # every view's fields, settings included
                self.assertEqual(unlabelled, [])
                self.assert_no_console_errors()

    def test_force_axis_is_not_scaled_to_noise(self):
        with Wsgsim() as sim:
            self.open_page(sim)
            self.wait_for("a chart of more than a second", lambda d: d.execute_script(
                "return live.chart && live.chartData.length > 10 &&"
                " live.chart.xAxisRange()[1] - live.chart.xAxisRange()[0] > 1"))
            forces = self.driver.execute_script(
                "return live.chartData.map((point) => point[2])")
            self.assertLess(max(forces) - min(forces), 1.0)  # near-constant
            low, high = self.driver.execute_script("return live.chart.yAxisRange(1)")
            nominal = self.driver.execute_script("return live.forceSpanN")
            self.assertEqual(nominal, 80)  # the WSG 50-110's force_max_n from /system
            self.assertGreaterEqual(high - low, nominal)
            self.assertLessEqual(low, min(forces))
            self.assert_no_console_errors()

    def test_system_view_shows_identity_and_log(self):
        with Wsgsim(control=True) as sim, sim.tcp() as client:
            self.open_page(sim)
            self.show_view("system")
            self.wait_for_text("sys-model", client.command("DEVTYPE?").split('"')[1])
            self.wait_for_text("sys-serial", client.command("SN?").split("=")[1])
            self.wait_for_text("sys-firmware", client.command("VERSION?").split('"')[1])
            self.wait_for("the ready line in the log", lambda d: "ready: tcp" in d.find_element(
                By.ID, "system-log").text)
            with sim.control() as control:  # a power cycle: logged, uptime from 0
                self.assertEqual(control("PAUSE()"), "ACK PAUSE")
                self.assertEqual(control("RESET()"), "ACK RESET")
                self.wait_for_text_start("sys-uptime", "0:00:00 (0.000 s)")
            self.assert_no_console_errors()

    # ------------------------------------------------- the page's states

    def test_screenshots_of_the_device_states(self):
        """Fresh, homed, moving (the clock paused mid-MOVE) and holding, each
        as the live view and the motion view show it."""
        with Wsgsim("--part", "40", paused=True) as sim, sim.tcp() as client, \
                sim.control() as control:
            self.open_page(sim)
            self.wait_for_text("sim-time", "0.000")
            self.shot("fresh")
            self.home_paused(client, control)
            self.wait_for_flag("SF_REFERENCED")
            self.wait_for_text("motion-text", "none")
            self.shot("homed")
            client.expect("MOVE(80)", "ACK MOVE")
            control.step(150)
            self.wait_for_text("motion-text", "move")
            self.wait_for_flag("SF_MOVING")
            self.shot("moving")
            self.show_view("motion")
            self.shot("moving-motion-view")
            control.step_until(client, "FIN MOVE", step_ms=20)
            client.expect("GRIP(30)", "ACK GRIP")
            control.step_until(client, "FIN GRIP", step_ms=20)
            control.step(1000)
            self.wait_for_text("m-grip-state", "HOLDING (4)")
            self.shot("holding-motion-view")
            self.show_view("live")
            self.wait_for("the part held", lambda d: "held" in d.find_element(
                By.ID, "part").get_attribute("class"))
            self.shot("holding")
            self.assert_no_console_errors()

    def test_move_faster_than_the_stroke(self):
        """The speed field is not capped by the stroke (110 mm): MOVE at
        200 mm/s runs, as GCL's MOVE(40, 200) does; a speed beyond the
        model's 420 mm/s is the device's refusal, in words."""
        with Wsgsim(paused=True) as sim, sim.tcp() as client, sim.control() as control:
            self.home_paused(client, control)
            self.open_page(sim)
            self.show_view("motion")
            speed = self.driver.find_element(By.CSS_SELECTOR, "#op-move input[name=speed_mm_s]")
            self.wait_for("the speed's range", lambda d: speed.get_attribute("max") == "420")
            self.assertIn("(5–420 mm/s)", speed.find_element(By.XPATH, "..").text)
            self.fill("#op-move input[name=position_mm]", 40)
            self.fill("#op-move input[name=speed_mm_s]", 200)
            self.click("#op-move button")
            self.wait_for_text_start("op-result", "MOVE: E_SUCCESS")
            control.step(300)  # past the ramp (0.2 s at 1000 mm/s²), at full speed
            self.assertEqual(client.query_float("SPEED"), 200.0)
            self.assertEqual(control.run_until_done()[1], "done")
            self.fill("#op-move input[name=speed_mm_s]", 500)
            self.click("#op-move button")
            self.wait_for_text("op-result", "MOVE: E_RANGE_ERROR (28): the device refused: "
                               "Range error — speed 500 mm/s is outside 5–420 mm/s")
            self.assert_no_console_errors(refused=1)

    def test_paused_clock_is_shown_on_every_view(self):
        with Wsgsim(paused=True) as sim, sim.control() as control, sim.tcp() as client:
            self.open_page(sim)
            # at t = 0 the fingers have not started: said so, not "none … no data"
            self.wait_for_text_start("fingers", "Slot 0: starting")
            self.assertIn("the clock is paused", self.text("fingers"))
            self.assertNotIn("no data", self.text("fingers"))
            self.shot("paused-clock")
            for view in VIEWS:
                self.show_view(view)
                self.assertTrue(self.driver.find_element(By.ID, "clock-pill").is_displayed())
                self.assertEqual(self.driver.find_element(By.ID, "clock-text").text,
                                 "clock paused at 0.000 s")
                self.assertTrue(self.driver.find_element(By.ID, "clock-step").is_displayed())
                self.assertTrue(self.driver.find_element(By.ID, "clock-resume").is_displayed())
            self.show_view("motion")
            client.expect("FSACK()", "ACK FSACK")
            self.click("#op-home button")  # HOME waits for the clock: said so
            self.wait_for_text_start("op-done", "HOME running since 0.000 s — the clock is paused")
            self.shot("paused-clock-motion-view")
            self.click("#clock-step")  # from the motion view
            self.wait_for_text("clock-result", "clock: stepped 100 ms: the clock stands at "
                               "0.100 s")
            self.assertEqual(control.json("SIMTIME?")[0], 100)
            self.wait_for_text("clock-text", "clock paused at 0.100 s")
            self.show_view("live")
            self.wait_for_text_start("fingers", "Slot 0: fmf")
            self.click("#clock-resume")
            self.wait_for_text_start("clock-text", "clock running")
            self.assertFalse(self.driver.find_element(By.ID, "clock-pill").is_displayed())
            self.assertTrue(self.driver.find_element(By.ID, "clock-pause").is_displayed())
            self.assert_no_console_errors()

    def test_status_area_on_every_view_faults_in_alarm_style(self):
        with Wsgsim(paused=True) as sim, sim.control() as control, sim.tcp() as client:
            self.home_paused(client, control)
            self.open_page(sim)
            self.wait_for_chip("SF_REFERENCED")
            self.assertEqual(control('FAULT("POWER")'), "ACK FAULT")
            self.wait_for_chip("SF_POWER_FAULT")
            colour = "return getComputedStyle(arguments[0]).backgroundColor"
            for view in VIEWS:
                self.show_view(view)
                chips = dict(self.status_chips())
                self.assertEqual(chips["SF_FAST_STOP"], "chip fault")
                self.assertEqual(chips["SF_POWER_FAULT"], "chip fault")
                self.assertEqual(chips["SF_REFERENCED"], "chip state")
                fault, plain = (self.driver.find_element(
                    By.CSS_SELECTOR, "#status-flags li[data-name=%s]" % name)
                    for name in ("SF_POWER_FAULT", "SF_REFERENCED"))
                self.assertTrue(fault.is_displayed())
                self.assertNotEqual(self.js(colour, fault), self.js(colour, plain))
                self.assertEqual(fault.get_attribute("textContent"), "!SF_POWER_FAULT (fault)")
            # faults first; the live view's grid tells them apart as well
            self.assertEqual([name for name, _ in self.status_chips()][:2],
                             ["SF_FAST_STOP", "SF_POWER_FAULT"])
            grid = {name: self.driver.find_element(By.CSS_SELECTOR, "#flags li[data-name=%s]" %
                                                   name)
                    for name in ("SF_REFERENCED", "SF_FAST_STOP", "SF_POWER_FAULT")}
            self.assertEqual(self.js(colour, grid["SF_FAST_STOP"]),
                             self.js(colour, grid["SF_POWER_FAULT"]))
            self.assertNotEqual(self.js(colour, grid["SF_FAST_STOP"]),
                                self.js(colour, grid["SF_REFERENCED"]))
            self.assertEqual(grid["SF_POWER_FAULT"].get_attribute("textContent"),
                             "!SF_POWER_FAULT: set, a fault")
            self.assertEqual(control('CLEAR("POWER")'), "ACK CLEAR")
            client.expect("FSACK()", "ACK FSACK")
            self.wait_for("the faults to go", lambda d: "SF_FAST_STOP" not in dict(
                self.status_chips()))
            self.assert_no_console_errors()

    def test_part_around_the_jaws(self):
        """A part wider than the jaws' opening lies around them (STATE?'s
        side): drawn as a ring around the jaws, and a MOVE wider than it is
        blocked with a visible reason."""
        with Wsgsim(paused=True) as sim, sim.control() as control, sim.tcp() as client:
            self.home_paused(client, control)
            client.expect("MOVE(20)", "ACK MOVE")
            control.step_until(client, "FIN MOVE", step_ms=50)
            self.assertEqual(control("PART(50)"), "ACK PART")
            self.assertIn('"side":"outside"', control("STATE?"))
            self.open_page(sim)
            self.wait_for_text("part-text", "50.0 mm, around the jaws (blocks opening)")
            box = ("const r = document.getElementById(arguments[0]).getBoundingClientRect();"
                   "return [r.left, r.right];")
            jaw_left, jaw_right = self.js(box, "jaw-left"), self.js(box, "jaw-right")
            wall_minus, wall_plus = self.js(box, "part-wall-minus"), self.js(box, "part-wall-plus")
            self.assertLessEqual(wall_minus[1], jaw_left[0] + 0.5)  # outside the left jaw
            self.assertGreaterEqual(wall_plus[0], jaw_right[1] - 0.5)  # outside the right jaw
            self.assertFalse(self.driver.find_element(By.ID, "part-body").is_displayed())
            client.expect("MOVE(80)", "ACK MOVE")  # opens onto the ring
            control.step_until(client, "ERR MOVE 29", step_ms=50)
            self.wait_for_chip("SF_BLOCKED_PLUS")
            self.assertEqual(dict(self.status_chips())["SF_BLOCKED_PLUS"], "chip warning")
            self.shot("part-around-the-jaws")
            self.assert_no_console_errors()

    def finger_contacts(self):
        return self.js("return [...document.querySelectorAll('#scene .scene-contact')]"
                       ".filter((c) => /finger/.test(c.dataset.a + c.dataset.b)).length")

    def test_physics_scene_is_drawn_from_the_plant(self):
        """With --physics mujoco the live view draws the scene from the
        bodies' poses: the fingers close on the box, the grip's contacts
        appear. Without a scene nothing is drawn (and nothing refused)."""
        with Wsgsim("--physics", "mujoco", paused=True) as sim, sim.control() as control, \
                sim.tcp() as client:
            self.open_page(sim)
            finger_x = ("const r = document.querySelector('#scene [data-name=wsg_finger_left] rect')"
                        ".getBoundingClientRect(); return r.left;")
            self.wait_for("the scene drawn", lambda d: self.js(
                "return !document.getElementById('scene-view').hidden && "
                "document.querySelector('#scene [data-name=box]') !== null"))
            self.assertEqual(self.finger_contacts(), 0)
            open_x = self.js(finger_x)
            self.home_paused(client, control)
            client.expect("GRIP(40,40)", "ACK GRIP")
            control.step_until(client, "FIN GRIP", step_ms=50)
            self.wait_for("the grip's contacts drawn", lambda d: self.finger_contacts() >= 2)
            self.assertGreater(self.js(finger_x), open_x)  # the left finger moved in
            self.assertIn("mujoco: jaws 39.", self.text("scene-text"))
            self.shot("physics-scene")
            self.assert_no_console_errors()
        with Wsgsim(paused=True) as sim:
            self.open_page(sim)
            self.wait_for("the page to learn there is no scene",
                          lambda d: self.js("return scene.absent"))
            self.assertFalse(self.driver.find_element(By.ID, "scene-view").is_displayed())
            self.assert_no_console_errors()

    def test_tactile_map_empties_after_fast_stop(self):
        with Wsgsim("--part", "40", paused=True) as sim, sim.control() as control, \
                sim.tcp() as client:
            self.home_paused(client, control)
            client.expect("GRIP(40)", "ACK GRIP")
            control.step_until(client, "FIN GRIP", step_ms=20)
            control.step(500)
            self.open_page(sim)
            dsa = "#fingers .finger:nth-child(2) .fdata"
            self.wait_for("the squeezed map", lambda d: "peak" in d.find_element(
                By.CSS_SELECTOR, dsa).text)
            client.expect("FASTSTOP()", "ACK FASTSTOP")
            control.step(200)
            cells = client.command("FDATA[1]?").split("=", 1)[1].strip("[]").split(",")
            self.assertEqual(max(int(cell) for cell in cells), 0)  # GCL reads it empty
            self.wait_for("the empty map", lambda d: d.find_element(
                By.CSS_SELECTOR, dsa).text == "14 × 6 tactile map, no contact (all cells 0)")
            self.wait_for_text_start("faststop-cause", "the drive is off")
            self.shot("fast-stop")
            self.assert_no_console_errors()

    def test_settings_errors_in_user_terms(self):
        with Wsgsim() as sim:
            self.open_page(sim)
            self.show_view("settings")
            self.wait_for_text("setting-range-force_n", "5–80 N")
            ranges = self.js("return Object.fromEntries([...document.querySelectorAll("
                             "'.setting input[type=number]')].map((input) => [input.name, "
                             "input.parentElement.querySelector('.range').textContent]))")
            self.assertEqual(ranges, {"pwt_mm": "0–110 mm", "clt_mm": "0–110 mm",
                                      "pullback_mm": "0–110 mm", "force_n": "5–80 N",
                                      "speed_mm_s": "5–420 mm/s", "accel_mm_s2":
                                      "100–5000 mm/s²", "soft_limit_minus_mm": "0–110 mm",
                                      "soft_limit_plus_mm": "0–110 mm"})
            self.fill("#setting-force_n", 500)
            self.click("#settings-apply")
            self.wait_for_text("setting-error-force_n", "grip force 500 N is out of range: "
                               "5–80 N; the device keeps 40 N")
            self.assertEqual(self.text("settings-result"), "not applied: grip force 500 N is "
                             "out of range: 5–80 N. Nothing was changed (E_RANGE_ERROR).")
            self.assertNotIn("force_n", self.text("settings-result"))
            field = self.driver.find_element(By.ID, "setting-force_n")
            self.assertEqual(field.get_attribute("value"), "40")  # the value in force again
            self.assertEqual(request(sim.url("/api/devices/0/settings")).json()["force_n"], 40)
            self.shot("settings-error")
            self.assert_no_console_errors(refused=1)

    def test_script_editor_marks_the_error_line(self):
        with tempfile.TemporaryDirectory(prefix="wsgsim-store-") as store:
            with open(os.path.join(store, "bad.lua"), "w") as f:
                f.write("-- a script with a mistake\nlocal x = 1\nx = = 2\nprint(x)\n")
            with Wsgsim("--script-dir", store) as sim:
                self.open_page(sim)
                self.show_view("scripting")
                self.wait_for("bad.lua listed", lambda d: d.find_elements(
                    By.CSS_SELECTOR, "#file-list tr[data-name='bad.lua']"))
                self.click("#file-list button[aria-label='Open bad.lua']")
                self.wait_for_text("editor-file", "/user/bad.lua")
                # numbered and highlighted lines (CodeMirror's Lua mode)
                numbers = self.js("return [...document.querySelectorAll("
                                  "'.CodeMirror-linenumber')].map((n) => n.textContent)"
                                  ".filter((n) => n !== '')")
                self.assertEqual(numbers[:4], ["1", "2", "3", "4"])
                self.assertTrue(self.driver.find_elements(By.CSS_SELECTOR, ".cm-keyword"))
                self.assertTrue(self.driver.find_elements(By.CSS_SELECTOR, ".cm-comment"))
                self.click("#script-run")
                self.wait_for_text_start("script-error-text", "error: bad.lua:3:")
                self.wait_for("the line marked", lambda d: self.js(
                    "return [...document.querySelectorAll('.CodeMirror-code > div')].findIndex("
                    "(line) => line.querySelector('.error-line'))") == 2)
                self.assertEqual(len(self.driver.find_elements(By.CSS_SELECTOR,
                                                               ".error-marker")), 1)
                # the green "started" gave way to the error
                self.wait_for_text("script-result", "run /user/bad.lua: stopped with an error "
                                   "at line 3 (SF_SCRIPT_FAILURE)")
                self.assertIn("error", self.driver.find_element(
                    By.ID, "script-result").get_attribute("class"))
                self.assertEqual(self.driver.find_element(By.ID, "script-error-line").text,
                                 "Show line 3")
                self.shot("script-error")
                self.set_editor("-- fixed\nlocal x = 1\nx = 2\nprint(x)\n")
                self.assertFalse(self.driver.find_elements(By.CSS_SELECTOR, ".error-marker"))
                self.click("#script-run")
                self.wait_for_text("script-result", "run /user/bad.lua: finished")
                self.assertEqual(self.text("script-error-text"), "")
                self.assert_no_console_errors()

    def assert_fits(self, view):
        """Nothing wider than the window, no flag name cut, the jaws'
        label clear of the jaws."""
        wide = self.js("""
            const width = document.documentElement.clientWidth;
            return [document.documentElement.scrollWidth - width,
                    [...document.querySelectorAll('body *')].filter((e) => {
                      const r = e.getBoundingClientRect();
                      return r.width > 0 && r.right > width + 0.5 && !e.closest('.CodeMirror');
                    }).map((e) => e.tagName + '#' + e.id + '.' + e.className).slice(0, 5)]""")
        self.assertEqual(wide, [0, []], view)
        cut = self.js("return [...document.querySelectorAll('#flags li, #status-flags li')]"
                      ".filter((e) => e.scrollWidth > e.clientWidth + 1).map((e) => e.textContent)")
        self.assertEqual(cut, [], view)

    def test_narrow_window_and_the_server_gone(self):
        self.driver.set_window_size(*NARROW)
        try:
            self.narrow_window_and_the_server_gone()
        finally:
            self.driver.set_window_size(*(int(n) for n in WINDOW.split(",")))

    def narrow_window_and_the_server_gone(self):
        with tempfile.TemporaryDirectory(prefix="wsgsim-store-") as store, \
                Wsgsim("--script-dir", store, paused=True) as sim, \
                sim.control() as control, sim.tcp() as client:
            self.home_paused(client, control)
            client.expect("MOVE(8)", "ACK MOVE")  # the jaws closer than their label is wide
            control.step_until(client, "FIN MOVE", step_ms=50)
            self.open_page(sim)
            self.wait_for_text("width", "8.0")
            overlap = self.js("""
                const box = (id) => document.getElementById(id).getBoundingClientRect();
                const text = box('span-text');
                return ['jaw-left', 'jaw-right', 'part'].filter((id) => {
                  const r = box(id);
                  return r.width > 0 && text.right > r.left && text.left < r.right &&
                         text.bottom > r.top && text.top < r.bottom;
                });""")
            self.assertEqual(overlap, [])
            # the chart's legend outside its drawing
            self.wait_for("the chart", lambda d: d.find_elements(By.CSS_SELECTOR, "#chart canvas"))
            self.wait_for("the legend", lambda d: "width (mm)" in self.text("chart-legend"))
            legend = self.js("""
                const legend = document.getElementById('chart-legend').getBoundingClientRect();
                const chart = document.querySelector('#chart canvas').getBoundingClientRect();
                return [legend.bottom <= chart.top + 0.5,
                        document.querySelectorAll('#chart .dygraph-legend').length];""")
            self.assertEqual(legend, [True, 0])  # above the drawing, none inside it
            for view in ("live", "motion", "settings", "scripting", "system"):
                self.show_view(view)
                if view == "settings":
                    self.wait_for("the settings", lambda d: d.find_elements(
                        By.ID, "setting-pwt_mm"))
                self.assert_fits(view)
                self.shot("narrow-420-" + view)
            self.show_view("live")
            sim.stop()  # the server gone
            self.wait_for("the offline banner", lambda d: d.find_element(
                By.ID, "offline-banner").is_displayed())
            self.assertIn("the values shown are from simulated time", self.text("offline-text"))
            grey = self.js("return getComputedStyle(document.querySelector('#readouts dd'))"
                           ".opacity")
            self.assertLess(float(grey), 1.0)
            self.assertIn("stale", self.js("return document.body.className"))
            self.shot("server-gone")


def main():
    suite = unittest.defaultTestLoader.loadTestsFromTestCase(PageTest)
    result = unittest.TextTestRunner(verbosity=2, stream=sys.stdout).run(suite)
    failed = len(result.failures) + len(result.errors) + len(result.unexpectedSuccesses)
    skipped = len(result.skipped)
    if skipped:  # a test that cannot run here must fail and say why, never skip
        print("browser: %d tests were skipped; skipping is not allowed" % skipped)
        failed += skipped
    print("browser: %d passed, %d failed" % (result.testsRun - failed, failed))
    return 0 if failed == 0 and result.testsRun else 1


if __name__ == "__main__":
    sys.exit(main())
