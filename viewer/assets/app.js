// helm view: the page. Plain JS and SVG, no build step. Every value that came from the
// MOOSDB or a log is put in the page with textContent or setAttribute, never as markup.
"use strict";

const SVGNS = "http://www.w3.org/2000/svg";
const $ = (id) => document.getElementById(id);

const S = {
  info: null,
  run: 0,
  t: 0,
  vehicles: new Map(),
  trails: new Map(),
  objects: new Map(),
  vars: new Map(),
  appcasts: new Map(),
  view: { cx: 0, cy: 0, s: 2 },
  fitted: false,
  allTracks: [],
  frames: 0,
  dirty: true,
};

function el(tag, attrs, parent) {
  const e = document.createElementNS(SVGNS, tag);
  for (const k in attrs) e.setAttribute(k, attrs[k]);
  if (parent) parent.appendChild(e);
  return e;
}

function clear(node) {
  while (node.firstChild) node.removeChild(node.firstChild);
}

// A colour from the server (already CSS, or a MOOS-IvP name) if the browser knows it.
function color(c, dflt) {
  if (c === undefined || c === null || c === "") return dflt;
  return CSS.supports("color", c) || c === "none" ? c : dflt;
}

function size() {
  const r = $("map").getBoundingClientRect();
  return { w: r.width || 800, h: r.height || 600 };
}

function toScreen(x, y) {
  const { w, h } = size();
  return [w / 2 + (x - S.view.cx) * S.view.s, h / 2 - (y - S.view.cy) * S.view.s];
}

function fit(b) {
  if (!b) return;
  const { w, h } = size();
  const dx = Math.max(b[2] - b[0], 20), dy = Math.max(b[3] - b[1], 20);
  S.view.cx = (b[0] + b[2]) / 2;
  S.view.cy = (b[1] + b[3]) / 2;
  S.view.s = Math.min((w * 0.85) / dx, (h * 0.85) / dy);
  S.fitted = true;
}

function boundsOfScene() {
  let b = null;
  const grow = (x, y) => {
    if (!b) b = [x, y, x, y];
    b[0] = Math.min(b[0], x); b[1] = Math.min(b[1], y);
    b[2] = Math.max(b[2], x); b[3] = Math.max(b[3], y);
  };
  for (const v of S.vehicles.values()) grow(v.x, v.y);
  for (const o of S.objects.values()) for (const p of o.pts) grow(p[0], p[1]);
  return b;
}

// ---------------------------------------------------------------- frames

function applyFrame(f) {
  if (f.full) {
    S.vehicles.clear(); S.trails.clear(); S.objects.clear(); S.vars.clear(); S.appcasts.clear();
  }
  for (const v of f.vehicles) S.vehicles.set(v.name, v);
  for (const name in f.trails) {
    if (f.full || !S.trails.has(name)) S.trails.set(name, f.trails[name].slice());
    else {
      const tr = S.trails.get(name);
      for (const p of f.trails[name]) tr.push(p);
      if (tr.length > 8000) S.trails.set(name, tr.filter((_, i) => i % 2 === 0));
    }
  }
  for (const o of f.objects) S.objects.set(o.key, o);
  for (const k of f.removed) S.objects.delete(k);
  for (const k in f.vars) S.vars.set(k, f.vars[k]);
  for (const a of f.appcasts) S.appcasts.set(a.key, a);
  if (typeof f.skipped === "string") $("skipped").textContent = f.skipped;
  S.t = f.t;
  S.frames += 1;
  document.body.dataset.t = String(f.t);
  document.body.dataset.frames = String(S.frames);
  if (!S.fitted && (S.vehicles.size || S.objects.size)) fit(boundsOfScene());
  S.dirty = true;
  panels();
}

// ---------------------------------------------------------------- drawing

function niceStep(raw) {
  const p = Math.pow(10, Math.floor(Math.log10(raw)));
  for (const m of [1, 2, 5, 10]) if (m * p >= raw) return m * p;
  return 10 * p;
}

