// The live page: server-sent snapshots drawn as a top-down radar and a table. Every id is
// set with textContent (never markup), so an id is shown as text, whatever it holds.
"use strict";
const SVG = "http://www.w3.org/2000/svg";
const COLOUR = { ENGAGED: "#22aa22", ENGAGING: "#e6a800", DISENGAGING: "#e6a800",
                 DISENGAGED: "#dd2222", UNKNOWN: "#999999" };
const GROUP = "#bb33bb";
const PLACE = "#1a80ff";  // where the robot should stand
const radar = document.getElementById("radar");
const connection = document.getElementById("connection");

function el(name, attrs, parent) {
  const node = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, v);
  parent.appendChild(node);
  return node;
}
// Base frame (x ahead, y left) to the screen (up, left): sx = -y, sy = -x, times the zoom:
// the marks keep their size on screen while a scene within 2 m is spread over the radar.
let zoom = 1;
const sx = (p) => -p.y * zoom, sy = (p) => -p.x * zoom;

// Where the robot should stand (a place: x, y, yaw in radians): a triangle pointing the
// way to face.
function place(p, cls, id) {
  const shape = el("g", { class: cls, "data-id": id,
                          transform: `translate(${sx(p)} ${sy(p)}) rotate(${-(p.yaw * 180) / Math.PI - 90})` }, radar);
  el("polygon", { points: "0.3,0 -0.15,0.15 -0.15,-0.15", fill: PLACE, "fill-opacity": 0.85 }, shape);
}
const at2 = (p) => `(${p.x.toFixed(1)}, ${p.y.toFixed(1)})`;

// Where a label goes: beside its person, else the first free line below it (a line is
// 0.4 high at font size 0.3, a character about 0.17 wide), so that the names of people
// standing close never overlap.
function labelSpot(x, y, width, placed) {
  for (let k = 0; k < 40; k++) {
    const top = y + 0.4 * k;
    const free = placed.every((b) => x >= b.x + b.w || b.x >= x + width ||
                                      top - 0.4 >= b.y || b.y - 0.4 >= top);
    if (free) {
      placed.push({ x, y: top, w: width });
      return [x, top];
    }
  }
  return [x, y];
}

