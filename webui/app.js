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
};

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
  const part = state.part;
  setText("part-text", part && part.present ? fixed(part.width_mm, 1) + " mm" : "none");
  // the motion view's line
  setText("m-width", fixed(state.position_mm, 1));
  setText("m-force", fixed(state.force_n, 1));
  setText("m-grip-state", $("grip-state").textContent);
  setText("m-motion", state.motion || "–");
}

function setJawSpan(stroke) {
  if (stroke === live.stroke || !(stroke > 0)) {
    return;
  }
  live.stroke = stroke;
  const width = stroke + 2 * (SVG_MARGIN_MM + JAW_WIDTH_MM);
  $("jaws").setAttribute("viewBox", "0 0 " + width + " 50");
  $("jaw-base").setAttribute("width", String(width - 10));
  for (const input of document.querySelectorAll("#op-move input")) {
    input.max = String(stroke);
  }
}

// x of the inner face of a jaw at offset mm from the middle
function jawX(offsetMm) {
  return SVG_MARGIN_MM + JAW_WIDTH_MM + live.stroke / 2 + offsetMm;
}

function placeBox(element, widthMm) {
  element.setAttribute("x", String(jawX(-widthMm / 2)));
  element.setAttribute("width", String(Math.max(widthMm, 0)));
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
  const part = state.part || {};
  $("part").toggleAttribute("hidden", !part.present);
  if (part.present) {
    // a held part is squeezed to the jaws' width
    placeBox($("part"), Math.min(part.width_mm, state.position_mm));
    $("part").classList.toggle("held", (state.grip_state || {}).code === 4);
  }
  const obstacle = state.obstacle || {};
  for (const side of ["minus", "plus"]) {
    const line = $("obstacle-" + side);
    line.toggleAttribute("hidden", !obstacle.present);
    if (obstacle.present) {
      const x = jawX((side === "minus" ? -1 : 1) * obstacle.width_mm / 2);
      line.setAttribute("x1", String(x));
      line.setAttribute("x2", String(x));
    }
  }
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
      item.querySelector(".name").textContent = item.dataset.name;
      item.title = "bit " + bit;
      item.classList.toggle("reserved", !name);
      list.appendChild(item);
      live.flagItems.push(item);
    });
  }
  // set or clear in words and a mark, not only by colour
  live.flagItems.forEach((item, bit) => {
    const set = ((sysflags.value >>> bit) & 1) === 1;
    if (item.classList.contains("set") !== set || !item.dataset.shown) {
      item.dataset.shown = "1";
      item.classList.toggle("set", set);
      item.querySelector(".mark").textContent = set ? "✔" : "○";
      item.querySelector(".sr-only").textContent = set ? ": set" : ": clear";
    }
  });
  renderFastStop(sysflags.set || []);
  renderScriptFlags(sysflags.set || []);
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

function renderFinger(finger) {
  const box = fingerView(finger.slot);
  box.querySelector("h4").textContent = "Slot " + finger.slot + ": " + finger.type;
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
  if (isForce) {
    text = "force " + finger.data.toFixed(2) + " N";
    const fullScale = Math.max(FMF_BAR_FULL_SCALE_N, Math.abs(finger.data));
    bar.firstChild.style.width = (100 * Math.abs(finger.data)) / fullScale + "%";
  } else if (isMap) {
    text = (finger.rows || 14) + " × " + (finger.cols || 6) + " tactile map, peak " +
      Math.max(...finger.data) + " of " + DSA_CELL_MAX;
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
      labelsSeparateLines: false,
      animatedZooms: false,
    });
  } else {
    live.chart.updateOptions({ file: live.chartData, axes: axes });
  }
}

// ------------------------------------------------------------- the stream

function renderState(state) {
  renderReadouts(state);
  renderJaws(state);
  followWidth(state.position_mm);
  renderFlags(state.sysflags);
  renderFingers(state.fingers);
  renderConnections(state.connections);
  renderWebOp(state.web_op);
  addChartPoint(state);
  scheduleChart();
}

function setLink(up, text) {
  const link = $("link");
  link.textContent = text;
  link.classList.toggle("up", up);
  link.classList.toggle("down", !up);
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
    showResult(element, true, name + " running since " + fixed(op.started_ms / 1000, 3) + " s");
    return;
  }
  const ended = " at " + fixed(op.ended_ms / 1000, 3) + " s";
  showResult(element, op.code === 0, name + " finished: " + op.status + " (" + op.code + ")" + ended);
}

// The command's name as the manual writes it (the route says fast_stop).
function commandName(op) {
  return op.replace("_", "").toUpperCase();
}

