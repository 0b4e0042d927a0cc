// SPDX-License-Identifier: BSD-3-Clause
// The wsgsim device page: views as on the device's own web interface
// (live view, motion control, settings, scripting, system), chosen by the
// address's hash (#live, ...), on the event stream and the JSON API
// (docs/web.md).
"use strict";

const CHART_SECONDS = 30;
const RECONNECT_MIN_MS = 500;
const RECONNECT_MAX_MS = 5000;
const SVG_MARGIN_MM = 10; // room left and right of the stroke in the drawing
const JAW_WIDTH_MM = 6;
const DSA_CELL_MAX = 4095; // 12-bit tactile cells: the heat map's full scale
const FMF_BAR_FULL_SCALE_N = 80; // the WSG 50's grip force limit; the bar rescales past it
// The force axis spans at least the model's nominal force range (GET
// /system's force_max_n; this until it came), so a near-constant force and
// its sensor noise are not blown up to the chart's full height.
const FORCE_AXIS_MIN_SPAN_N = 80;
// The thickness of a part that lies around the jaws (a ring), as drawn.
const RING_WALL_MM = 4;
// How a set system flag shows, after Appendix B's own words: an error
// condition ("Error", "Fault", "stopped due to an error condition") in the
// alarm style, a warning or a blocked axis in amber, the rest as plain state.
const FAULT_FLAGS = ["SF_FAST_STOP", "SF_TEMP_FAULT", "SF_POWER_FAULT", "SF_CURR_FAULT",
  "SF_FINGER_FAULT", "SF_CMD_FAILURE", "SF_SCRIPT_FAILURE"];
const WARNING_FLAGS = ["SF_TEMP_WARNING", "SF_BLOCKED_MINUS", "SF_BLOCKED_PLUS",
  "SF_SOFT_LIMIT_MINUS", "SF_SOFT_LIMIT_PLUS", "SF_AXIS_STOPPED"];
const CONSOLE_POLL_MS = 500; // the scripting view's console, while shown
const SYSTEM_POLL_MS = 1000; // the system view's uptime and log, while shown
const LOG_LINES_SHOWN = 100;
const CONSOLE_LINES_SHOWN = 1000;
const VIEWS = ["live", "motion", "settings", "scripting", "system"];

const deviceId = deviceIdFromPath(location.pathname);
const apiBase = "/api/devices/" + deviceId;
const $ = (id) => document.getElementById(id);

// ---------------------------------------------------------------- the API

class ApiError extends Error {
  constructor(httpStatus, body) {
    super(body.message || body.error || "HTTP " + httpStatus);
    this.httpStatus = httpStatus;
    this.statusName = body.error || "HTTP " + httpStatus; // the Appendix A name
    this.code = body.code;
  }
  describe() {
    const code = this.code === undefined ? "" : " (" + this.code + ")";
    return this.statusName + code + (this.message !== this.statusName ? ": " + this.message : "");
  }
}

function deviceIdFromPath(path) {
  const match = /\/devices\/(\d+)/.exec(path);
  return match ? Number(match[1]) : 0;
}

async function api(method, path, body) {
  const options = { method: method, headers: {} };
  if (method !== "GET") {
    // the server takes changing requests as JSON only (no cross-site forms)
    options.headers["Content-Type"] = "application/json";
    options.body = JSON.stringify(body === undefined ? {} : body);
  }
  let response;
  let text;
  try {
    response = await fetch(path, options);
    text = await response.text();
  } catch (error) {
    // no answer (wsgsim stopped, the network): shown like a refusal
    throw new ApiError(0, { error: "no answer from wsgsim", message: error.message });
  }
  let json = {};
  try {
    json = text ? JSON.parse(text) : {};
  } catch (e) {
    json = { message: text };
  }
  if (!response.ok) {
    throw new ApiError(response.status, json);
  }
  return json;
}

// The reply of an API call, or null after a refusal, which goes to
// onRefusal(error); any other exception is a bug in the page and propagates.
async function callApi(onRefusal, method, path, body) {
  try {
    return await api(method, path, body);
  } catch (error) {
    if (!(error instanceof ApiError)) {
      throw error;
    }
    onRefusal(error);
    return null;
  }
}

function showResult(element, ok, text) {
  element.textContent = text;
  element.classList.toggle("error", !ok);
  element.classList.toggle("ok", ok);
}

// ------------------------------------------------------------ form values

// The form's number fields as {name: number}, empty ones left out (the
// device's defaults apply), text and select fields as strings.
function formArguments(form) {
  const args = {};
  for (const field of form.elements) {
    if (!field.name || field.value === "" || field.type === "range") {
      continue;
    }
    args[field.name] = field.type === "number" ? Number(field.value) : field.value;
  }
  return args;
}

// ----------------------------------------------------------- the live view

const live = {
  flagItems: [],
  fingerViews: [],
  chartData: [],
  chart: null,
  chartDrawPending: false,
  lastConnections: "",
  moveTouched: false,
  stroke: 0,
  forceSpanN: FORCE_AXIS_MIN_SPAN_N,
  lastState: null, // the newest state (what a stale page still shows)
  statusFlags: "", // the set flags the status area shows
  paused: false, // the simulated clock is paused
  simAllowed: true, // this client may use the simulation (sim_allowed)
  step: null, // a STEP under way: {toMs, ms, result}
};

// A flag's name with a line break allowed after each "_" (<wbr>: the text
// stays the name), so that a narrow column wraps it between its words.
function setFlagName(element, name) {
  const parts = name.split("_");
  element.replaceChildren();
  parts.forEach((part, i) => {
    element.append(part + (i < parts.length - 1 ? "_" : ""));
    if (i < parts.length - 1) {
      element.appendChild(document.createElement("wbr"));
    }
  });
}

function flagKind(name) {
  return FAULT_FLAGS.includes(name) ? "fault" : WARNING_FLAGS.includes(name) ? "warning" : "state";
}

function fixed(value, digits) {
  return typeof value === "number" ? value.toFixed(digits) : "–";
}

function setText(id, text) {
  const element = $(id);
  if (element.textContent !== text) {
    element.textContent = text;
    return true;
  }
  return false;
}

function renderReadouts(state) {
  // the moment the shown width changed (the browser test reports the latency)
  if (setText("width", fixed(state.position_mm, 1))) {
    $("width").dataset.shownAt = String(Date.now());
  }
  setText("speed", fixed(state.speed_mm_s, 1));
  setText("force", fixed(state.force_n, 1));
  const grip = state.grip_state || {};
  setText("grip-state", grip.name ? grip.name + " (" + grip.code + ")" : "–");
  setText("motion-text", state.motion || "–");
  setText("temperature", fixed(state.temperature_c, 1));
  setText("sim-time", fixed(state.time_ms / 1000, 3));
  setText("part-text", partText(state.part));
  // the motion view's line
  setText("m-width", fixed(state.position_mm, 1));
  setText("m-force", fixed(state.force_n, 1));
  setText("m-grip-state", $("grip-state").textContent);
  setText("m-motion", state.motion || "–");
}

// "40.0 mm between the jaws" or "around the jaws": an outside part (a
// ring) blocks opening, so it says why a wider MOVE stops.
function partText(part) {
  if (!part || !part.present) {
    return "none";
  }
  const where = part.side === "outside" ? "around the jaws (blocks opening)" : "between the jaws";
  return fixed(part.width_mm, 1) + " mm, " + where;
}

// The stroke bounds the jaws' drawing and the widths (data-range="stroke"):
// the target, a part width, the pull-back; never a speed or a force.
function setJawSpan(stroke) {
  if (stroke === live.stroke || !(stroke > 0)) {
    return;
  }
  live.stroke = stroke;
  const width = stroke + 2 * (SVG_MARGIN_MM + JAW_WIDTH_MM);
  $("jaws").setAttribute("viewBox", "0 0 " + width + " 58");
  $("jaw-base").setAttribute("width", String(width - 10));
  $("op-move").elements.position_slider.max = String(stroke);
  limits.stroke = [0, stroke];
  showRanges();
}

// x of the inner face of a jaw at offset mm from the middle
function jawX(offsetMm) {
  return SVG_MARGIN_MM + JAW_WIDTH_MM + live.stroke / 2 + offsetMm;
}