function drawGrid() {
  const g = $("grid");
  clear(g);
  const { w, h } = size();
  const step = niceStep(80 / S.view.s);
  const x0 = S.view.cx - w / 2 / S.view.s, x1 = S.view.cx + w / 2 / S.view.s;
  const y0 = S.view.cy - h / 2 / S.view.s, y1 = S.view.cy + h / 2 / S.view.s;
  for (let x = Math.ceil(x0 / step) * step; x <= x1; x += step) {
    const [sx] = toScreen(x, 0);
    el("line", { x1: sx, y1: 0, x2: sx, y2: h }, g);
    el("text", { x: sx + 2, y: 12 }, g).textContent = `${+x.toFixed(6)} m`;
  }
  for (let y = Math.ceil(y0 / step) * step; y <= y1; y += step) {
    const [, sy] = toScreen(0, y);
    el("line", { x1: 0, y1: sy, x2: w, y2: sy }, g);
    el("text", { x: 2, y: sy - 2 }, g).textContent = `${+y.toFixed(6)} m`;
  }
}

function pts(list) {
  return list.map((p) => toScreen(p[0], p[1]).map((v) => v.toFixed(1)).join(",")).join(" ");
}

// Labels placed so far in this picture (shapes' first, then vehicles'), as [left, top,
// right, bottom] in pixels.
let placed = [];

// A label's top edge, moved down a line at a time from `top` while its box would cover a
// label already placed: the points of several vehicles often share a spot (each one's
// next waypoint), and a vehicle sits on its waypoint when it arrives. The width is
// estimated (11 px text) rather than measured, to keep a frame cheap.
function place(left, top, text) {
  const w = text.length * 6.5, h = 15;
  for (let i = 0; i < 8; i++) {
    const hit = placed.some((r) => left < r[2] && r[0] < left + w && top < r[3] && r[1] < top + h);
    if (!hit) break;
    top += h;
  }
  placed.push([left, top, left + w, top + h]);
  return top;
}

// A shape's label beside its spot.
function label(g, x, y, text, c) {
  if (!text) return;
  const top = place(x + 6, y - 18, text);
  const t = el("text", { x: x + 6, y: top + 12, fill: color(c, "#ffffff"), class: "label" }, g);
  t.textContent = text;
}

function drawShape(o, parent) {
  const g = el("g", { class: "shape", "data-key": o.key, "data-kind": o.kind }, parent);
  const vs = o.vertex_size ?? (o.kind === "point" ? 4 : 2);
  const ew = o.edge_size ?? 1.5;
  const [x, y] = toScreen(o.pts[0][0], o.pts[0][1]);
  if (o.kind === "polygon" || o.kind === "seglist") {
    const fill = o.kind === "polygon" ? color(o.fill_color, "none") : "none";
    el(o.kind === "polygon" ? "polygon" : "polyline", {
      points: pts(o.pts), stroke: color(o.edge_color, o.kind === "polygon" ? "#ffd700" : "#f0f0f0"),
      "stroke-width": ew, fill, "fill-opacity": o.fill_transparency ?? 0.2,
    }, g);
    for (const p of o.pts) {
      const [px, py] = toScreen(p[0], p[1]);
      el("circle", { cx: px, cy: py, r: Math.max(vs / 2, 0.5), fill: color(o.vertex_color, "#ff4040") }, g);
    }
  } else if (o.kind === "circle") {
    el("circle", { cx: x, cy: y, r: Math.max(o.radius * S.view.s, 1), stroke: color(o.edge_color, "#ffd700"),
      "stroke-width": ew, fill: color(o.fill_color, "none"), "fill-opacity": o.fill_transparency ?? 0.2 }, g);
  } else if (o.kind === "marker") {
    const r = 6 * (o.scale ?? 1);
    const c = color(o.fill_color, "#ff8c00");
    const shape = {
      square: `${x - r},${y - r} ${x + r},${y - r} ${x + r},${y + r} ${x - r},${y + r}`,
      diamond: `${x},${y - r} ${x + r},${y} ${x},${y + r} ${x - r},${y}`,
      triangle: `${x},${y - r} ${x + r},${y + r} ${x - r},${y + r}`,
    }[o.marker];
    if (shape) el("polygon", { points: shape, fill: c, stroke: "#000" }, g);
    else if (o.marker === "kelp") {
      // pMarineViewer's kelp: a small star.
      const pts = [];
      for (let i = 0; i < 10; i++) {
        const a = (i * Math.PI) / 5, q = i % 2 ? r * 0.45 : r;
        pts.push(`${(x + q * Math.sin(a)).toFixed(1)},${(y - q * Math.cos(a)).toFixed(1)}`);
      }
      el("polygon", { points: pts.join(" "), fill: c, stroke: "#000" }, g);
    } else {
      el("circle", { cx: x, cy: y, r, fill: c, stroke: "#000" }, g);
      // efield: a plus inside the disc; gateway: a cross (what pMarineViewer draws in them).
      const d = r * 0.7;
      if (o.marker === "efield")
        el("path", { d: `M${x - d},${y}H${x + d}M${x},${y - d}V${y + d}`, stroke: "#000" }, g);
      else if (o.marker === "gateway")
        el("path", { d: `M${x - d},${y - d}L${x + d},${y + d}M${x + d},${y - d}L${x - d},${y + d}`, stroke: "#000" }, g);
    }
  } else {
    el("circle", { cx: x, cy: y, r: vs, fill: color(o.vertex_color, "#ffff00") }, g);
  }
  label(g, x, y, o.label, o.label_color);
}