async function runOp(name, args) {
  const result = $("op-result");
  const refused = (error) => showResult(result, false, commandName(name) + ": " + error.describe());
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
    runOp(name, formArguments(form));
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
  slider.addEventListener("change", () => runOp("move", formArguments(form)));
}

function setUpControl() {
  ["home", "move", "grip", "release", "tare"].forEach(bindOpForm);
  ["stop", "fast_stop", "fsack"].forEach((name) => {
    $("op-" + name).addEventListener("click", () => runOp(name));
  });
  bindMoveSlider();
}

// ----------------------------------------------------------- settings panel

// The fields of GET /settings, grouped as on the device's own page. The
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
    ["pwt_mm", "part width tolerance (PWT), mm"],
    ["clt_mm", "clamping travel (CLT), mm"],
    ["pullback_mm", "pull-back distance, mm"],
    ["force_n", "force, N"],
    ["speed_mm_s", "speed, mm/s"],
  ]],
  ["Motion", [
    ["accel_mm_s2", "acceleration, mm/s²"],
    ["soft_limits", "soft limits"],
    ["soft_limit_minus_mm", "soft limit minus, mm"],
    ["soft_limit_plus_mm", "soft limit plus, mm"],
    ["overdrive", "overdrive"],
  ]],
  ["Identity", [["tag", "tag"]]],
];

const settings = { loaded: {} };

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

function buildSettingsForm(values) {
  const container = $("settings-fields");
  container.replaceChildren();
  for (const [title, fields] of SETTINGS_GROUPS) {
    const group = document.createElement("fieldset");
    group.appendChild(document.createElement("legend")).textContent = title;
    for (const [name, label] of fields) {
      if (!(name in values)) {
        continue; // a field this server does not have
      }
      const row = document.createElement("div");
      row.className = "setting";
      const text = document.createElement("label");
      text.htmlFor = "setting-" + name;
      text.textContent = label;
      const error = document.createElement("span");
      error.className = "field-error";
      error.id = "setting-error-" + name;
      row.append(text, settingsInput(name, values[name]), error);
      group.appendChild(row);
    }
    container.appendChild(group);
  }
}

function settingsValue(input) {
  if (input.type === "checkbox") {
    return input.checked;
  }
  return input.type === "number" ? Number(input.value) : input.value;
}

function fillSettings(values) {
  settings.loaded = values;
  for (const name of Object.keys(values)) {
    const input = $("setting-" + name);
    if (!input) {
      continue;
    }
    if (input.type === "checkbox") {
      input.checked = Boolean(values[name]);
    } else {
      input.value = values[name] === null ? (input.readOnly ? "–" : "") : String(values[name]);
    }
  }
  const file = values.save_file;
  $("settings-file").textContent = file
    ? "to " + file
    : "started without --config or --save-file: nothing to save to";
  $("settings-save").disabled = !file;
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

// The server names the field first: "pwt_mm: out of range".
function showSettingsError(error) {
  const field = /^([a-z0-9_]+):/.exec(error.message || "");
  const slot = field && $("setting-error-" + field[1]);
  if (slot) {
    slot.textContent = error.describe();
    slot.parentElement.classList.add("invalid");
  }
  showResult($("settings-result"), false, error.describe());
}

// PUTs what changed; true when the device took it (or nothing changed).
async function applySettings() {
  clearFieldErrors();
  const changes = changedSettings();
  if (Object.keys(changes).length === 0) {
    showResult($("settings-result"), true, "nothing changed");
    return true;
  }
  const values = await callApi(showSettingsError, "PUT", apiBase + "/settings", changes);
  if (!values) {
    return false;
  }
  fillSettings(values);
  showResult($("settings-result"), true, "applied: " + Object.keys(changes).join(", "));
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
    buildSettingsForm(values);
    fillSettings(values);
  }
}

// --------------------------------------------------------- simulation panel

function simUnavailable() {
  $("sim-controls").disabled = true;
  $("sim-unavailable").hidden = false;
}

async function runSim(route, args) {
  const result = $("sim-result");
  const refused = (error) => {
    if (error.httpStatus === 403) {
      simUnavailable();
    }
    showResult(result, false, route + ": " + error.describe());
  };
  const reply = await callApi(refused, "POST", apiBase + "/sim/" + route, args || {});
  if (reply) {
    // the control channel's reply line ("ACK PART"); a STEP runs on
    showResult(result, true, route + ": " + (reply.reply || (reply.started ? "started" : reply.status)));
  }
}

function bindSimForm(route) {
  const form = $("sim-" + route);
  form.addEventListener("submit", (event) => {
    event.preventDefault();
    runSim(route, formArguments(form));
  });
}