function placeBox(element, widthMm) {
  element.setAttribute("x", String(jawX(-widthMm / 2)));
  element.setAttribute("width", String(Math.max(widthMm, 0)));
}

function placeSpan(element, fromX, toX) {
  element.setAttribute("x", String(fromX));
  element.setAttribute("width", String(Math.max(toX - fromX, 0)));
}

// Between the jaws a part is a block, squeezed to the jaws' width when held;
// around them (outside) a ring whose walls stand outside the jaws and whose
// band runs behind them, stretched to the jaws' width when held.
function renderPart(part, positionMm, held) {
  $("part").toggleAttribute("hidden", !part.present);
  if (!part.present) {
    return;
  }
  const outside = part.side === "outside";
  $("part").classList.toggle("held", held);
  $("part").classList.toggle("outside", outside);
  for (const id of ["part-ring", "part-wall-minus", "part-wall-plus"]) {
    $(id).toggleAttribute("hidden", !outside);
  }
  $("part-body").toggleAttribute("hidden", outside);
  if (!outside) {
    placeBox($("part-body"), Math.min(part.width_mm, positionMm));
    return;
  }
  const inner = Math.max(part.width_mm, positionMm) / 2 + JAW_WIDTH_MM;
  placeSpan($("part-wall-minus"), jawX(-inner) - RING_WALL_MM, jawX(-inner));
  placeSpan($("part-wall-plus"), jawX(inner), jawX(inner) + RING_WALL_MM);
  placeSpan($("part-ring"), jawX(-inner), jawX(inner));
}

// An obstacle is a line where it stops the jaws: at their inner faces
// between them, at their outer faces around them.
function renderObstacle(obstacle) {
  for (const side of ["minus", "plus"]) {
    const line = $("obstacle-" + side);
    line.toggleAttribute("hidden", !obstacle.present);
    if (obstacle.present) {
      const reach = obstacle.width_mm / 2 + (obstacle.side === "outside" ? JAW_WIDTH_MM : 0);
      const x = jawX((side === "minus" ? -1 : 1) * reach);
      line.setAttribute("x1", String(x));
      line.setAttribute("x2", String(x));
    }
  }
}

function renderJaws(state) {
  setJawSpan(state.stroke_mm);
  const half = Math.max(state.position_mm || 0, 0) / 2;
  $("jaw-left").setAttribute("x", String(jawX(-half) - JAW_WIDTH_MM));
  $("jaw-right").setAttribute("x", String(jawX(half)));
  $("span-line").setAttribute("x1", String(jawX(-half)));
  $("span-line").setAttribute("x2", String(jawX(half)));
  $("span-text").setAttribute("x", String(jawX(0)));
  $("span-text").textContent = fixed(state.position_mm, 1) + " mm";
  const held = (state.grip_state || {}).code === 4;
  renderPart(state.part || {}, Math.max(state.position_mm || 0, 0), held);
  renderObstacle(state.obstacle || {});
}

function renderFlags(sysflags) {
  if (!sysflags) {
    return;
  }
  const list = $("flags");
  if (live.flagItems.length === 0 && sysflags.names) {
    sysflags.names.forEach((name, bit) => {
      const item = document.createElement("li");
      item.innerHTML = '<span class="mark" aria-hidden="true"></span><span class="name"></span>' +
        '<span class="sr-only"></span>';
      item.dataset.name = name || "bit " + bit;
      setFlagName(item.querySelector(".name"), item.dataset.name);
      item.title = "bit " + bit;
      item.classList.toggle("reserved", !name);
      item.classList.add(flagKind(name));
      list.appendChild(item);
      live.flagItems.push(item);
    });
  }
  // set or clear in words and a mark, not only by colour; a set fault's
  // mark is the alarm's "!"
  live.flagItems.forEach((item, bit) => {
    const set = ((sysflags.value >>> bit) & 1) === 1;
    if (item.classList.contains("set") !== set || !item.dataset.shown) {
      item.dataset.shown = "1";
      item.classList.toggle("set", set);
      const fault = item.classList.contains("fault");
      item.querySelector(".mark").textContent = set ? (fault ? "!" : "✔") : "○";
      item.querySelector(".sr-only").textContent = set ? (fault ? ": set, a fault" : ": set")
        : ": clear";
    }
  });
  renderStatusFlags(sysflags.set || [], (sysflags.value & 1) === 1);
  renderFastStop(sysflags.set || []);
  renderScriptFlags(sysflags.set || []);
}

// ------------------------------------------------------------ status area

// The status area under the tabs, on every view as on the device's own web
// interface: the grip state, width and force, the clock, and the set flags
// (faults first, in the alarm style), with a hint while not homed.
function renderStatus(state) {
  const grip = state.grip_state || {};
  setText("st-grip", grip.name ? grip.name + " (" + grip.code + ")" : "–");
  setText("st-width", fixed(state.position_mm, 1));
  setText("st-force", fixed(state.force_n, 1));
  renderClock(state.clock, state.time_ms);
}

const KIND_ORDER = { fault: 0, warning: 1, state: 2 };

function renderStatusFlags(setFlags, referenced) {
  const key = setFlags.join(",") + (referenced ? "" : ",not homed");
  if (key === live.statusFlags) {
    return;
  }
  live.statusFlags = key;
  const sorted = setFlags.slice().sort((a, b) => KIND_ORDER[flagKind(a)] - KIND_ORDER[flagKind(b)]);
  const items = sorted.map((name) => {
    const item = document.createElement("li");
    const kind = flagKind(name);
    item.className = "chip " + kind;
    item.dataset.name = name;
    item.innerHTML = '<span class="icon" aria-hidden="true"></span><span class="name"></span>';
    item.querySelector(".icon").textContent = kind === "fault" ? "!" : kind === "warning" ? "▲" : "✔";
    setFlagName(item.querySelector(".name"), name);
    if (kind !== "state") {
      item.querySelector(".name").append(" (" + kind + ")");
    }
    return item;
  });
  if (!referenced) {
    const hint = document.createElement("li");
    hint.className = "chip hint";
    hint.dataset.name = "not homed";
    hint.textContent = "not homed: HOME before moving";
    items.push(hint);
  }
  if (items.length === 0) {
    const none = document.createElement("li");
    none.className = "chip none";
    none.textContent = "no system flag set";
    items.push(none);
  }
  $("status-flags").replaceChildren(...items);
}

// The simulated clock: running (and its scale) or paused at its time, with
// Step and Resume at hand on every view (Pause while it runs).
function renderClock(clock, timeMs) {
  const paused = Boolean(clock && clock.paused);
  live.paused = paused;
  let text = "clock –";
  if (clock) {
    text = paused ? "clock paused at " + fixed(timeMs / 1000, 3) + " s"
      : "clock running" + (clock.scale !== 1 ? " at ×" + clock.scale : "");
  }
  setText("clock-text", text);
  $("st-clock").classList.toggle("paused", paused);
  $("clock-pill").hidden = !paused;
  $("clock-step").hidden = !paused;
  $("clock-resume").hidden = !paused;
  $("clock-pause").hidden = paused || !clock;
  followStep(timeMs);
}

// A STEP answers at once (202) and runs on: its result says where the clock
// stands once the state shows it there.
function followStep(timeMs) {
  const step = live.step;
  if (step && timeMs >= step.toMs - 0.0005) {
    live.step = null;
    showResult(step.result, true, "clock: stepped " + step.ms + " ms: the clock stands at " +
      fixed(timeMs / 1000, 3) + " s");
  }
}

// --------------------------------------------------------- FAST STOP banner

// The severe faults that raise FAST STOP by themselves (docs/behaviour.md):
// FSACK is refused while one persists, so the banner names them.
const FAST_STOP_CAUSES = ["SF_TEMP_FAULT", "SF_POWER_FAULT", "SF_CURR_FAULT"];

function renderFastStop(setFlags) {
  const on = setFlags.includes("SF_FAST_STOP");
  if (!on) {
    $("banner-result").textContent = ""; // a refused FSACK's message is old news
  }
  $("faststop-banner").hidden = !on;
  const causes = setFlags.filter((name) => FAST_STOP_CAUSES.includes(name));
  setText("faststop-cause", causes.length
    ? "while " + causes.join(", ") + " persists FSACK is refused"
    : "the drive is off: motion is refused until FSACK");
}

