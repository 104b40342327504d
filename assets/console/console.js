// capflow live console: the page of capflow run|steady --serve and capflow view.
// Talks only to its own server (docs/usage.md, "The live console's API"); no CDN.
"use strict";

const params = new URLSearchParams(location.search);
let token = params.get("token") || sessionStorage.getItem("capflow_token") || "";
if (params.get("token")) {
  sessionStorage.setItem("capflow_token", token);
  history.replaceState(null, "", location.pathname);  // the token leaves the address bar
}

const $ = (id) => document.getElementById(id);
const PRESETS = { oblique: [36.25, 33.69], xy: [0, 90], xz: [0, 0], yz: [90, 0] };
const cam = { yaw: 36.25, pitch: 33.69, zoom: 1 };
const state = { run: null, revision: -1, control: null, fields: [], times: [], events: [],
                rows: [], columns: [], lastT: null, nextEvent: 0, frames: 0 };
window.capflow = { cam, state };  // for scripts and tests

function api(path, opts = {}) {
  opts.headers = Object.assign({ "X-Capflow-Token": token }, opts.headers || {});
  return fetch(path, opts);
}

// ---- the 3-D view -----------------------------------------------------------------------------

let inFlight = false, again = false, lastUrl = "";
function frameUrl() {
  const img = $("view");
  const w = Math.min(1280, Math.max(64, 2 * Math.round(img.clientWidth / 2) || 1280));
  const h = Math.max(64, 2 * Math.round(w * 9 / 32));
  const q = new URLSearchParams({ yaw: cam.yaw.toFixed(2), pitch: cam.pitch.toFixed(2),
    zoom: cam.zoom.toFixed(3), field: $("field").value, range: $("range").value,
    width: String(w), height: String(h) });
  if (!$("follow").checked && state.times.length) q.set("time", String(state.times[$("timeline").value]));
  return "api/frame?" + q.toString();
}
function requestFrame() {
  if (inFlight) { again = true; return; }
  inFlight = true; again = false;
  const url = frameUrl();
  api(url).then((r) => r.ok ? r.blob() : Promise.reject(r.status)).then((b) => {
    const old = $("view").src;
    $("view").src = URL.createObjectURL(b);
    if (old.startsWith("blob:")) URL.revokeObjectURL(old);
    lastUrl = url; state.frames += 1;
    $("view").dataset.url = url;
    $("view").dataset.frames = String(state.frames);
  }).catch(() => {}).finally(() => {
    inFlight = false;
    if (again) requestFrame();
  });
  $("camera").textContent = `yaw ${cam.yaw.toFixed(0)}°, pitch ${cam.pitch.toFixed(0)}°, zoom ${cam.zoom.toFixed(2)}`;
}

(function cameraControls() {
  const wrap = $("view-wrap");
  let drag = null;
  wrap.addEventListener("pointerdown", (e) => {
    drag = { x: e.clientX, y: e.clientY, yaw: cam.yaw, pitch: cam.pitch };
    wrap.setPointerCapture(e.pointerId);
  });
  wrap.addEventListener("pointermove", (e) => {
    if (!drag) return;
    cam.yaw = drag.yaw - (e.clientX - drag.x) * 0.4;
    cam.pitch = Math.max(-90, Math.min(90, drag.pitch + (e.clientY - drag.y) * 0.4));
    requestFrame();
  });
  const end = () => { drag = null; };
  wrap.addEventListener("pointerup", end);
  wrap.addEventListener("pointercancel", end);
  wrap.addEventListener("wheel", (e) => {
    e.preventDefault();
    cam.zoom = Math.max(0.05, Math.min(20, cam.zoom * Math.exp(-e.deltaY * 0.001)));
    requestFrame();
  }, { passive: false });
  document.querySelectorAll("button[data-view]").forEach((b) => b.addEventListener("click", () => {
    [cam.yaw, cam.pitch] = PRESETS[b.dataset.view];
    requestFrame();
  }));
  $("reset").addEventListener("click", () => {
    [cam.yaw, cam.pitch] = PRESETS.oblique; cam.zoom = 1; requestFrame();
  });
  $("field").addEventListener("change", requestFrame);
  $("range").addEventListener("change", requestFrame);
  $("follow").addEventListener("change", requestFrame);
  $("timeline").addEventListener("input", () => {
    $("follow").checked = false;
    $("timeline-t").textContent = "t = " + state.times[$("timeline").value];
    requestFrame();
  });
})();

