#pragma once
// The replay page (replay.cpp) as text, apart from the code that fills it in.
namespace st::arm {

// The page around its data D: a stylesheet, the controls, two views, the timeline and the STOP
// list, and the script that draws them from D. Everything inline (no external URL).
inline constexpr const char* kPageHead = R"HTML(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>stsim arm replay</title>
<style>
body{background:#fafafa;color:#222;font:13px sans-serif;margin:10px}
h1{font-size:15px;margin:0 0 4px}
.views{display:flex;gap:10px}
.view{flex:1;border:1px solid #bbb;background:#fff}
.view h2,.tl h2{font-size:12px;margin:2px 6px;font-weight:normal;color:#555}
svg{display:block}
.controls{margin:6px 0}
.controls input[type=range]{width:45%;vertical-align:middle}
.shape.cause{stroke:#d62728!important;fill:#d62728!important;opacity:1!important;fill-opacity:1!important;stroke-opacity:1!important}
.tl{border:1px solid #bbb;background:#fff;margin-top:8px}
table{border-collapse:collapse;margin-top:8px}
td,th{border-bottom:1px solid #ddd;padding:2px 8px;text-align:left}
tr.stop{cursor:pointer}
tr.stop:hover{background:#fde}
#status{white-space:pre;font-family:monospace;margin-top:4px}
.key span{display:inline-block;width:12px;height:10px;margin:0 3px 0 10px;vertical-align:middle}
</style></head><body>
<h1 id="title"></h1>
<div class="controls"><button id="play">play</button>
<button id="prev" title="previous STOP">&#9664; STOP</button><button id="next" title="next STOP">STOP &#9654;</button>
<input id="scrub" type="range" min="0" value="0" step="1">
<label>speed <select id="speed"><option>0.1</option><option selected>0.25</option><option>1</option><option>4</option></select>x</label>
<span id="clock"></span></div>
<div class="views">
<div class="view"><h2>top view (x right, y up)</h2><svg id="top"></svg></div>
<div class="view"><h2>side view, from -y (x right, z up)</h2><svg id="side"></svg></div>
</div>
<div id="status"></div>
<div class="tl"><h2>timeline: per arm, collision monitor (upper band) and persons (lower band); &#9650; a STOP, click to see it
<span class="key"><span style="background:#f0a020"></span>WARN (hit within the look-ahead)<span style="background:#d62728"></span>STOP
<span style="background:#e6d23c"></span>person: scaled<span style="background:#8e44ad"></span>person: STOP</span></h2>
<svg id="timeline"></svg></div>
<table id="stoplist"><thead><tr><th>STOP</th><th>t s</th><th>arm</th><th>rule</th><th>cause pair</th><th>distance m</th><th>TTC s</th></tr></thead><tbody></tbody></table>
<script>
const D = )HTML";
inline constexpr const char* kPageTail = R"HTML(;
const NS = 'http://www.w3.org/2000/svg';
const armColour = ['#1f77b4', '#2ca02c', '#9467bd', '#8c564b', '#17becf', '#7f7f7f', '#bcbd22', '#ff7f0e'];
const nC = D.cap_arm.length, nP = D.parts.length;
function el(tag, attrs, parent) {
  const e = document.createElementNS(NS, tag);
  for (const k in attrs) e.setAttribute(k, attrs[k]);
  if (parent) parent.appendChild(e);
  return e;
}
const fmt = (x, n) => (x === null || x === undefined) ? 'inf' : (+x).toFixed(n);
// where obstacle o is at time t (moving ones at constant velocity from t = 0)
function obstacleShift(o, t) { return [o.v[0] * t, o.v[1] * t, o.v[2] * t]; }
const moving = D.obs.map(o => o.v[0] !== 0 || o.v[1] !== 0 || o.v[2] !== 0);
// the views' extent: every pose of every frame, the obstacles over the run
const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
function grow(p, r) { for (let k = 0; k < 3; ++k) { lo[k] = Math.min(lo[k], p[k] - r); hi[k] = Math.max(hi[k], p[k] + r); } }
D.fc.forEach(f => { for (let i = 0; i < nC; ++i) { grow([f[6*i]/1000, f[6*i+1]/1000, f[6*i+2]/1000], D.cap_r[i]); grow([f[6*i+3]/1000, f[6*i+4]/1000, f[6*i+5]/1000], D.cap_r[i]); } });
D.fp.forEach(f => { for (let k = 0; k < f.length; k += 1 + 6 * nP) for (let j = 0; j < nP; ++j) { const q = k + 1 + 6 * j;
  grow([f[q]/1000, f[q+1]/1000, f[q+2]/1000], D.part_r[j]); grow([f[q+3]/1000, f[q+4]/1000, f[q+5]/1000], D.part_r[j]); } });
D.obs.forEach((o, k) => { for (const at of moving[k] ? [0, D.t_end] : [0]) { const s = obstacleShift(o, at);
  const pts = o.k === 's' ? [o.c] : o.k === 'c' ? [o.a, o.b] : o.p;
  for (const p of pts) grow([p[0] + s[0], p[1] + s[1], p[2] + s[2]], o.r || 0); } });
if (!isFinite(lo[0])) { lo.fill(-1); hi.fill(1); }
const VIEWS = {top: [0, 1], side: [0, 2]};
const view = {};
// one view: an SVG in world metres (y flipped), a shape per capsule, obstacle and person part
function buildView(id) {
  const [u, w] = VIEWS[id], svg = document.getElementById(id), pad = 0.05;
  const x0 = lo[u] - pad, x1 = hi[u] + pad, y0 = lo[w] - pad, y1 = hi[w] + pad;
  svg.setAttribute('viewBox', `${x0} ${-y1} ${x1 - x0} ${y1 - y0}`);
  const width = svg.parentNode.clientWidth - 2;
  svg.setAttribute('width', width);
  svg.setAttribute('height', Math.min(560, width * (y1 - y0) / (x1 - x0)));
  const g = el('g', {transform: 'scale(1,-1)'}, svg);
  // a floor grid every 0.25 m
  const grid = el('g', {stroke: '#eee', 'stroke-width': 0.003}, g);
  for (let x = Math.ceil(x0 * 4) / 4; x <= x1; x += 0.25) el('line', {x1: x, y1: y0, x2: x, y2: y1}, grid);
  for (let y = Math.ceil(y0 * 4) / 4; y <= y1; y += 0.25) el('line', {x1: x0, y1: y, x2: x1, y2: y}, grid);
  el('line', {x1: 0, y1: 0, x2: 0.1, y2: 0, stroke: '#d62728', 'stroke-width': 0.006}, g);
  el('line', {x1: 0, y1: 0, x2: 0, y2: 0.1, stroke: w === 1 ? '#2ca02c' : '#1f77b4', 'stroke-width': 0.006}, g);
  const v = {u, w, g, obs: [], caps: [], parts: []};
  // obstacles far from the eye first (top: the lowest; side: the farthest in +y), so that a small
  // one on a large one (a tool on the table) shows
  const depth = o => { const pts = o.k === 's' ? [o.c] : o.k === 'c' ? [o.a, o.b] : o.p, r = o.r || 0;
    return id === 'top' ? Math.max(...pts.map(p => p[2])) + r : -Math.min(...pts.map(p => p[1])) + r; };
  const order = D.obs.map((o, k) => k).sort((a, b) => depth(D.obs[a]) - depth(D.obs[b]));
  v.obs = new Array(D.obs.length);
  order.forEach(k => {
    const o = D.obs[k];
    const base = {class: 'shape obstacle', fill: moving[k] ? '#e8b84a' : '#b0b0b0', stroke: moving[k] ? '#b8860b' : '#6e6e6e',
                  'fill-opacity': 0.55};
    let e;
    if (o.k === 's') e = el('circle', Object.assign(base, {cx: o.c[u], cy: o.c[w], r: o.r, 'stroke-width': 0.004}), g);
    else if (o.k === 'c') e = el('line', Object.assign(base, {x1: o.a[u], y1: o.a[w], x2: o.b[u] + 1e-6, y2: o.b[w], stroke: base.fill,
                              'stroke-opacity': 0.7, 'stroke-width': 2 * o.r, 'stroke-linecap': 'round'}), g);
    else e = el('polygon', Object.assign(base, {points: hull(o.p.map(p => [p[u], p[w]])).join(' '), 'stroke-width': 0.004}), g);
    const title = el('title', {}, e); title.textContent = 'obstacle:' + o.n;
    v.obs[k] = e;
  });
  for (let p = 0; p < D.persons.length; ++p) {
    const row = [];
    for (let j = 0; j < nP; ++j) {
      const e = el('line', {class: 'shape person', stroke: '#d81b9a', opacity: 0.75, 'stroke-width': 2 * D.part_r[j], 'stroke-linecap': 'round'}, g);
      el('title', {}, e).textContent = D.persons[p] + '/' + D.parts[j];
      row.push(e);
    }
    v.parts.push(row);
  }
  for (let i = 0; i < nC; ++i) {
    const e = el('line', {class: 'shape capsule', stroke: armColour[D.cap_arm[i] % armColour.length], opacity: 0.85,
                          'stroke-width': 2 * D.cap_r[i], 'stroke-linecap': 'round'}, g);
    el('title', {}, e).textContent = D.arms[D.cap_arm[i]] + '/' + D.cap_link[i];
    v.caps.push(e);
  }
  view[id] = v;
}
// convex hull of 2-D points (monotone chain): a box's outline in a view
function hull(pts) {
  pts = pts.slice().sort((a, b) => a[0] - b[0] || a[1] - b[1]);
  const cross = (o, a, b) => (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  const lower = [], upper = [];
  for (const p of pts) { while (lower.length >= 2 && cross(lower[lower.length - 2], lower[lower.length - 1], p) <= 0) lower.pop(); lower.push(p); }
  for (const p of pts.slice().reverse()) { while (upper.length >= 2 && cross(upper[upper.length - 2], upper[upper.length - 1], p) <= 0) upper.pop(); upper.push(p); }
  return lower.slice(0, -1).concat(upper.slice(0, -1));
}
// a cause pair's shape is drawn red, on top of the rest
function lit(v, e, on) {
  if (e.classList.contains('cause') === on) return;
  e.classList.toggle('cause', on);
  if (on) v.g.appendChild(e);
}
// the STOP in force for arm a at time t (its STOP segment's), or null
function stopAt(a, t) {
  let s = null;
  for (const r of D.rows[a]) if (r[2] === 2 && r[0] <= t && t < r[1]) { s = r; break; }
  if (!s) return null;
  for (const st of D.stops) if (st.a === a && st.t === s[0]) return st;
  return null;
}
let frame = 0, playing = false, t = 0;
function show(f) {
  frame = Math.max(0, Math.min(D.ft.length - 1, f));
  if (!D.ft.length) return;
  t = D.ft[frame];
  const fc = D.fc[frame];
  const cause = new Set(), causeObs = new Set();
  const lines = [];
  for (let a = 0; a < D.arms.length; ++a) {
    const st = stopAt(a, t);
    let lvl = 'OK';
    for (const r of D.rows[a]) if (r[0] <= t && t < r[1]) lvl = r[2] === 2 ? 'STOP' : 'WARN';
    if (st) {
      if (st.cap >= 0) cause.add(st.cap);
      if (st.oc >= 0) cause.add(st.oc);
      if (st.ob >= 0) causeObs.add(st.ob);
      lines.push(`${D.arms[a]}: STOP since ${fmt(st.t, 3)} s, ${st.cause}` + (st.body ? `: ${st.body} - ${st.other}, d ${fmt(st.d, 4)} m, TTC ${fmt(st.ttc, 3)} s` : ''));
    } else lines.push(`${D.arms[a]}: ${lvl}`);
  }
  for (const id in view) {
    const v = view[id];
    for (let i = 0; i < nC; ++i) {
      const e = v.caps[i], q = 6 * i;
      e.setAttribute('x1', fc[q + v.u] / 1000); e.setAttribute('y1', fc[q + v.w] / 1000);
      e.setAttribute('x2', fc[q + 3 + v.u] / 1000 + 1e-6); e.setAttribute('y2', fc[q + 3 + v.w] / 1000);
      lit(v, e, cause.has(i));
    }
    D.obs.forEach((o, k) => {
      const e = v.obs[k];
      lit(v, e, causeObs.has(k));
      if (!moving[k]) return;
      const s = obstacleShift(o, t);
      e.setAttribute('transform', `translate(${s[v.u]},${s[v.w]})`);
    });
    v.parts.forEach(row => row.forEach(e => e.setAttribute('visibility', 'hidden')));
    const fp = D.fp[frame];
    for (let k = 0; k < fp.length; k += 1 + 6 * nP) {
      const row = v.parts[fp[k]];
      for (let j = 0; j < nP; ++j) {
        const q = k + 1 + 6 * j, e = row[j];
        e.setAttribute('visibility', 'visible');
        e.setAttribute('x1', fp[q + v.u] / 1000); e.setAttribute('y1', fp[q + v.w] / 1000);
        e.setAttribute('x2', fp[q + 3 + v.u] / 1000 + 1e-6); e.setAttribute('y2', fp[q + 3 + v.w] / 1000);
      }
    }
  }
  document.getElementById('scrub').value = frame;
  document.getElementById('clock').textContent = `t = ${t.toFixed(3)} s of ${D.t_end.toFixed(3)} s (frame ${frame + 1} of ${D.ft.length})`;
  document.getElementById('status').textContent = lines.join('\n');
  cursor.setAttribute('x1', X(t)); cursor.setAttribute('x2', X(t));
}
// the timeline: a row per arm, time across
const TW = 1000, RH = 22, tl = document.getElementById('timeline');
const X = s => 60 + (TW - 70) * (D.t_end > 0 ? s / D.t_end : 0);
tl.setAttribute('viewBox', `0 0 ${TW} ${D.arms.length * RH + 22}`);
tl.setAttribute('width', '100%');
const tlColour = {1: '#f0a020', 2: '#d62728', 3: '#e6d23c', 4: '#8e44ad'};
D.arms.forEach((name, a) => {
  const y = a * RH + 4;
  el('text', {x: 2, y: y + 11, 'font-size': 11}, tl).textContent = name;
  el('rect', {x: X(0), y, width: X(D.t_end) - X(0), height: 14, fill: '#e9f5e9'}, tl);
  for (const r of D.rows[a]) el('rect', {class: 'seg level' + r[2], x: X(r[0]), y, width: Math.max(0.5, X(r[1]) - X(r[0])), height: 9, fill: tlColour[r[2]]}, tl);
  for (const r of D.prows[a]) el('rect', {class: 'seg level' + r[2], x: X(r[0]), y: y + 10, width: Math.max(0.5, X(r[1]) - X(r[0])), height: 4, fill: tlColour[r[2]]}, tl);
});
D.stops.forEach((s, k) => {
  const x = X(s.t), y = s.a * RH + 4 + 14;
  const m = el('polygon', {class: 'stop-mark', points: `${x},${y - 4} ${x - 4},${y + 3} ${x + 4},${y + 3}`, fill: '#000', 'data-stop': k, style: 'cursor:pointer'}, tl);
  el('title', {}, m).textContent = `STOP ${D.arms[s.a]} at ${fmt(s.t, 3)} s: ${s.cause}` + (s.body ? ` (${s.body} - ${s.other})` : '');
  m.addEventListener('click', ev => { ev.stopPropagation(); playing = false; show(s.f); });
});
for (let k = 0; k <= 10; ++k) {
  const s = D.t_end * k / 10;
  el('line', {x1: X(s), x2: X(s), y1: D.arms.length * RH, y2: D.arms.length * RH + 4, stroke: '#888'}, tl);
  el('text', {x: X(s), y: D.arms.length * RH + 16, 'font-size': 10, 'text-anchor': 'middle'}, tl).textContent = s.toFixed(2) + ' s';
}
const cursor = el('line', {y1: 0, y2: D.arms.length * RH + 2, stroke: '#000', 'stroke-width': 1.2}, tl);
function frameAt(s) { let a = 0, b = D.ft.length - 1; while (a < b) { const m = (a + b + 1) >> 1; if (D.ft[m] <= s) a = m; else b = m - 1; } return a; }
tl.addEventListener('click', ev => {
  const r = tl.getBoundingClientRect(), x = (ev.clientX - r.left) * TW / r.width;
  playing = false; show(frameAt(Math.max(0, (x - 60) / (TW - 70) * D.t_end)));
});
// the STOP list
const tb = document.querySelector('#stoplist tbody');
D.stops.forEach((s, k) => {
  const tr = document.createElement('tr'); tr.className = 'stop';
  for (const c of [k + 1, fmt(s.t, 3), D.arms[s.a], s.cause, s.body ? s.body + ' - ' + s.other : '', s.body ? fmt(s.d, 4) : '', s.body ? fmt(s.ttc, 3) : '']) {
    const td = document.createElement('td'); td.textContent = c; tr.appendChild(td);
  }
  tr.onclick = () => { playing = false; show(s.f); };
  tb.appendChild(tr);
});
document.getElementById('title').textContent = `${D.title}: ${D.arms.length} arms, ${nC} capsules, ${D.obs.length} obstacles` +
  (D.persons.length ? `, ${D.persons.length} persons` : '') + `, ${D.cycles} cycles, ${D.stops.length} STOPs (safe time ${D.safe_time} s)` +
  (D.stride > 1 ? `; poses shown every ${D.stride} cycles and at each STOP` : '');
buildView('top'); buildView('side');
const scrub = document.getElementById('scrub');
scrub.max = Math.max(0, D.ft.length - 1);
scrub.oninput = () => { playing = false; show(+scrub.value); };
document.getElementById('play').onclick = () => { playing = !playing; if (playing && frame >= D.ft.length - 1) show(0); };
document.getElementById('next').onclick = () => { playing = false; const s = D.stops.find(s => s.t > t + 1e-12); if (s) show(s.f); };
document.getElementById('prev').onclick = () => { playing = false; const s = D.stops.filter(s => s.t < t - 1e-12).pop(); if (s) show(s.f); };
let last = null;
function tick(now) {
  if (playing && last !== null && D.ft.length) {
    const target = t + (now - last) / 1000 * +document.getElementById('speed').value;
    const f = frameAt(target);
    if (f >= D.ft.length - 1) playing = false;
    if (f !== frame) show(f); else t = target;
  }
  last = now;
  document.getElementById('play').textContent = playing ? 'pause' : 'play';
  requestAnimationFrame(tick);
}
show(0);
requestAnimationFrame(tick);
// for tests and scripts: what the page drew
window.replay = {
  data: D,
  frames: () => D.ft.length,
  seek: f => show(f),
  frame: () => frame,
  shapes: id => document.querySelectorAll('#' + id + ' .shape').length,
  highlighted: id => Array.from(document.querySelectorAll('#' + id + ' .shape.cause')).map(e => e.querySelector('title').textContent).sort(),
  stopMarks: () => document.querySelectorAll('#timeline .stop-mark').length,
  ready: true,
};
</script></body></html>
)HTML";

}  // namespace st::arm