async function bannerFsack() {
  const result = $("banner-result");
  const refused = (error) => showResult(result, false, "FSACK: " + error.describe());
  if (await callApi(refused, "POST", apiBase + "/ops/fsack")) {
    showResult(result, true, "FSACK: E_SUCCESS");
  }
}

// ------------------------------------------------------------------ fingers

function heatColour(fraction) {
  const f = Math.min(Math.max(fraction, 0), 1);
  // dark blue (no pressure) through cyan and green to yellow (full scale)
  const hue = 240 - 180 * f;
  const light = 20 + 45 * f;
  return "hsl(" + hue + ",90%," + light + "%)";
}

function drawTactileMap(canvas, finger) {
  const rows = finger.rows || 14;
  const cols = finger.cols || 6;
  const cell = 8;
  canvas.width = cols * cell;
  canvas.height = rows * cell;
  const context = canvas.getContext("2d");
  const cells = finger.data;
  for (let row = 0; row < rows; row++) {
    for (let col = 0; col < cols; col++) {
      // square root: a light touch still shows on the 12-bit scale
      context.fillStyle = heatColour(Math.sqrt(cells[row * cols + col] / DSA_CELL_MAX));
      context.fillRect(col * cell, row * cell, cell - 1, cell - 1);
    }
  }
}

function fingerView(slot) {
  if (!live.fingerViews[slot]) {
    const box = document.createElement("div");
    box.className = "finger";
    box.innerHTML =
      '<h4></h4><p class="fflags"></p><p class="fdata"></p>' +
      '<div class="bar" hidden><div></div></div><canvas hidden></canvas>';
    $("fingers").appendChild(box);
    live.fingerViews[slot] = box;
  }
  return live.fingerViews[slot];
}

// A powered slot whose finger has not described itself yet (no
// FF_CONFIG_AVAIL, no fault): the finger bus still starts it, on the
// simulated clock (at t = 0 on a paused clock, until a step).
function fingerStarting(finger) {
  const set = (finger.flags || {}).set || [];
  return finger.type === "none" && set.includes("FF_POWER_ON") &&
    !set.includes("FF_CONFIG_AVAIL") && !set.some((name) => /FAULT/.test(name));
}

function renderFinger(finger) {
  const box = fingerView(finger.slot);
  const starting = fingerStarting(finger);
  box.querySelector("h4").textContent = "Slot " + finger.slot + ": " +
    (starting ? "starting" : finger.type);
  const flags = finger.flags || {};
  const set = flags.set && flags.set.length ? flags.set.join(", ") : "no flags set";
  box.querySelector(".fflags").textContent =
    "flags 0x" + Number(flags.value || 0).toString(16) + ": " + set;
  const bar = box.querySelector(".bar");
  const canvas = box.querySelector("canvas");
  const isForce = typeof finger.data === "number";
  const isMap = Array.isArray(finger.data);
  bar.hidden = !isForce;
  canvas.hidden = !isMap;
  let text = "no data";
  if (starting) {
    text = "powered, waiting for the finger to describe itself" +
      (live.paused ? " (the clock is paused: Step or Resume runs the finger bus)" : "");
  } else if (isForce) {
    text = "force " + finger.data.toFixed(2) + " N";
    const fullScale = Math.max(FMF_BAR_FULL_SCALE_N, Math.abs(finger.data));
    bar.firstChild.style.width = (100 * Math.abs(finger.data)) / fullScale + "%";
  } else if (isMap) {
    const peak = Math.max(...finger.data);
    text = (finger.rows || 14) + " × " + (finger.cols || 6) + " tactile map, " +
      (peak > 0 ? "peak " + peak + " of " + DSA_CELL_MAX : "no contact (all cells 0)");
    drawTactileMap(canvas, finger);
  }
  box.querySelector(".fdata").textContent = text;
}

function renderFingers(fingers) {
  (fingers || []).forEach(renderFinger);
}

// -------------------------------------------------------------- connections

function renderConnections(connections) {
  const json = JSON.stringify(connections || []);
  if (json === live.lastConnections) {
    return; // unchanged: keep the text selectable
  }
  live.lastConnections = json;
  const container = $("connections");
  container.replaceChildren();
  if (!connections || connections.length === 0) {
    const empty = document.createElement("p");
    empty.className = "empty";
    empty.textContent = "none";
    container.appendChild(empty);
    return;
  }
  for (const connection of connections) {
    const box = document.createElement("div");
    box.className = "connection";
    const title = document.createElement("h4");
    title.textContent =
      "#" + connection.id + " " + (connection.peer || "–") + " · " +
      connection.protocol.toUpperCase() + " over " + connection.transport.toUpperCase();
    const lines = document.createElement("pre");
    lines.textContent = (connection.last_lines || []).join("\n");
    box.append(title, lines);
    container.appendChild(box);
  }
}

// -------------------------------------------------------------------- chart

function addChartPoint(state) {
  const seconds = state.time_ms / 1000;
  const data = live.chartData;
  if (data.length && seconds < data[data.length - 1][0]) {
    data.length = 0; // the simulated clock started again
  }
  if (data.length && seconds === data[data.length - 1][0]) {
    data[data.length - 1] = [seconds, state.position_mm, state.force_n];
  } else {
    data.push([seconds, state.position_mm, state.force_n]);
  }
  while (data.length && data[0][0] < seconds - CHART_SECONDS) {
    data.shift();
  }
}

// The chart follows every event (25 Hz), at most once per frame of the
// browser, and not at all while the page is hidden.
function scheduleChart() {
  if (!live.chartDrawPending && views.current === "live") {
    live.chartDrawPending = true;
    requestAnimationFrame(drawChart);
  }
}

// [low, high] of the force axis: the data's range grown to at least the
// minimum span, from 0 or from below 0 (a tared or pushed finger).
function forceAxisRange(data) {
  let low = 0;
  let high = 0;
  for (const point of data) {
    if (typeof point[2] === "number") {
      low = Math.min(low, point[2]);
      high = Math.max(high, point[2]);
    }
  }
  const span = Math.max(high - low, live.forceSpanN);
  return [low, low + span * 1.05]; // a little room above the highest point
}

function widthAxisRange() {
  return [0, (live.stroke > 0 ? live.stroke : 110) * 1.05];
}

function drawChart() {
  live.chartDrawPending = false;
  // one instant is no line: said, rather than an empty chart
  const history = live.chartData.length >= 2;
  $("chart-note").hidden = history || live.chartData.length === 0;
  setText("chart-note", "The chart fills as the simulated clock runs" +
    (live.paused ? " (it is paused: Step or Resume)." : "."));
  if (live.chartData.length === 0) {
    return; // no state yet
  }
  const axes = {
    y: { valueRange: widthAxisRange() },
    y2: { independentTicks: true, valueRange: forceAxisRange(live.chartData) },
  };
  if (!live.chart) {
    live.chart = new Dygraph($("chart"), live.chartData, {
      labels: ["time (s)", "width (mm)", "force (N)"],
      series: { "force (N)": { axis: "y2" } },
      axes: axes,
      ylabel: "width (mm)",
      y2label: "force (N)",
      xlabel: "simulated time (s)",
      colors: ["#1f6fb2", "#c0392b"],
      legend: "always",
      // the legend above the chart, never over its data
      labelsDiv: $("chart-legend"),
      labelsSeparateLines: false,
      animatedZooms: false,
    });
  } else {
    live.chart.updateOptions({ file: live.chartData, axes: axes });
  }
}

// ------------------------------------------------------------- the stream

function renderState(state) {
  live.lastState = state;
  showOffline(false);
  renderStatus(state);
  renderReadouts(state);
  renderJaws(state);
  followWidth(state.position_mm);
  renderFlags(state.sysflags);
  renderFingers(state.fingers);
  renderConnections(state.connections);
  renderWebOp(state.web_op);
  addChartPoint(state);
  scheduleChart();
  document.dispatchEvent(new CustomEvent("wsgsim-state", { detail: state })); // scene.js
}

function setLink(up, text) {
  const link = $("link");
  link.textContent = text;
  link.classList.toggle("up", up);
  link.classList.toggle("down", !up);
}

function clockTime(date) {
  const two = (n) => String(n).padStart(2, "0");
  return two(date.getHours()) + ":" + two(date.getMinutes()) + ":" + two(date.getSeconds());
}