// ---- state and progress ------------------------------------------------------------------------

function fmt(v, d = 4) { return v === null || v === undefined ? "–" : Number(v).toPrecision(d); }
function eta(s) {
  if (s === null || s < 0) return "";
  if (s < 120) return `, ETA ${s.toFixed(0)} s`;
  return `, ETA ${(s / 60).toFixed(1)} min`;
}
async function pollState() {
  try {
    const r = await api("api/state");
    if (!r.ok) throw r.status;
    const s = await r.json();
    state.run = s;
    const badge = $("badge");
    badge.textContent = s.state; badge.className = "badge " + s.state;
    $("progress").textContent = `t = ${fmt(s.t, 5)}  Ca = ${fmt(s.ca)}  D = ${fmt(s.D)}  ` +
      `steps ${s.steps}  ${s.steps_per_second ? s.steps_per_second.toFixed(1) + " steps/s" : ""}${eta(s.eta_seconds)}`;
    $("schedule").textContent = [s.schedule.now, s.schedule.next].filter(Boolean).join("; ");
    if (s.revision !== state.revision) await loadControl();
  } catch (e) {
    $("progress").textContent = "the console is not answering (" + e + ")";
  }
}

// ---- plots -------------------------------------------------------------------------------------

const markerPlugin = {
  id: "markers",
  afterDatasetsDraw(chart) {
    const x = chart.scales.x, ctx = chart.ctx, area = chart.chartArea;
    ctx.save();
    for (const e of state.events) {
      if (e.event !== "steady" && e.event !== "level" && e.event !== "edit") continue;
      if (typeof e.t !== "number" || e.t < x.min || e.t > x.max) continue;
      const px = x.getPixelForValue(e.t);
      ctx.strokeStyle = e.event === "steady" ? "#1565c0" : e.event === "edit" ? "#8e24aa" : "#f9a825";
      ctx.setLineDash([4, 3]);
      ctx.beginPath(); ctx.moveTo(px, area.top); ctx.lineTo(px, area.bottom); ctx.stroke();
    }
    ctx.restore();
  },
};
const chart = new Chart($("chart"), {
  type: "line",
  data: { datasets: [{ label: "D", data: [], borderColor: "#00796b", pointRadius: 0, borderWidth: 1.5 }] },
  options: { animation: false, parsing: false, normalized: true, maintainAspectRatio: false,
             scales: { x: { type: "linear", title: { display: true, text: "t G" } } },
             plugins: { legend: { display: true } } },
  plugins: [markerPlugin],
});
let view = null;  // [tmin, tmax] when zoomed
function redrawChart() {
  const q = $("quantity").value, ti = state.columns.indexOf("t"), qi = state.columns.indexOf(q);
  if (ti < 0 || qi < 0) return;
  const ds = chart.data.datasets[0];
  ds.label = q === "ca" ? "Ca" : q;
  ds.data = state.rows.map((r) => ({ x: r[ti], y: r[qi] }));
  chart.options.scales.x.min = view ? view[0] : undefined;
  chart.options.scales.x.max = view ? view[1] : undefined;
  chart.update("none");
  $("chart").dataset.rows = String(state.rows.length);
}
async function pollSeries() {
  try {
    const since = state.lastT === null ? "" : "?since=" + state.lastT;
    const r = await api("api/timeseries" + since);
    if (!r.ok) return;
    const s = await r.json();
    if (s.columns.length) state.columns = s.columns;
    if (s.rows.length) {
      const ti = state.columns.indexOf("t");
      state.rows.push(...s.rows);
      state.lastT = s.rows[s.rows.length - 1][ti];
      redrawChart();
    }
  } catch (e) { /* the next poll retries */ }
}
$("quantity").addEventListener("change", redrawChart);
$("zoom-reset").addEventListener("click", () => { view = null; redrawChart(); });
(function chartZoom() {
  const c = $("chart");
  c.addEventListener("wheel", (e) => {
    e.preventDefault();
    const x = chart.scales.x, at = x.getValueForPixel(e.offsetX);
    const f = Math.exp(e.deltaY * 0.002);
    view = [at - (at - x.min) * f, at + (x.max - at) * f];
    redrawChart();
  }, { passive: false });
  let pan = null;
  c.addEventListener("pointerdown", (e) => { pan = { x: e.offsetX, min: chart.scales.x.min, max: chart.scales.x.max }; });
  c.addEventListener("pointermove", (e) => {
    if (!pan) return;
    const x = chart.scales.x, per = (pan.max - pan.min) / (x.right - x.left);
    const d = (e.offsetX - pan.x) * per;
    view = [pan.min - d, pan.max - d];
    redrawChart();
  });
  c.addEventListener("pointerup", () => { pan = null; });
  c.addEventListener("pointerleave", () => { pan = null; });
})();
function download(name, href) {
  const a = document.createElement("a");
  a.href = href; a.download = name; document.body.appendChild(a); a.click(); a.remove();
}
$("export-png").addEventListener("click", () => download("capflow_" + $("quantity").value + ".png", chart.toBase64Image()));
$("export-csv").addEventListener("click", () => {
  const text = state.columns.join(",") + "\n" + state.rows.map((r) => r.join(",")).join("\n") + "\n";
  download("timeseries.csv", URL.createObjectURL(new Blob([text], { type: "text/csv" })));
});