function draw(model) {
  document.getElementById("frame").textContent = "frame " + model.frame;
  const people = model.people;
  // Zoomed to the people (at least 2 m around the robot), the marks at the size they have
  // on a 4 m radar: someone at 0.6 m is drawn apart from the robot and the group, not on them.
  const far = Math.max(2, ...people.map((p) => Math.hypot(p.x, p.y) + 1));
  const r = Math.min(Math.ceil(far), 50), view = Math.max(r, 4);
  zoom = view / r;
  radar.setAttribute("viewBox", `${-view} ${-view} ${2 * view} ${2 * view}`);
  radar.replaceChildren();
  for (let ring = 1; ring <= r; ring++)
    el("circle", { cx: 0, cy: 0, r: ring * zoom, fill: "none", stroke: "#e3e3e3", "stroke-width": 0.02 }, radar);
  const at = Object.fromEntries(people.map((p) => [p.id, p]));
  at[""] = { x: 0, y: 0 };
  for (const g of model.gazing) {
    const a = at[g.sender], b = at[g.receiver];
    if (!a || !b) continue;
    el("line", { x1: sx(a), y1: sy(a), x2: sx(b), y2: sy(b), stroke: "#5577cc",
                 "stroke-width": 0.03, "stroke-dasharray": g.mutual ? "" : "0.1 0.08",
                 class: "gaze" }, radar);
  }
  for (const g of model.groups) {
    const c = { x: g.centre.x, y: g.centre.y };
    const shape = el("g", { class: "group", "data-id": g.id, "data-robot": g.robot }, radar);
    el("circle", { cx: sx(c), cy: sy(c), r: 0.12, fill: GROUP, "fill-opacity": 0.3,
                   stroke: GROUP, "stroke-width": 0.04 }, shape);
    for (const m of g.members.concat(g.robot ? [""] : [])) {
      const p = at[m];
      if (p) el("line", { x1: sx(c), y1: sy(c), x2: sx(p), y2: sy(p), stroke: GROUP,
                          "stroke-width": 0.025 }, shape);
    }
    if (g.join) place(g.join, "join", g.id);
  }
  for (const g of model.greetings || []) place(g.place, "greet", g.body_id);
  el("polygon", { points: "0,-0.25 0.18,0.15 -0.18,0.15", fill: "#223", class: "robot" }, radar);
  el("text", { x: 0.25, y: 0.35, "font-size": 0.3, fill: "#223", class: "robot-label" },
     radar).textContent = "robot";
  const placed = [];  // label boxes drawn: people standing close get labels apart
  for (const p of people) {
    const colour = COLOUR[p.level] || COLOUR.UNKNOWN;
    const shape = el("g", { class: "person", "data-id": p.id, "data-level": p.level,
                            transform: `translate(${sx(p)} ${sy(p)}) rotate(${-p.heading_deg - 90})` }, radar);
    const t = (p.threshold_deg * Math.PI) / 180, len = 1.2;
    el("path", { d: `M0 0 L${len * Math.cos(t)} ${len * Math.sin(t)} A${len} ${len} 0 0 0 ${len * Math.cos(t)} ${-len * Math.sin(t)} Z`,
                 fill: colour, "fill-opacity": 0.18, stroke: colour, "stroke-width": 0.01,
                 class: "cone" }, shape);
    el("line", { x1: 0, y1: 0, x2: 0.45, y2: 0, stroke: colour, "stroke-width": 0.06 }, shape);
    el("circle", { cx: 0, cy: 0, r: 0.14, fill: colour }, shape);
    const name = p.id;
    const [lx, ly] = labelSpot(sx(p) + 0.2, sy(p) - 0.2, 0.17 * name.length, placed);
    const label = el("text", { x: lx, y: ly, "font-size": 0.3, fill: "#222",
                               class: "label" }, radar);
    label.textContent = name;
  }
  const rows = document.querySelector("#people tbody");
  rows.replaceChildren();
  const groupOf = {};
  for (const g of model.groups) for (const m of g.members) groupOf[m] = g.id + (g.robot ? " +robot" : "");
  for (const p of people) {
    const row = rows.insertRow();
    const cells = [p.id, p.level, p.facing ? "yes" : "no",
                   p.angle_deg === null ? "-" : p.angle_deg.toFixed(1),
                   p.distance_m === null ? "-" : p.distance_m.toFixed(2), groupOf[p.id] || "-"];
    cells.forEach((text, i) => {
      const cell = row.insertCell();
      cell.textContent = text;
      if (i === 1) cell.className = "level " + p.level;
    });
  }
  const list = document.getElementById("groups");
  list.replaceChildren();
  for (const g of model.groups) {
    const item = document.createElement("li");
    const join = g.robot ? "" : g.join ? `; join at ${at2(g.join)}` : "; no room to join";
    item.textContent = `group ${g.id}: ${g.members.join(", ")}${g.robot ? " and the robot" : ""}${join}`;
    list.appendChild(item);
  }
  for (const g of model.greetings || []) {
    const item = document.createElement("li");
    item.textContent = `greet ${g.body_id} at ${at2(g.place)}`;
    list.appendChild(item);
  }
  const notes = [];
  if (model.not_drawn) notes.push(`${model.not_drawn} more people not drawn (the ${people.length} nearest are)`);
  const others = Object.entries(model.elsewhere);
  if (!people.length && others.length)
    notes.push("nobody in this frame; people are tracked in " +
               others.map(([f, n]) => `${f} (${n})`).join(", ") + ": view --base-frame " + others[0][0]);
  document.getElementById("note").textContent = notes.join("; ");
  if (model.service !== "live") setConnection("disconnected", "disconnected: no service answers");
  else if (model.input) setConnection("held", "connected; " + model.input);
  else setConnection("connected", "connected");
}

function setConnection(state, text) {
  connection.className = state;
  connection.textContent = text;
}

const source = new EventSource("events");
source.onmessage = (event) => draw(JSON.parse(event.data));
source.onerror = () => setConnection("disconnected", "disconnected: the view is not reachable");