// The server gone: a banner says so and since when, and every value shown
// turns grey (stale) until the stream brings a state again.
function showOffline(offline) {
  if (!offline) {
    if (document.body.classList.contains("stale")) {
      document.body.classList.remove("stale");
      $("offline-banner").hidden = true;
      $("banner-fsack").disabled = false;
      simAvailable(live.simAllowed);
    }
    return;
  }
  if (document.body.classList.contains("stale")) {
    return; // still gone: the banner keeps the first moment
  }
  document.body.classList.add("stale");
  // nothing to send them to: the buttons that act wait for the server
  for (const id of ["banner-fsack", "clock-step", "clock-resume", "clock-pause"]) {
    $(id).disabled = true;
  }
  const shown = live.lastState ? "the values shown are from simulated time " +
    fixed(live.lastState.time_ms / 1000, 3) + " s and no longer change" : "nothing was shown yet";
  setText("offline-text", "since " + clockTime(new Date()) + ": " + shown +
    ". The page reconnects by itself when wsgsim is back.");
  $("offline-banner").hidden = false;
}

// EventSource retries on its own after a dropped stream, but not after an
// HTTP error (e.g. the server restarting): one reconnect loop for both.
function openStream(delayMs) {
  const source = new EventSource(apiBase + "/events");
  source.addEventListener("open", () => setLink(true, "live"));
  source.addEventListener("state", (event) => {
    delayMs = RECONNECT_MIN_MS;
    renderState(JSON.parse(event.data));
  });
  source.addEventListener("error", () => {
    source.close();
    setLink(false, "reconnecting");
    showOffline(true);
    setTimeout(() => openStream(Math.min(delayMs * 2, RECONNECT_MAX_MS)), delayMs);
  });
}

// ------------------------------------------------------------ control panel

// How the page's last long operation (HOME, MOVE, GRIP, RELEASE) ended: a
// started op answers 202 at once; its outcome comes with the state.
function renderWebOp(op) {
  if (!op) {
    return;
  }
  const name = commandName(op.op);
  const element = $("op-done");
  if (!op.done) {
    // on a paused clock nothing moves until a step: said, not left to guess
    const waiting = live.paused ? " — the clock is paused: Step or Resume (above) runs it" : "";
    showResult(element, true, name + " running since " + fixed(op.started_ms / 1000, 3) + " s" +
      waiting);
    return;
  }
  const ended = " at " + fixed(op.ended_ms / 1000, 3) + " s";
  showResult(element, op.code === 0, name + " finished: " + op.status + " (" + op.code + ")" + ended);
}

// The command's name as the manual writes it (the route says fast_stop).
function commandName(op) {
  return op.replace("_", "").toUpperCase();
}

// ----------------------------------------------------------------- ranges

// The model's ranges (GET …/system; the stroke also from the state): each
// number field with data-range shows its range, and a refusal for a value
// outside it says which value and what is allowed, in the page's words.
const limits = { stroke: null, speed: null, force: null, accel: null };
const RANGE_UNITS = { stroke: "mm", speed: "mm/s", force: "N", accel: "mm/s²" };

function rangeText(kind) {
  const range = limits[kind];
  return range ? trimmed(range[0]) + "–" + trimmed(range[1]) + " " + RANGE_UNITS[kind] : "";
}

function trimmed(value) {
  return String(Math.round(value * 1000) / 1000);
}

function setLimits(info) {
  limits.speed = [info.speed_min_mm_s, info.speed_max_mm_s];
  limits.forceNominal = [info.force_min_n, info.force_max_n];
  limits.accel = [info.accel_min_mm_s2, info.accel_max_mm_s2];
  limits.overdriveN = info.force_overdrive_n;
  updateForceLimit();
  if (!limits.stroke && info.stroke_mm > 0) {
    limits.stroke = [0, info.stroke_mm];
  }
  showRanges();
}

// min and max on each field (the spinner's bounds: the forms do not
// validate, the device does) and the range beside it.
function showRanges() {
  for (const input of document.querySelectorAll("input[data-range]")) {
    const range = limits[input.dataset.range];
    if (!range) {
      continue;
    }
    input.min = String(range[0]);
    input.max = String(range[1]);
    let hint = input.parentElement.querySelector(".range");
    if (!hint) {
      hint = document.createElement("span");
      hint.className = "range";
      input.parentElement.appendChild(hint);
    }
    hint.textContent = "(" + rangeText(input.dataset.range) + ")";
  }
  if (settings.built) {
    showSettingsRanges();
  }
}

// The first value of a form outside its range: "speed 500 mm/s is outside
// 5–420 mm/s"; "" when none is.
function outOfRange(form) {
  for (const input of form.querySelectorAll("input[data-range]")) {
    const range = limits[input.dataset.range];
    const value = Number(input.value);
    if (range && input.value !== "" && (value < range[0] || value > range[1])) {
      const label = input.parentElement.firstChild.textContent.trim();
      return label + " " + input.value + " " + RANGE_UNITS[input.dataset.range] +
        " is outside " + rangeText(input.dataset.range);
    }
  }
  return "";
}

async function runOp(name, args, form) {
  const result = $("op-result");
  const refused = (error) => {
    const why = error.statusName === "E_RANGE_ERROR" && form ? outOfRange(form) : "";
    showResult(result, false, commandName(name) + ": " + error.describe() + (why ? " — " + why : ""));
  };
  const reply = await callApi(refused, "POST", apiBase + "/ops/" + name, args || {});
  if (reply) {
    const started = reply.started ? " (started)" : "";
    showResult(result, true, commandName(name) + ": " + reply.status + started);
  }
}

function bindOpForm(name) {
  const form = $("op-" + name);
  form.addEventListener("submit", (event) => {
    event.preventDefault();
    runOp(name, formArguments(form), form);
  });
}

// The MOVE inputs follow the jaws until the user sets a target.
function followWidth(position) {
  const form = $("op-move");
  if (!live.moveTouched && typeof position === "number") {
    form.elements.position_slider.value = position.toFixed(1);
    form.elements.position_mm.value = position.toFixed(1);
  }
}

function bindMoveSlider() {
  const form = $("op-move");
  const slider = form.elements.position_slider;
  const number = form.elements.position_mm;
  form.addEventListener("focusin", () => (live.moveTouched = true));
  slider.addEventListener("input", () => (number.value = slider.value));
  number.addEventListener("input", () => (slider.value = number.value));
  // the slider moves the jaws when let go
  slider.addEventListener("change", () => runOp("move", formArguments(form), form));
}

function setUpControl() {
  ["home", "move", "grip", "release", "tare"].forEach(bindOpForm);
  ["stop", "fast_stop", "fsack"].forEach((name) => {
    $("op-" + name).addEventListener("click", () => runOp(name));
  });
  bindMoveSlider();
}

// ----------------------------------------------------------- settings panel

// The fields of GET /settings, grouped as on the device's own page, with
// their names in words and the range each number takes (RANGE_UNITS). The
// protocol and the ports are fixed while wsgsim runs (docs/web.md): shown,
// not edited.
const FIXED_SETTINGS = ["protocol", "tcp_port", "udp_port", "binary_udp_port"];
const SETTINGS_GROUPS = [
  ["Command interface", [
    ["protocol", "protocol"],
    ["tcp_port", "TCP port"],
    ["udp_port", "UDP port"],
    ["binary_udp_port", "binary UDP port"],
    ["binary_crc_check", "check binary CRC"],
    ["faststop_on_disconnect", "FAST STOP on TCP disconnect"],
  ]],
  ["Grasping defaults", [
    ["pwt_mm", "part width tolerance (PWT)", "stroke"],
    ["clt_mm", "clamping travel (CLT)", "stroke"],
    ["pullback_mm", "pull-back distance", "stroke"],
    ["force_n", "grip force", "force"],
    ["speed_mm_s", "speed", "speed"],
  ]],
  ["Motion", [
    ["accel_mm_s2", "acceleration", "accel"],
    ["soft_limits", "soft limits"],
    ["soft_limit_minus_mm", "soft limit minus", "stroke"],
    ["soft_limit_plus_mm", "soft limit plus", "stroke"],
    ["overdrive", "overdrive"],
  ]],
  ["Identity", [["tag", "tag"]]],
];