// ---- events ------------------------------------------------------------------------------------

function describe(e) {
  const t = typeof e.t === "number" ? `t = ${fmt(e.t, 5)}: ` : "";
  if (e.event === "edit") {
    const parts = [];
    for (const [k, v] of Object.entries(e.applied || {})) parts.push(`${k} ${JSON.stringify(v.old)} → ${JSON.stringify(v.new)}`);
    for (const [k, v] of Object.entries(e.refused || {})) parts.push(`${k} refused: ${v.reason}`);
    if (e.errors) parts.push("refused: " + JSON.stringify(e.errors));
    return t + "edit " + parts.join("; ");
  }
  return t + e.event + (e.message ? ": " + e.message : "") + (e.reason ? ": " + e.reason : "");
}
async function pollEvents() {
  try {
    const r = await api("api/events?since=" + state.nextEvent);
    if (!r.ok) return;
    const s = await r.json();
    state.nextEvent = s.next;
    const list = $("event-list");
    for (const e of s.events) {
      if (typeof e !== "object" || e === null) continue;
      state.events.push(e);
      const li = document.createElement("li");
      const refused = e.event === "edit" && (e.refused && Object.keys(e.refused).length || e.accepted === false);
      li.className = refused ? "refused" : e.event;
      li.textContent = describe(e);
      list.appendChild(li);
      list.scrollTop = list.scrollHeight;
    }
    if (s.events.length) chart.update("none");
  } catch (e) { /* retried */ }
}

// ---- the timeline ------------------------------------------------------------------------------

async function pollSurfaces() {
  try {
    const r = await api("api/surfaces");
    if (!r.ok) return;
    const s = await r.json();
    if (s.times.length === state.times.length) return;
    state.times = s.times;
    const tl = $("timeline");
    tl.disabled = s.times.length === 0;
    tl.max = String(Math.max(0, s.times.length - 1));
    if ($("follow").checked) tl.value = tl.max;
    $("timeline-t").textContent = s.times.length ? `${s.times.length} saved surfaces` : "no saved surfaces";
  } catch (e) { /* retried */ }
}

// ---- steering ----------------------------------------------------------------------------------

function valueAt(obj, path) {
  let v = obj;
  for (const k of path.split(".")) { if (v === null || typeof v !== "object") return undefined; v = v[k]; }
  return v;
}
function patchFor(path, value) {
  const keys = path.split("."), patch = {};
  let o = patch;
  keys.forEach((k, i) => { if (i === keys.length - 1) o[k] = value; else o = o[k] = {}; });
  return patch;
}
function showIssues(issues, fallback) {
  document.querySelectorAll(".msg[data-for]").forEach((m) => { m.textContent = ""; m.className = "msg"; });
  for (const i of issues) {
    const root = i.path.split(/[.[]/)[0];
    const m = document.querySelector(`.msg[data-for="${i.path}"]`) ||
              document.querySelector(`.msg[data-for="${root}"]`) || fallback;
    m.className = "msg"; m.textContent = (i.path ? i.path + ": " : "") + i.message;
  }
}
async function send(patch, near) {
  const msg = $("steer-msg");
  const r = await api("api/control", { method: "POST", headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ revision: state.revision, patch }) });
  let body = {};
  try { body = await r.json(); } catch (e) { /* not JSON */ }
  if (r.status === 200) {
    showIssues([], msg);
    const ok = near || msg;
    ok.className = "msg ok"; ok.textContent = `saved as revision ${body.revision}; the run applies it at its next step`;
    await loadControl();
  } else if (r.status === 409) {
    msg.className = "msg"; msg.textContent = "the control file changed meanwhile (revision " + body.revision + "): values reloaded, try again";
    await loadControl();
  } else {
    showIssues(body.issues || [{ path: "", message: body.error || ("error " + r.status) }], near || msg);
  }
  return r.status;
}
window.capflow.send = send;