// A vehicle's drawn length in pixels: to scale, but never too small to see.
function hullLength(v) {
  return Math.max((v.length || 4) * S.view.s, 16);
}

function hull(v) {
  const [cx, cy] = toScreen(v.x, v.y);
  const L = hullLength(v), W = L * 0.4;
  const a = (v.hdg * Math.PI) / 180;
  const f = [Math.sin(a), -Math.cos(a)], r = [Math.cos(a), Math.sin(a)];
  const body = [[0.5 * L, 0], [0.15 * L, 0.5 * W], [-0.5 * L, 0.5 * W], [-0.5 * L, -0.5 * W], [0.15 * L, -0.5 * W]];
  return body.map(([fw, rt]) => `${(cx + fw * f[0] + rt * r[0]).toFixed(1)},${(cy + fw * f[1] + rt * r[1]).toFixed(1)}`).join(" ");
}

function render() {
  if (!S.dirty) return;
  S.dirty = false;
  drawGrid();
  const at = $("alltracks");
  clear(at);
  S.allTracks.forEach((run, i) => {
    for (const name in run) {
      el("polyline", { points: pts(run[name]), fill: "none", stroke: i === S.run ? "#ffffff" : "#7fa8cc",
        "stroke-opacity": i === S.run ? 0.6 : 0.45, "stroke-width": 1, "data-run": i }, at);
    }
  });
  const sh = $("shapes");
  clear(sh);
  placed = [];
  for (const o of S.objects.values()) drawShape(o, sh);
  const tr = $("trails");
  clear(tr);
  for (const [name, list] of S.trails) {
    const v = S.vehicles.get(name);
    el("polyline", { points: pts(list), fill: "none", stroke: color(v && v.color, "#9ad0ff"),
      "stroke-width": 1.5, "stroke-opacity": 0.8, "data-name": name }, tr);
  }
  const vg = $("vehicles");
  clear(vg);
  for (const v of S.vehicles.values()) {
    const g = el("g", { class: "vehicle", "data-name": v.name, "data-x": v.x, "data-y": v.y, "data-hdg": v.hdg }, vg);
    el("polygon", { points: hull(v), fill: color(v.color, "#ffd700"), stroke: "#000", "stroke-width": 1 }, g);
    const [x, y] = toScreen(v.x, v.y);
    const text = `${v.name} ${(+v.spd).toFixed(1)} m/s`;
    // Clear of the hull whichever way it points (a long ship's reaches past 12 px).
    const left = x + Math.max(12, hullLength(v) / 2 + 4);
    const top = place(left, y - 8, text);
    const t = el("text", { x: left, y: top + 12, fill: "#ffffff", class: "vlabel" }, g);
    t.textContent = text;
  }
  // The time of the picture now drawn (frames arrive before the next paint draws them).
  document.body.dataset.drawn = String(S.t);
}