const settings = { loaded: {}, built: false };

// [label, range kind] of a field ("grip force", "force").
function settingInfo(name) {
  for (const [, fields] of SETTINGS_GROUPS) {
    const field = fields.find((f) => f[0] === name);
    if (field) {
      return { label: field[1], kind: field[2] };
    }
  }
  return { label: name, kind: undefined };
}

function settingsInput(name, value) {
  const input = document.createElement("input");
  input.type = typeof value === "boolean" ? "checkbox" : typeof value === "number" ? "number" : "text";
  if (input.type === "number") {
    input.step = "any";
  }
  if (FIXED_SETTINGS.includes(name)) {
    input.readOnly = true;
    input.type = "text"; // a null port reads as "–"
    input.title = "set at start (command line or --config file)";
  }
  input.name = name;
  input.id = "setting-" + name;
  return input;
}

function settingLabel(name) {
  const info = settingInfo(name);
  return info.label + (info.kind ? ", " + RANGE_UNITS[info.kind] : "");
}

function buildSettingsForm(values) {
  const container = $("settings-fields");
  container.replaceChildren();
  for (const [title, fields] of SETTINGS_GROUPS) {
    const group = document.createElement("fieldset");
    group.appendChild(document.createElement("legend")).textContent = title;
    for (const [name] of fields) {
      if (!(name in values)) {
        continue; // a field this server does not have
      }
      const row = document.createElement("div");
      row.className = "setting";
      const text = document.createElement("label");
      text.htmlFor = "setting-" + name;
      text.textContent = settingLabel(name);
      const range = document.createElement("span");
      range.className = "range";
      range.id = "setting-range-" + name;
      const error = document.createElement("span");
      error.className = "field-error";
      error.id = "setting-error-" + name;
      row.append(text, settingsInput(name, values[name]), range, error);
      group.appendChild(row);
    }
    container.appendChild(group);
  }
  settings.built = true;
  showSettingsRanges();
}

// The largest grip force follows the overdrive setting (the model's
// overdrive force while it is on).
function updateForceLimit() {
  if (!limits.forceNominal) {
    return;
  }
  const overdrive = settings.loaded.overdrive && limits.overdriveN > 0;
  limits.force = [limits.forceNominal[0], overdrive ? limits.overdriveN : limits.forceNominal[1]];
}

function showSettingsRanges() {
  for (const name of Object.keys(settings.loaded)) {
    const kind = settingInfo(name).kind;
    const input = $("setting-" + name);
    if (!kind || !input || !limits[kind]) {
      continue;
    }
    input.min = String(limits[kind][0]);
    input.max = String(limits[kind][1]);
    setText("setting-range-" + name, rangeText(kind));
  }
}

function settingsValue(input) {
  if (input.type === "checkbox") {
    return input.checked;
  }
  return input.type === "number" ? Number(input.value) : input.value;
}

function showSettingValue(name, value) {
  const input = $("setting-" + name);
  if (!input) {
    return;
  }
  if (input.type === "checkbox") {
    input.checked = Boolean(value);
  } else {
    input.value = value === null ? (input.readOnly ? "–" : "") : String(value);
  }
}

function fillSettings(values) {
  settings.loaded = values;
  for (const name of Object.keys(values)) {
    showSettingValue(name, values[name]);
  }
  const file = values.save_file;
  $("settings-file").textContent = file
    ? "to " + file
    : "started without --config or --save-file: nothing to save to";
  $("settings-save").disabled = !file;
  updateForceLimit();
  showRanges();
}

function changedSettings() {
  const changes = {};
  for (const name of Object.keys(settings.loaded)) {
    const input = $("setting-" + name);
    if (!input || input.readOnly || (input.type === "number" && input.value === "")) {
      continue;
    }
    if (settingsValue(input) !== settings.loaded[name]) {
      changes[name] = settingsValue(input);
    }
  }
  return changes;
}

function clearFieldErrors() {
  for (const element of document.querySelectorAll(".field-error")) {
    element.textContent = "";
  }
  for (const element of document.querySelectorAll(".setting.invalid")) {
    element.classList.remove("invalid");
  }
}

// What the device said about one field, in the page's words: "grip force
// 500 N is out of range: 5–80 N".
function settingProblem(error, name, asked) {
  const info = settingInfo(name);
  const unit = info.kind ? " " + RANGE_UNITS[info.kind] : "";
  const value = asked === undefined ? "" : " " + (typeof asked === "string" ? '"' + asked + '"'
    : String(asked) + unit);
  if (error.statusName === "E_RANGE_ERROR" && info.kind) {
    const order = /^soft_limit/.test(name) ? ", the minus limit below the plus limit" : "";
    return info.label + value + " is out of range: " + rangeText(info.kind) + order;
  }
  if (name === "tag") {
    return "tag" + value + ": at most 47 characters of printable ASCII, without \"";
  }
  if (error.statusName === "E_ACCESS_DENIED") {
    return info.label + " is fixed while wsgsim runs: set it in the configuration file or " +
      "on the command line, and restart";
  }
  return info.label + value + ": refused (" + error.statusName + ")";
}

// The server names the field first ("force_n: …"). The field shows the
// problem and goes back to the value in force: nothing was applied.
function showSettingsError(error, changes) {
  const field = /^([a-z0-9_]+):/.exec(error.message || "");
  const name = field && field[1];
  const slot = name && $("setting-error-" + name);
  if (!slot) {
    showResult($("settings-result"), false, "not applied: " + error.describe());
    return;
  }
  const problem = settingProblem(error, name, changes[name]);
  const kept = settings.loaded[name];
  const unit = settingInfo(name).kind ? " " + RANGE_UNITS[settingInfo(name).kind] : "";
  slot.textContent = problem + "; the device keeps " +
    (typeof kept === "boolean" ? (kept ? "on" : "off") : String(kept) + unit);
  slot.parentElement.classList.add("invalid");
  showSettingValue(name, kept);
  showResult($("settings-result"), false, "not applied: " + problem +
    ". Nothing was changed (" + error.statusName + ").");
}

// PUTs what changed; true when the device took it (or nothing changed).
async function applySettings() {
  clearFieldErrors();
  const changes = changedSettings();
  if (Object.keys(changes).length === 0) {
    showResult($("settings-result"), true, "nothing changed");
    return true;
  }
  const refused = (error) => showSettingsError(error, changes);
  const values = await callApi(refused, "PUT", apiBase + "/settings", changes);
  if (!values) {
    return false;
  }
  fillSettings(values);
  const names = Object.keys(changes).map((name) => settingInfo(name).label);
  showResult($("settings-result"), true, "applied: " + names.join(", "));
  return true;
}

async function saveSettings() {
  if (!(await applySettings())) {
    return;
  }
  const result = $("settings-result");
  const refused = (error) => showResult(result, false, "save: " + error.describe());
  if (await callApi(refused, "POST", apiBase + "/settings/save")) {
    showResult(result, true, "saved to " + settings.loaded.save_file);
  }
}

async function setUpSettings() {
  $("settings-form").addEventListener("submit", (event) => {
    event.preventDefault();
    applySettings();
  });
  $("settings-save").addEventListener("click", saveSettings);
  $("startup-apply").addEventListener("click", applyStartup);
  const refused = (error) => showResult($("settings-result"), false, "settings: " + error.describe());
  const values = await callApi(refused, "GET", apiBase + "/settings");
  if (values) {
    settings.loaded = values;
    buildSettingsForm(values);
    fillSettings(values);
  }
}

// --------------------------------------------------------- simulation panel

// Without sim_allowed (GET /api/devices, at load) the server refuses the
// simulation routes: the panel and the status area's clock buttons are
// shown disabled with the reason, not left to fail at the first click.
function simAvailable(allowed) {
  live.simAllowed = allowed;
  $("sim-controls").disabled = !allowed;
  $("sim-unavailable").hidden = allowed;
  for (const id of ["clock-step", "clock-resume", "clock-pause"]) {
    $(id).disabled = !allowed;
    $(id).title = allowed ? "" : "the simulation is served to wsgsim's own machine only";
  }
}