async function loadControl() {
  const r = await api("api/control");
  if (!r.ok) return;
  const c = await r.json();
  state.revision = c.revision;
  state.control = c.control;
  $("revision").textContent = c.control ? `control file revision ${c.revision}` : (c.error || "");
  if (state.fields.length === 0) buildFields(c.fields);
  for (const f of state.fields) {
    const input = document.querySelector(`[data-path="${f.path}"]`);
    if (!input || document.activeElement === input) continue;
    const v = valueAt(c.control, f.path);
    if (input.type === "checkbox") input.checked = v === undefined ? f.default === "true" : !!v;
    else input.value = v === undefined ? f.default.replace(/^"|"$/g, "") : (typeof v === "string" ? v : JSON.stringify(v));
  }
}
function buildFields(fields) {
  state.fields = fields.filter((f) => f.path !== "ca" && !f.path.startsWith("run."));
  const box = $("fields");
  box.textContent = "";
  for (const f of state.fields) {
    const row = document.createElement("div");
    row.className = "field";
    const label = document.createElement("label");
    label.textContent = f.path; label.title = f.doc + (f.unit ? ` [${f.unit}]` : "") + "; valid: " + f.valid;
    const input = document.createElement("input");
    input.dataset.path = f.path;
    input.type = f.type === "boolean" ? "checkbox" : "text";
    input.title = "valid: " + f.valid;
    const apply = document.createElement("button");
    apply.textContent = "apply";
    const msg = document.createElement("span");
    msg.className = "msg"; msg.dataset.for = f.path;
    apply.addEventListener("click", () => {
      let v;
      if (input.type === "checkbox") v = input.checked;
      else { try { v = JSON.parse(input.value); } catch (e) { v = input.value; } }
      send(patchFor(f.path, v), msg);
    });
    row.append(label, input, apply, msg);
    box.appendChild(row);
  }
}
$("pause").addEventListener("click", () => send({ run: { state: "paused" } }));
$("resume").addEventListener("click", () => send({ run: { state: "running" } }));
$("stop").addEventListener("click", () => send({ run: { state: "stopped" } }));
$("checkpoint").addEventListener("click", async () => {
  if (valueAt(state.control, "run.checkpoint_now") === true) await send({ run: { checkpoint_now: false } });
  send({ run: { checkpoint_now: true } });
});
$("seg-apply").addEventListener("click", () => {
  const kind = $("seg-kind").value, x = parseFloat($("seg-ca").value);
  const by = parseFloat($("seg-by").value), hold = parseFloat($("seg-hold").value);
  const holdv = isNaN(hold) ? "steady" : hold;
  let ca;
  if (kind === "hold") ca = isNaN(hold) ? x : [{ ca: x, hold: hold }];
  else if (kind === "steady") ca = [{ ca: x, hold: "steady" }];
  else if (kind === "step") ca = [{ steps: { to: x, by: by, hold: holdv } }];
  else ca = [{ ramp: { to: x, rate: by } }];
  send({ ca }, document.querySelector('.msg[data-for="ca"]'));
});

// ---- the loops ---------------------------------------------------------------------------------

async function tick() {
  await pollState();
  const live = state.run && state.run.state === "running";
  if ($("follow").checked && (live || state.frames === 0)) requestFrame();
}
loadControl();
tick(); pollSeries(); pollEvents(); pollSurfaces();
setInterval(tick, 250);
setInterval(pollSeries, 250);
setInterval(pollEvents, 500);
setInterval(pollSurfaces, 2000);