function bindClock() {
  const form = $("sim-clock");
  const fields = form.elements;
  const argsFor = {
    pause: () => ({ action: "pause" }),
    resume: () => ({ action: "resume" }),
    step: () => ({ action: "step", ms: Number(fields.ms.value) }),
    scale: () => ({ action: "scale", scale: Number(fields.scale.value) }),
  };
  form.addEventListener("submit", (event) => {
    event.preventDefault();
    runSim("clock", argsFor.step());
  });
  for (const button of form.querySelectorAll("button[type=button]")) {
    button.addEventListener("click", () => runSim("clock", argsFor[button.dataset.action]()));
  }
}

function setUpSim() {
  ["part", "obstacle", "ambient", "fault"].forEach(bindSimForm);
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
};

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
  $("editor-text").disabled = !open;
  $("editor-text").readOnly = !canWrite;
  $("script-save").disabled = !open || !canWrite;
  $("script-run").disabled = !open || !scripting.allowed;
  $("script-stop").disabled = !scripting.allowed;
}

async function openFile(name) {
  if (scripting.openFile !== null && $("editor-text").value !== scripting.savedText &&
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
  $("editor-text").value = text;
  $("editor-file").textContent = "/user/" + name;
  updateEditorButtons();
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
  const text = $("editor-text").value;
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
// the old one deleted.
async function renameFile(name) {
  const to = prompt("Rename " + name + " to:", name);
  if (!to || to === name || !mayReplace(to)) {
    return;
  }
  const response = await fetch(storePath(name));
  const text = await response.text();
  const result = $("files-result");
  if (!response.ok) {
    showResult(result, false, "rename " + name + ": HTTP " + response.status);
    return;
  }
  if (await writeFile(to, text, result)) {
    await deleteFile(name, true);
    if (scripting.openFile === name) {
      scripting.openFile = to;
      $("editor-file").textContent = "/user/" + to;
    }
    showResult(result, true, "renamed " + name + " to " + to);
  }
}

async function deleteFile(name, quiet) {
  if (!quiet && !confirm("Delete /user/" + name + "?")) {
    return;
  }
  const result = $("files-result");
  const refused = (error) => showResult(result, false, "delete " + name + ": " + error.describe());
  if (await callApi(refused, "DELETE", storePath(name))) {
    if (!quiet) {
      showResult(result, true, "deleted " + name);
    }
    await listFiles();
  }
}

// Run saves the open file first (spec: "run the open file (saved first)").
async function runOpenFile() {
  if (scripting.writable && $("editor-text").value !== scripting.savedText) {
    if (!(await saveOpenFile())) {
      return;
    }
  }
  const file = "/user/" + scripting.openFile;
  const refused = (error) => scriptResult(false, "run " + file + ": " + error.describe());
  const reply = await callApi(refused, "POST", apiBase + "/script/run", { file: file });
  if (reply) {
    scriptResult(true, "run " + file + ": started");
    renderScript(reply);
    pollConsole();
  }
}

async function stopScript() {
  const refused = (error) => scriptResult(false, "stop: " + error.describe());
  const reply = await callApi(refused, "POST", apiBase + "/script/stop");
  if (reply) {
    scriptResult(true, "stop: stopped");
    renderScript(reply);
  }
}

function renderScript(script) {
  setText("script-file", script.running ? script.file : "no script runs" +
    (script.file ? " (last: " + script.file + ")" : ""));
  setText("script-error", script.error ? "error: " + script.error : "");
  setText("startup-script", script.startup ? script.startup + " (runs at power-on)"
    : "none (or not started at power-on: --no-script-autostart)");
  scripting.startup = script.startup;
  const choice = $("startup-choice");
  if ([...choice.options].some((o) => o.value === (script.startup || ""))) {
    choice.value = script.startup || "";
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

function setUpScripting() {
  $("file-new").addEventListener("submit", newFile);
  $("file-upload").elements.file.addEventListener("change", uploadFile);
  $("script-save").addEventListener("click", saveOpenFile);
  $("script-run").addEventListener("click", runOpenFile);
  $("script-stop").addEventListener("click", stopScript);
  $("console-clear").addEventListener("click", () => ($("console").textContent = ""));
  pollWhileShown("scripting", CONSOLE_POLL_MS, pollConsole);
  const showScripting = views.onShow.scripting;
  views.onShow.scripting = () => {
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
  setUpControl();
  setUpSim();
  setUpSettings();
  setUpDevices();
  system.info = loadSystemInfo();
  setUpScripting();
  pollWhileShown("system", SYSTEM_POLL_MS, pollSystem);
  $("banner-fsack").addEventListener("click", bannerFsack);
  setUpViews();
  loadScriptState();
  openStream(RECONNECT_MIN_MS);
}

main();