// What a clock action did, in words: a STEP answers at once and runs on
// (followStep() says where it ended). from: the time the state showed when
// the step was asked for (an event may show its end before its reply).
function clockDone(args, reply, result, from) {
  if (args.action === "step") {
    live.step = { toMs: from + args.ms, ms: args.ms, result: result };
    return "stepping " + args.ms + " ms from " + fixed(from / 1000, 3) + " s";
  }
  if (args.action === "pause") {
    return "paused";
  }
  return args.action === "resume" ? "running" : reply.reply;
}

async function runSim(route, args, result) {
  result = result || $("sim-result");
  const refused = (error) => {
    if (error.httpStatus === 403) {
      simAvailable(false);
    }
    showResult(result, false, route + ": " + error.describe());
  };
  const from = live.lastState ? live.lastState.time_ms : 0;
  const reply = await callApi(refused, "POST", apiBase + "/sim/" + route, args || {});
  if (reply) {
    // the control channel's reply line ("ACK PART")
    const said = route === "clock" ? clockDone(args, reply, result, from)
      : reply.reply || reply.status;
    showResult(result, true, route + ": " + said);
    if (live.lastState) {
      followStep(live.lastState.time_ms); // a step the state already shows
    }
  }
}

function bindSimForm(route) {
  const form = $("sim-" + route);
  form.addEventListener("submit", (event) => {
    event.preventDefault();
    runSim(route, formArguments(form));
  });
}

function stepMs() {
  return Number($("sim-clock").elements.ms.value) || 100;
}

function bindClock() {
  const form = $("sim-clock");
  const fields = form.elements;
  const argsFor = {
    pause: () => ({ action: "pause" }),
    resume: () => ({ action: "resume" }),
    step: () => ({ action: "step", ms: stepMs() }),
    scale: () => ({ action: "scale", scale: Number(fields.scale.value) }),
  };
  form.addEventListener("submit", (event) => {
    event.preventDefault();
    runSim("clock", argsFor.step());
  });
  for (const button of form.querySelectorAll("button[type=button]")) {
    button.addEventListener("click", () => runSim("clock", argsFor[button.dataset.action]()));
  }
  // the status area's buttons, on every view, with their own result
  for (const action of ["step", "resume", "pause"]) {
    $("clock-" + action).addEventListener("click",
      () => runSim("clock", argsFor[action](), $("clock-result")));
  }
  const label = () => ($("clock-step").textContent = "Step " + stepMs() + " ms");
  fields.ms.addEventListener("input", label);
  label();
}

function setUpSim() {
  ["part", "obstacle", "ambient", "fault", "place", "pull", "mass", "friction", "lift"]
    .forEach(bindSimForm);
  for (const route of ["part_remove", "obstacle_remove", "clear"]) {
    $("sim-" + route).addEventListener("click", () => runSim(route));
  }
  const fault = $("sim-fault");
  $("sim-clear-one").addEventListener("click", () => runSim("clear", formArguments(fault)));
  bindClock();
}

// ---------------------------------------------------------------- the views

// One view at a time, named by the address's hash (#live, #motion, ...):
// the browser's back button and bookmarks work, the tabs are plain links.
const views = { current: "", onShow: {}, title: "wsgsim" };

// "wsgsim WSG 50-110 (device 0) · Scripting"
function showTitle() {
  const tab = views.current ? " · " + $("tab-" + views.current).textContent : "";
  document.title = views.title + tab;
}