function loop() {
  render();
  requestAnimationFrame(loop);
}

// ---------------------------------------------------------------- panels

function row(tbody, cells) {
  const tr = document.createElement("tr");
  for (const c of cells) {
    const td = document.createElement("td");
    td.textContent = c;
    tr.appendChild(td);
  }
  tbody.appendChild(tr);
  return tr;
}

function panels() {
  const vb = $("vehtable").tBodies[0];
  clear(vb);
  for (const v of S.vehicles.values()) {
    row(vb, [v.name, (+v.x).toFixed(1), (+v.y).toFixed(1), (+v.hdg).toFixed(0), (+v.spd).toFixed(2), v.mode || ""]);
  }
  const tb = $("vars").tBodies[0];
  clear(tb);
  for (const k of [...S.vars.keys()].sort()) row(tb, [k, S.vars.get(k)]).dataset.var = k;
  const sel = $("appsel");
  const keys = [...S.appcasts.keys()].sort();
  if ([...sel.options].map((o) => o.value).join() !== keys.join()) {
    const cur = sel.value;
    clear(sel);
    for (const k of keys) {
      const o = document.createElement("option");
      o.value = k;
      o.textContent = k;
      sel.appendChild(o);
    }
    sel.value = keys.includes(cur) ? cur : keys.find((k) => k.startsWith("pHelmIvP")) || keys[0] || "";
  }
  const a = S.appcasts.get(sel.value);
  let text = a ? a.lines.join("\n") : "";
  if (a && a.config_warnings.length) text += "\n\nConfiguration warnings:\n" + a.config_warnings.join("\n");
  if (a && a.run_warnings.length) text += "\n\nRun warnings:\n" + a.run_warnings.join("\n");
  $("appcast").textContent = text;
  if (S.info && S.info.mode === "replay") $("clock").textContent = `${S.t.toFixed(1)} s`;
}

// ---------------------------------------------------------------- replay

const R = { inflight: false, want: null, playing: false, last: 0 };

function requestFrame(t) {
  R.want = t;
  if (R.inflight) return;
  R.inflight = true;
  const ask = R.want;
  fetch(`/api/frame?run=${S.run}&t=${ask}`)
    .then((r) => r.json())
    .then((f) => applyFrame(f))
    .catch((e) => { $("status").textContent = `error: ${e}`; })
    .finally(() => {
      R.inflight = false;
      if (R.want !== ask) requestFrame(R.want);
    });
}

function selectRun(i) {
  S.run = i;
  const run = S.info.runs[i];
  const sl = $("slider");
  sl.min = run.t0;
  sl.max = run.t1;
  sl.value = run.t1;
  $("skipped").textContent = run.skipped ? `${run.name}: ${run.skipped}` : "";
  for (const tr of $("runs").tBodies[0].rows) tr.classList.toggle("sel", +tr.dataset.run === i);
  fit(run.bounds);
  S.dirty = true;
  requestFrame(run.t1);
}

function play(now) {
  if (!R.playing) return;
  const sl = $("slider");
  const dt = R.last ? (now - R.last) / 1000 : 0;
  R.last = now;
  let t = +sl.value + dt * +$("speed").value;
  if (t >= +sl.max) { t = +sl.max; setPlaying(false); }
  sl.value = t;
  requestFrame(t);
  requestAnimationFrame(play);
}

function setPlaying(on) {
  R.playing = on;
  R.last = 0;
  $("play").textContent = on ? "❚❚" : "▶";
  if (on) requestAnimationFrame(play);
}

