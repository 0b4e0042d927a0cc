// SPDX-License-Identifier: BSD-3-Clause
// The live view's drawing of the physics scene (--physics mujoco or
// socket:PATH; docs/web.md): the jaws, the bodies and the contacts from
// their poses (GET .../scene), seen from the side (x across, z up, mm),
// redrawn as the event stream brings states. Without a scene (the engine
// null) the drawing stays hidden and is not asked for again.
"use strict";

const SCENE_NS = "http://www.w3.org/2000/svg";
// at most this often (ms): a state comes every 100 ms or so
const SCENE_MIN_INTERVAL_MS = 100;
const SCENE_MARGIN_MM = 15;
const SCENE_MIN_SPAN_MM = 120;
// a finger drawn from its frame down this far (the pose has no shape)
const SCENE_FINGER_MM = 45;
// a contact's force drawn as a line of this many mm per N, at most
const SCENE_MM_PER_N = 0.5;
const SCENE_FORCE_LINE_MAX_MM = 30;

const scene = { busy: false, last: 0, absent: false };

function sceneElement(name, attrs, parent) {
  const el = document.createElementNS(SCENE_NS, name);
  for (const [key, value] of Object.entries(attrs)) {
    el.setAttribute(key, String(value));
  }
  parent.appendChild(el);
  return el;
}

function sceneIsFinger(body) {
  return /finger|^wsg_(left|right)$/.test(body.name);
}

// The view box: every body but the world, the ground, a margin.
function sceneBounds(bodies) {
  let minX = -SCENE_MIN_SPAN_MM / 2, maxX = SCENE_MIN_SPAN_MM / 2, minZ = 0, maxZ = 0;
  for (const b of bodies) {
    minX = Math.min(minX, b.pos_mm[0]);
    maxX = Math.max(maxX, b.pos_mm[0]);
    minZ = Math.min(minZ, b.pos_mm[2] - (sceneIsFinger(b) ? SCENE_FINGER_MM : 0));
    maxZ = Math.max(maxZ, b.pos_mm[2]);
  }
  maxZ = Math.max(maxZ, minZ + SCENE_MIN_SPAN_MM / 2);
  return [minX - SCENE_MARGIN_MM, -maxZ - SCENE_MARGIN_MM,
    maxX - minX + 2 * SCENE_MARGIN_MM, maxZ - minZ + 2 * SCENE_MARGIN_MM];
}

function sceneDrawBody(svg, body) {
  const x = body.pos_mm[0], y = -body.pos_mm[2];
  const kind = sceneIsFinger(body) ? "finger" : body.free ? "free" : body.mocap ? "mocap" : "fixed";
  const g = sceneElement("g", { class: "scene-body scene-" + kind, "data-name": body.name }, svg);
  if (kind === "finger") {
    sceneElement("rect", { x: x - 2, y: y, width: 4, height: SCENE_FINGER_MM }, g);
  } else {
    sceneElement("circle", { cx: x, cy: y, r: 2.5 }, g);
  }
  // a finger's name under its bar, the others' beside their dot
  const at = kind === "finger" ? { x: x, y: y + SCENE_FINGER_MM + 5, "text-anchor": "middle" }
    : { x: x + 4, y: y - 3 };
  sceneElement("text", at, g).textContent = body.name;
}

function sceneDrawContact(svg, contact) {
  const x = contact.pos_mm[0], y = -contact.pos_mm[2];
  const g = sceneElement("g", { class: "scene-contact", "data-a": contact.a, "data-b": contact.b },
    svg);
  sceneElement("circle", { cx: x, cy: y, r: 1.5 }, g);
  const length = Math.min(contact.normal_n * SCENE_MM_PER_N, SCENE_FORCE_LINE_MAX_MM);
  sceneElement("line", { x1: x, y1: y, x2: x + contact.normal[0] * length,
    y2: y - contact.normal[2] * length }, g);
}

function sceneRender(data) {
  const svg = document.getElementById("scene");
  const bodies = data.bodies.filter((b) => b.name !== "world");
  svg.replaceChildren();
  svg.setAttribute("viewBox", sceneBounds(bodies).map((v) => v.toFixed(1)).join(" "));
  sceneElement("line", { class: "scene-ground", x1: -1000, y1: 0, x2: 1000, y2: 0 }, svg);
  bodies.forEach((b) => sceneDrawBody(svg, b));
  data.contacts.filter((c) => c.normal_n > 0).forEach((c) => sceneDrawContact(svg, c));
  const text = data.engine + ": jaws " + data.jaws.width_mm.toFixed(2) + " mm, " +
    data.jaws.force_n.toFixed(1) + " N, " + data.contacts.length + " contacts";
  document.getElementById("scene-text").textContent =
    data.fault ? text + "; the plant is lost: " + data.fault : text;
  document.getElementById("scene-view").hidden = false;
}

async function sceneFetch() {
  scene.busy = true;
  scene.last = Date.now();
  try {
    const reply = await fetch(apiBase + "/scene");
    const data = reply.ok ? await reply.json() : null;
    if (data && data.engine === null) {
      scene.absent = true; // no scene in this run: none comes later
    } else if (data) {
      sceneRender(data);
    }
  } catch (error) {
    // the stream's own banner says the server is gone; the next state retries
  } finally {
    scene.busy = false;
  }
}

document.addEventListener("wsgsim-state", () => {
  if (!scene.absent && !scene.busy && Date.now() - scene.last >= SCENE_MIN_INTERVAL_MS) {
    sceneFetch();
  }
});