// Another hash (the "skip to the view" link's #views) keeps the view shown.
function viewFromHash() {
  const name = location.hash.replace(/^#/, "");
  return VIEWS.includes(name) ? name : views.current || "live";
}

function showView() {
  const name = viewFromHash();
  if (name === views.current) {
    return;
  }
  views.current = name;
  for (const view of VIEWS) {
    $("view-" + view).hidden = view !== name;
    const tab = $("tab-" + view);
    if (view === name) {
      tab.setAttribute("aria-current", "page");
    } else {
      tab.removeAttribute("aria-current");
    }
  }
  showTitle();
  if (views.onShow[name]) {
    views.onShow[name]();
  }
}

function setUpViews() {
  window.addEventListener("hashchange", showView);
  views.onShow.live = () => {
    if (live.chart) {
      live.chart.resize(); // drawn while hidden, it has no size
    }
    scheduleChart();
  };
  showView();
}

// A poll that runs while its view is shown, one request at a time.
function pollWhileShown(view, periodMs, poll) {
  let running = false;
  const tick = async () => {
    if (views.current !== view) {
      running = false;
      return;
    }
    await poll();
    setTimeout(tick, periodMs);
  };
  views.onShow[view] = () => {
    if (!running) {
      running = true;
      tick();
    }
  };
}

// ----------------------------------------------------------- the scripting

const scripting = {
  allowed: true, // may this client run scripts and change files (sim_allowed)
  writable: false, // the store can be written
  openFile: null, // the file in the editor
  startup: null, // the startup script (GET …/script), null: none
  savedText: "",
  consoleNext: 0,
  reading: null, // the console read under way (a promise)
  running: null, // the file a Run started, until the state says how it ended
  last: null, // the last GET …/script
};

// ------------------------------------------------------------ the editor

// Debian's CodeMirror (libjs-codemirror, served from the system as the
// chart library is): line numbers, Lua highlighting, matching brackets, the
// line of a script's error marked. Without it the plain textarea serves.
const editor = { cm: null, errorLine: null };

function setUpEditor() {
  if (typeof CodeMirror === "undefined") {
    return; // the library could not be loaded: the textarea stays
  }
  editor.cm = CodeMirror.fromTextArea($("editor-text"), {
    mode: "lua",
    lineNumbers: true,
    matchBrackets: true,
    indentUnit: 4,
    gutters: ["CodeMirror-linenumbers", "error-gutter"],
    inputStyle: "contenteditable", // a screen reader reads it as text
    screenReaderLabel: "the open file's text",
    readOnly: "nocursor",
  });
  editor.cm.on("change", () => clearErrorLine());
}

function editorText() {
  return editor.cm ? editor.cm.getValue() : $("editor-text").value;
}

function setEditorText(text) {
  clearErrorLine();
  if (editor.cm) {
    editor.cm.setValue(text);
    editor.cm.clearHistory();
  } else {
    $("editor-text").value = text;
  }
}

// open: a file is in the editor; writable: it may be changed.
function setEditorState(open, writable) {
  $("editor-text").disabled = !open;
  $("editor-text").readOnly = !writable;
  if (editor.cm) {
    editor.cm.setOption("readOnly", !open ? "nocursor" : !writable);
    editor.cm.getWrapperElement().classList.toggle("disabled", !open);
  }
}

function clearErrorLine() {
  if (editor.cm && editor.errorLine !== null) {
    editor.cm.removeLineClass(editor.errorLine, "background", "error-line");
    editor.cm.clearGutter("error-gutter");
  }
  editor.errorLine = null;
  $("script-error-line").hidden = true;
}

// "bad.lua:3: unexpected symbol near '='": {file: "bad.lua", line: 3}.
function errorPlace(error) {
  const match = /^(?:.*\/)?([^/:\s]+):(\d+):/.exec(error || "");
  return match ? { file: match[1], line: Number(match[2]) } : null;
}

// Marks the line of the last script error when it is in the open file.
function markErrorLine(script) {
  clearErrorLine();
  const place = errorPlace(script && script.error);
  if (!place || scripting.openFile === null || script.file !== "/user/" + scripting.openFile ||
      place.file !== scripting.openFile) {
    return;
  }
  const button = $("script-error-line");
  button.textContent = "Show line " + place.line;
  button.hidden = false;
  if (!editor.cm || place.line > editor.cm.lineCount()) {
    return;
  }
  const line = place.line - 1;
  editor.errorLine = line;
  editor.cm.addLineClass(line, "background", "error-line");
  const marker = document.createElement("span");
  marker.className = "error-marker";
  marker.textContent = "!";
  marker.title = script.error;
  editor.cm.setGutterMarker(line, "error-gutter", marker);
}

function showErrorLine() {
  const place = errorPlace(scripting.last && scripting.last.error);
  if (editor.cm && place) {
    editor.cm.focus();
    editor.cm.setCursor({ line: place.line - 1, ch: 0 });
    editor.cm.scrollIntoView({ line: place.line - 1, ch: 0 }, 40);
  }
}

function scriptResult(ok, text) {
  showResult($("script-result"), ok, text);
}

function storePath(name) {
  return apiBase + "/files/" + encodeURIComponent(name);
}

function fileRow(file) {
  const row = document.createElement("tr");
  row.dataset.name = file.name;
  const name = row.insertCell();
  name.textContent = file.name;
  row.insertCell().textContent = String(file.bytes);
  const actions = row.insertCell();
  const button = (text, action, needsWrite) => {
    const b = document.createElement("button");
    b.type = "button";
    b.textContent = text;
    b.setAttribute("aria-label", text + " " + file.name);
    b.disabled = needsWrite && !(scripting.writable && scripting.allowed);
    b.addEventListener("click", action);
    actions.appendChild(b);
  };
  button("Open", () => openFile(file.name), false);
  const download = document.createElement("a");
  download.href = storePath(file.name);
  download.download = file.name;
  download.textContent = "Download";
  download.setAttribute("aria-label", "Download " + file.name);
  actions.appendChild(download);
  button("Rename", () => renameFile(file.name), true);
  button("Delete", () => deleteFile(file.name), true);
  return row;
}

async function listFiles() {
  const info = await system.info;
  $("store-missing").hidden = !info || info.script_store;
  if (info && !info.script_store) {
    return; // no /user/ store: nothing to list (…/files is 404)
  }
  const refused = (error) => {
    if (error.httpStatus === 404) {
      $("store-missing").hidden = false;
    } else {
      showResult($("files-result"), false, "files: " + error.describe());
    }
  };
  const listing = await callApi(refused, "GET", apiBase + "/files");
  if (!listing) {
    return;
  }
  scripting.writable = listing.writable;
  $("store-readonly").hidden = listing.writable;
  const canWrite = listing.writable && scripting.allowed;
  for (const form of [$("file-new"), $("file-upload")]) {
    for (const field of form.elements) {
      field.disabled = !canWrite;
    }
  }
  const files = listing.files.sort((a, b) => a.name.localeCompare(b.name));
  $("file-list").replaceChildren(...files.map(fileRow));
  fillStartupChoice(files);
  updateEditorButtons();
}

// Settings → System: the store's files as startup scripts, the current one chosen.
function fillStartupChoice(files) {
  const choice = $("startup-choice");
  const current = scripting.startup || "";
  const options = [new Option("none", "")].concat(
    files.map((file) => new Option("/user/" + file.name, "/user/" + file.name)));
  choice.replaceChildren(...options);
  choice.value = options.some((o) => o.value === current) ? current : "";
  choice.disabled = !scripting.allowed;
  $("startup-apply").disabled = !scripting.allowed;
}

async function applyStartup() {
  const file = $("startup-choice").value;
  const refused = (error) => showResult($("startup-result"), false,
    "startup script: " + error.describe());
  const reply = await callApi(refused, "PUT", apiBase + "/script/startup",
    {file: file === "" ? null : file});
  if (reply) {
    showResult($("startup-result"), true, "startup script: " + (file || "none") +
      ", from the next power-on (Save keeps it)");
    renderScript(reply);
  }
}

function updateEditorButtons() {
  const open = scripting.openFile !== null;
  const canWrite = scripting.writable && scripting.allowed;
  setEditorState(open, canWrite);
  $("script-save").disabled = !open || !canWrite;
  $("script-run").disabled = !open || !scripting.allowed;
  $("script-stop").disabled = !scripting.allowed;
}

async function openFile(name) {
  if (scripting.openFile !== null && editorText() !== scripting.savedText &&
      !confirm(scripting.openFile + " has changes that are not saved: drop them?")) {
    return;
  }
  let text;
  try {
    const response = await fetch(storePath(name));
    text = await response.text();
    if (!response.ok) {
      throw new ApiError(response.status, JSON.parse(text));
    }
  } catch (error) {
    const problem = error instanceof ApiError ? error.describe() : error.message;
    showResult($("files-result"), false, "open " + name + ": " + problem);
    return;
  }
  scripting.openFile = name;
  scripting.savedText = text;
  setEditorText(text);
  $("editor-file").textContent = "/user/" + name;
  updateEditorButtons();
  markErrorLine(scripting.last); // the last run's error, if it was in this file
  showResult($("files-result"), true, "opened " + name);
}

function fileListed(name) {
  return [...$("file-list").rows].some((row) => row.dataset.name === name);
}

// Writing over a listed file only after the user said so.
function mayReplace(name) {
  return !fileListed(name) || confirm("/user/" + name + " exists: replace it?");
}

async function writeFile(name, text, result) {
  const refused = (error) => showResult(result, false, "save " + name + ": " + error.describe());
  const reply = await callApi(refused, "PUT", storePath(name), { text: text });
  if (reply) {
    showResult(result, true, "saved " + name + " (" + reply.bytes + " bytes)");
  }
  return reply !== null;
}

async function saveOpenFile() {
  const text = editorText();
  if (!(await writeFile(scripting.openFile, text, $("script-result")))) {
    return false;
  }
  scripting.savedText = text;
  await listFiles();
  return true;
}

async function newFile(event) {
  event.preventDefault();
  const name = $("file-new").elements.name.value.trim();
  if (fileListed(name)) {
    showResult($("files-result"), false, name + " exists: open it from the list");
    return;
  }
  if (await writeFile(name, "", $("files-result"))) {
    await listFiles();
    await openFile(name);
  }
}

async function uploadFile() {
  const input = $("file-upload").elements.file;
  const file = input.files[0];
  if (!file || !mayReplace(file.name)) {
    input.value = "";
    return;
  }
  if (await writeFile(file.name, await file.text(), $("files-result"))) {
    await listFiles();
  }
  input.value = "";
}

// The store has no rename: the file is written under the new name, then
// the old one deleted. A device's startup script is not deleted (409): it
// keeps its name, and the copy goes again.
async function renameFile(name) {
  const result = $("files-result");
  if (scripting.startup === "/user/" + name) {
    showResult(result, false, "rename " + name + ": it is the startup script: choose another " +
      "or none first (Settings → System)");
    return;
  }
  const to = prompt("Rename " + name + " to:", name);
  if (!to || to === name || !mayReplace(to)) {
    return;
  }
  const response = await fetch(storePath(name));
  const text = await response.text();
  if (!response.ok) {
    showResult(result, false, "rename " + name + ": HTTP " + response.status);
    return;
  }
  if (!(await writeFile(to, text, result))) {
    return;
  }
  const kept = (error) => showResult(result, false, "rename " + name + ": " + error.describe());
  if (!(await callApi(kept, "DELETE", storePath(name)))) {
    // the old name must stay (a device's startup script): no copy is left
    await callApi(() => {}, "DELETE", storePath(to));
    await listFiles();
    return;
  }
  if (scripting.openFile === name) {
    scripting.openFile = to;
    $("editor-file").textContent = "/user/" + to;
  }
  await listFiles();
  showResult(result, true, "renamed " + name + " to " + to);
}

async function deleteFile(name) {
  if (!confirm("Delete /user/" + name + "?")) {
    return;
  }
  const result = $("files-result");
  const refused = (error) => showResult(result, false, "delete " + name + ": " + error.describe());
  if (await callApi(refused, "DELETE", storePath(name))) {
    showResult(result, true, "deleted " + name);
    await listFiles();
  }
}

// Run saves the open file first (spec: "run the open file (saved first)").
async function runOpenFile() {
  if (scripting.writable && editorText() !== scripting.savedText) {
    if (!(await saveOpenFile())) {
      return;
    }
  }
  const file = "/user/" + scripting.openFile;
  const refused = (error) => scriptResult(false, "run " + file + ": " + error.describe());
  clearErrorLine();
  const reply = await callApi(refused, "POST", apiBase + "/script/run", { file: file });
  if (reply) {
    // a script that does not compile ends at once: its reply says so
    scripting.running = file;
    scriptResult(true, "run " + file + ": started");
    renderScript(reply);
    pollConsole();
  }
}

async function stopScript() {
  const refused = (error) => scriptResult(false, "stop: " + error.describe());
  const reply = await callApi(refused, "POST", apiBase + "/script/stop");
  if (reply) {
    scripting.running = null;
    scriptResult(true, "stop: stopped");
    renderScript(reply);
  }
}

function renderScript(script) {
  setText("script-file", script.running ? script.file : "no script runs" +
    (script.file ? " (last: " + script.file + ")" : ""));
  setText("script-error-text", script.error ? "error: " + script.error : "");
  if (!scripting.last || scripting.last.error !== script.error ||
      scripting.last.file !== script.file) {
    markErrorLine(script);
  }
  scripting.last = script;
  runEnded(script);
  setText("startup-script", script.startup ? script.startup + " (runs at power-on)"
    : "none (or not started at power-on: --no-script-autostart)");
  scripting.startup = script.startup;
  const choice = $("startup-choice");
  if ([...choice.options].some((o) => o.value === (script.startup || ""))) {
    choice.value = script.startup || "";
  }
}

// How the script a Run started ended, once GET …/script says it did: the
// "started" line gives way to the error or to "finished".
function runEnded(script) {
  const file = scripting.running;
  if (file === null || script.running || script.file !== file) {
    return;
  }
  scripting.running = null;
  const place = errorPlace(script.error);
  if (script.failure) {
    scriptResult(false, "run " + file + ": stopped with an error" +
      (place ? " at line " + place.line : "") + " (SF_SCRIPT_FAILURE)");
  } else {
    scriptResult(true, "run " + file + ": finished");
  }
}

// SF_SCRIPT_RUNNING and SF_SCRIPT_FAILURE from the event stream.
function renderScriptFlags(setFlags) {
  for (const [id, flag] of [["script-flag-running", "SF_SCRIPT_RUNNING"],
                            ["script-flag-failure", "SF_SCRIPT_FAILURE"]]) {
    const on = setFlags.includes(flag);
    setText(id, flag + (on ? " ✔ set" : " ○ clear"));
    $(id).classList.toggle("set", on);
  }
}

// One console read at a time (Run reads at once, besides the poll): two
// reads from the same line number would show its lines twice.
function pollConsole() {
  if (!scripting.reading) {
    scripting.reading = readConsole().finally(() => (scripting.reading = null));
  }
  return scripting.reading;
}

async function readConsole() {
  const failed = () => {}; // the link indicator shows a lost server
  const reply = await callApi(failed, "GET",
    apiBase + "/script/console?since=" + scripting.consoleNext);
  if (reply && reply.lines.length) {
    appendLines($("console"), reply.lines, CONSOLE_LINES_SHOWN);
  }
  if (reply) {
    scripting.consoleNext = reply.next;
  }
  const script = await callApi(failed, "GET", apiBase + "/script");
  if (script) {
    renderScript(script);
  }
}

// Adds lines to a <pre>, keeping the last `keep`, scrolled to the end when
// it was at the end.
function appendLines(pre, lines, keep) {
  const atEnd = pre.scrollTop + pre.clientHeight >= pre.scrollHeight - 4;
  const all = (pre.textContent ? pre.textContent.split("\n") : []).concat(lines);
  pre.textContent = all.slice(-keep).join("\n");
  if (atEnd) {
    pre.scrollTop = pre.scrollHeight;
  }
}

// The store holds Lua files only: a name the field's pattern refuses is
// explained in words where the results show, not only in the browser's tip.
const STORE_NAME_RULE = "a script's name ends in .lua (NAME.lua: at most 64 characters, " +
  "no spaces, '/', '\\' or '..')";

function setUpScripting() {
  $("file-new").addEventListener("submit", newFile);
  $("file-new").elements.name.addEventListener("invalid", () =>
    showResult($("files-result"), false, "new file: " + STORE_NAME_RULE));
  $("file-upload").elements.file.addEventListener("change", uploadFile);
  $("script-save").addEventListener("click", saveOpenFile);
  $("script-run").addEventListener("click", runOpenFile);
  $("script-stop").addEventListener("click", stopScript);
  $("script-error-line").addEventListener("click", showErrorLine);
  $("console-clear").addEventListener("click", () => ($("console").textContent = ""));
  pollWhileShown("scripting", CONSOLE_POLL_MS, pollConsole);
  const showScripting = views.onShow.scripting;
  views.onShow.scripting = () => {
    if (editor.cm) {
      editor.cm.refresh(); // laid out while hidden, it has no size
    }
    listFiles();
    showScripting();
  };
  views.onShow.settings = listFiles; // the startup script's choice of files
}

// Without sim_allowed the server refuses runs and changes: shown, not tried.
function scriptingAllowed(allowed) {
  scripting.allowed = allowed;
  $("script-unavailable").hidden = allowed;
  updateEditorButtons();
  if (views.current === "scripting" || views.current === "settings") {
    listFiles(); // its buttons follow the rule
  }
}

// --------------------------------------------------------------- the system

// info: GET /system as the page loaded (a promise, null after a refusal).
const system = { logNext: 0, info: null };

function formatUptime(ms) {
  const total = Math.floor(ms / 1000);
  const hours = Math.floor(total / 3600);
  const minutes = Math.floor((total % 3600) / 60);
  const seconds = total % 60;
  const two = (n) => String(n).padStart(2, "0");
  return hours + ":" + two(minutes) + ":" + two(seconds) + " (" + (ms / 1000).toFixed(3) + " s)";
}

function renderSystem(info) {
  setText("sys-model", info.model);
  setText("sys-serial", String(info.serial));
  setText("sys-firmware", info.firmware_version);
  setText("sys-wsgsim", info.wsgsim_version);
  setText("sys-timing", info.timing);
  setText("sys-uptime", formatUptime(info.uptime_ms));
  if (info.force_max_n > 0) {
    live.forceSpanN = info.force_max_n;
  }
  const log = info.log;
  if (log.next < system.logNext) {
    $("system-log").textContent = ""; // another wsgsim: its log starts again
  }
  if (log.lines.length) {
    appendLines($("system-log"), log.lines, LOG_LINES_SHOWN);
  }
  system.logNext = log.next;
}

async function pollSystem() {
  const info = await callApi(() => {}, "GET", apiBase + "/system?since=" + system.logNext);
  if (info) {
    renderSystem(info);
  }
}

// The model's ranges (the force axis's span) and whether there is a script
// store: GET /system once at start, without its log lines.
async function loadSystemInfo() {
  const info = await callApi(() => {}, "GET", apiBase + "/system?since=" + Number.MAX_SAFE_INTEGER);
  if (info && info.force_max_n > 0) {
    live.forceSpanN = info.force_max_n;
    setLimits(info);
    scheduleChart();
  }
  return info;
}

// ------------------------------------------------------------ the devices

async function setUpDevices() {
  const refused = (error) => ($("identity").textContent = "devices: " + error.describe());
  const reply = await callApi(refused, "GET", "/api/devices");
  const devices = reply ? reply.devices : [];
  if (reply) {
    simAvailable(reply.sim_allowed);
    scriptingAllowed(reply.sim_allowed);
  }
  const self = devices.find((device) => device.id === deviceId);
  if (self) {
    $("identity").textContent = self.model + (self.tag ? " · " + self.tag : "") + " · device " + deviceId;
    views.title = "wsgsim " + self.model + " (device " + deviceId + ")";
    showTitle();
  }
  if (devices.length < 2) {
    return;
  }
  const select = $("device-select");
  // --address-per-device: the devices share their ports and differ by address
  const byAddress = devices[0].address !== devices[1].address;
  for (const device of devices) {
    const where = byAddress ? device.address : "TCP " + device.tcp_port;
    const option = new Option(device.id + ": " + device.model + " (" + where + ")", device.id);
    option.selected = device.id === deviceId;
    select.appendChild(option);
  }
  select.addEventListener("change", () => (location.pathname = "/devices/" + select.value));
  $("device-picker").hidden = false;
}

async function loadScriptState() {
  const script = await callApi(() => {}, "GET", apiBase + "/script");
  if (script) {
    renderScript(script);
  }
}

function main() {
  setUpEditor();
  setUpControl();
  setUpSim();
  setUpSettings();
  setUpDevices();
  system.info = loadSystemInfo();
  system.info.then((info) => ($("sim-scene").hidden = !info || !info.physics));
  setUpScripting();
  pollWhileShown("system", SYSTEM_POLL_MS, pollSystem);
  $("banner-fsack").addEventListener("click", bannerFsack);
  setUpViews();
  loadScriptState();
  openStream(RECONNECT_MIN_MS);
}

main();