function startReplay(info) {
  $("controls").hidden = false;
  $("status").textContent = `replay: ${info.runs.length} run(s), ${info.runs.reduce((n, r) => n + r.lines, 0)} lines`;
  $("slider").addEventListener("input", () => requestFrame(+$("slider").value));
  $("play").addEventListener("click", () => {
    if (!R.playing && +$("slider").value >= +$("slider").max) $("slider").value = $("slider").min;
    setPlaying(!R.playing);
  });
  if (info.runs.length > 1) {
    $("runbox").hidden = false;
    const th = $("runs").tHead;
    const hr = document.createElement("tr");
    for (const c of info.table.columns) {
      const h = document.createElement("th");
      h.textContent = c;
      hr.appendChild(h);
    }
    th.appendChild(hr);
    info.table.rows.forEach((cells, i) => {
      const tr = row($("runs").tBodies[0], cells);
      tr.dataset.run = i;
      tr.addEventListener("click", () => selectRun(i));
    });
    fetch("/api/tracks").then((r) => r.json()).then((all) => { S.allTracks = all; S.dirty = true; });
  }
  selectRun(0);
}

// ---------------------------------------------------------------- live

function startLive(info) {
  const connect = () => {
    const ws = new WebSocket(`ws://${location.hostname}:${info.ws_port}/ws`);
    ws.onopen = () => { $("status").textContent = `live: ${info.db} — connected`; };
    ws.onmessage = (m) => applyFrame(JSON.parse(m.data));
    ws.onclose = () => {
      $("status").textContent = `live: ${info.db} — disconnected, retrying`;
      setTimeout(connect, 1000);
    };
  };
  connect();
  if (info.buttons.length) {
    $("buttonbox").hidden = false;
    info.buttons.forEach((labelText, i) => {
      const b = document.createElement("button");
      b.type = "button";
      b.textContent = labelText;
      b.dataset.button = i;
      b.addEventListener("click", () => {
        fetch(`/api/button/${i}`, { method: "POST", headers: { "X-Helm-View": "1" } })
          .then((r) => r.json())
          .then((r) => { $("pressed").textContent = `${r.button}: ${r.posted} posting(s) sent`; })
          .catch((e) => { $("pressed").textContent = `not sent: ${e}`; });
      });
      $("buttons").appendChild(b);
    });
  }
}

// ---------------------------------------------------------------- pan and zoom

function interaction() {
  const map = $("map");
  let drag = null;
  map.addEventListener("pointerdown", (e) => { drag = [e.clientX, e.clientY]; map.setPointerCapture(e.pointerId); });
  map.addEventListener("pointermove", (e) => {
    if (!drag) return;
    S.view.cx -= (e.clientX - drag[0]) / S.view.s;
    S.view.cy += (e.clientY - drag[1]) / S.view.s;
    drag = [e.clientX, e.clientY];
    S.dirty = true;
  });
  map.addEventListener("pointerup", () => { drag = null; });
  map.addEventListener("wheel", (e) => {
    e.preventDefault();
    const r = map.getBoundingClientRect();
    const { w, h } = size();
    const mx = S.view.cx + (e.clientX - r.left - w / 2) / S.view.s;
    const my = S.view.cy - (e.clientY - r.top - h / 2) / S.view.s;
    const k = Math.exp(-e.deltaY * 0.0015);
    S.view.s = Math.min(Math.max(S.view.s * k, 0.001), 1000);
    S.view.cx = mx - (e.clientX - r.left - w / 2) / S.view.s;
    S.view.cy = my + (e.clientY - r.top - h / 2) / S.view.s;
    S.dirty = true;
  }, { passive: false });
  window.addEventListener("resize", () => { S.dirty = true; });
  $("appsel").addEventListener("change", panels);
}

fetch("/api/info")
  .then((r) => r.json())
  .then((info) => {
    S.info = info;
    document.title = `helm view: ${info.title}`;
    $("title").textContent = info.title;
    interaction();
    if (info.mode === "replay") startReplay(info);
    else startLive(info);
    requestAnimationFrame(loop);
  })
  .catch((e) => { $("status").textContent = `error: ${e}`; });
