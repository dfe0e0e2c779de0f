#include <starm/replay.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

#include <starm/person.hpp>
#include <starm/ssm.hpp>
#include <stio/format.hpp>
#include <stio/output.hpp>

namespace st::arm {

namespace {

// a pose coordinate in whole millimetres (the page's unit of exchange: 1 mm is far below what
// the views resolve, and it keeps a frame of 24 capsules near 1 kB)
std::int32_t mm(double x) { return static_cast<std::int32_t>(std::lround(std::clamp(x, -1e6, 1e6) * 1000.0)); }

std::string num(double x) { return io::jsonNumber(x, 6); }

// appended piece by piece: GCC 12 takes "[" + std::string for an overlapping memcpy (-Wrestrict)
std::string vec(const Vec3& p) {
  std::string s(1, '[');
  s += num(p.x());
  s += ',';
  s += num(p.y());
  s += ',';
  s += num(p.z());
  s += ']';
  return s;
}

void appendCapsule(std::vector<std::int32_t>& out, const Capsule& c) {
  for (const Vec3* p : {&c.a, &c.b})
    for (int k = 0; k < 3; ++k) out.push_back(mm((*p)[k]));
}

}  // namespace

ReplayRecorder::ReplayRecorder(const Monitor& m, const PersonSet* persons, ReplayConfig cfg) : cfg_(cfg) {
  capsules_ = m.capsuleCount();
  cycleTime_ = m.safety().cycleTime;
  persons_ = persons ? persons->size() : 0;
  const int perFrame = std::max(1, capsules_ + persons_ * kBodyParts);
  if (cfg_.maxFrames <= 0) cfg_.maxFrames = std::clamp(60000 / perFrame, 200, 2000);
  first_.assign(m.armCount(), 0);
  for (int i = m.capsuleCount() - 1; i >= 0; --i) first_[m.capsuleArm(i)] = i;
  armRows_.resize(m.armCount());
  personRows_.resize(m.armCount());
  wasStopped_.assign(m.armCount(), 0);

  // the scene: what does not change from frame to frame
  std::ostringstream s;
  s << "\"arms\":[";
  for (int a = 0; a < m.armCount(); ++a) s << (a ? "," : "") << io::jsonString(m.arm(a).name);
  s << "],\"cap_arm\":[";
  for (int i = 0; i < capsules_; ++i) s << (i ? "," : "") << m.capsuleArm(i);
  s << "],\"cap_link\":[";
  for (int i = 0; i < capsules_; ++i)
    s << (i ? "," : "") << io::jsonString(bodyName(m.arm(m.capsuleArm(i)).model, m.capsuleBody(i)));
  s << "],\"cap_r\":[";
  for (int i = 0; i < capsules_; ++i) s << (i ? "," : "") << num(m.movingCapsule(i).c.radius);
  s << "],\"obs\":[";
  for (std::size_t o = 0; o < m.obstacles().size(); ++o) {
    const Obstacle& ob = m.obstacles()[o];
    s << (o ? "," : "") << "{\"n\":" << io::jsonString(ob.name) << ",\"v\":" << vec(ob.velocity);
    switch (ob.kind) {
      case ShapeKind::Sphere:
        s << ",\"k\":\"s\",\"c\":" << vec(ob.sphere.center) << ",\"r\":" << num(ob.sphere.radius);
        break;
      case ShapeKind::Capsule:
        s << ",\"k\":\"c\",\"a\":" << vec(ob.capsule.a) << ",\"b\":" << vec(ob.capsule.b) << ",\"r\":" << num(ob.capsule.radius);
        break;
      case ShapeKind::Box: {
        s << ",\"k\":\"b\",\"p\":[";
        for (int c = 0; c < 8; ++c) {
          const Vec3 h((c & 1 ? 1 : -1) * ob.box.halfExtents.x(), (c & 2 ? 1 : -1) * ob.box.halfExtents.y(),
                       (c & 4 ? 1 : -1) * ob.box.halfExtents.z());
          s << (c ? "," : "") << vec(ob.box.center + ob.box.rotation * h);
        }
        s << "]";
        break;
      }
    }
    s << "}";
  }
  s << "],\"persons\":[";
  for (int p = 0; p < persons_; ++p) s << (p ? "," : "") << io::jsonString(persons->name(p));
  s << "],\"parts\":[";
  for (int k = 0; k < kBodyParts; ++k) s << (k ? "," : "") << io::jsonString(bodyParts()[k].name);
  s << "],\"part_r\":[";
  for (int k = 0; k < kBodyParts; ++k) s << (k ? "," : "") << num(bodyParts()[k].radius);
  s << "],\"safe_time\":" << num(m.safety().safeTime()) << ",\"min_separation\":" << num(m.safety().minSeparation);
  scene_ = s.str();
}

void ReplayRecorder::level(std::vector<Segment>& row, int lvl, double t) {
  // a level holds from its cycle to the next; runs of one level are one segment
  if (!row.empty() && row.back().level == lvl && row.back().open) {
    row.back().t1 = t;
    return;
  }
  if (!row.empty()) row.back().open = false;
  if (lvl > 0) row.push_back({t, t, lvl, true});
}

void ReplayRecorder::see(const Monitor& m, const PersonSet* persons, const SeparationMonitor* ssm) {
  const double t = m.time();
  // the cycles' levels: each cycle's level holds until the next cycle
  for (int a = 0; a < m.armCount(); ++a) {
    for (auto* row : {&armRows_[a], &personRows_[a]})
      if (!row->empty() && row->back().open) row->back().t1 = t;
    const int lvl = m.stopped(a) ? 2 : std::isfinite(m.minTtc(a)) ? 1 : 0;
    level(armRows_[a], lvl, t);
    int plvl = 0;
    if (ssm && ssm->verdict(a).person >= 0) plvl = ssm->verdict(a).stop ? 4 : ssm->verdict(a).factor < 1.0 ? 3 : 0;
    level(personRows_[a], plvl, t);
  }
  // STOPs issued this cycle (the monitor's count: an arm's STOP after a cycle without one)
  bool forced = false;
  for (int a = 0; a < m.armCount(); ++a) {
    const bool stopped = m.stopped(a);
    if (stopped && !wasStopped_[a]) {
      ReplayStop st;
      st.arm = a;
      st.t = t;
      if (m.stale(a) || m.latched(a)) {
        st.cause = m.stale(a) ? "stale" : "latched";
      } else {
        // the pair with the arm's smallest time to collision decided it (as the service's verdict)
        const Warning& w = m.worst(a);
        st.cause = w.outcome == Approach::Touching ? "separation" : "collision";
        if (w.arm >= 0) {
          st.body = m.arm(a).name + "/" + bodyName(m.arm(a).model, w.body);
          st.other = otherName(m, w);
          st.capsule = first_[a] + w.capsule;
          if (w.otherArm >= 0) st.otherCapsule = first_[w.otherArm] + w.otherCapsule;
          st.obstacle = w.obstacle;
          st.distance = w.distance;
          st.ttc = w.ttc;
        }
      }
      stops_.push_back(st);
      stopCycle_.push_back(cycles_);
      if (forcedFrames_ < cfg_.maxStopFrames) forced = true;
    }
    wasStopped_[a] = stopped ? 1 : 0;
  }
  if (forced || cycles_ % static_cast<std::uint64_t>(stride_) == 0) keepFrame(m, persons, forced);
  lastT_ = t;
  ++cycles_;
}

void ReplayRecorder::keepFrame(const Monitor& m, const PersonSet* persons, bool forced) {
  frameT_.push_back(m.time());
  frameCycle_.push_back(cycles_);
  frameForced_.push_back(forced ? 1 : 0);
  if (forced) ++forcedFrames_;
  std::vector<std::int32_t> caps;
  caps.reserve(6 * static_cast<std::size_t>(capsules_));
  for (int i = 0; i < capsules_; ++i) appendCapsule(caps, m.movingCapsule(i).c);
  frameCaps_.push_back(std::move(caps));
  std::vector<std::int32_t> ps;
  for (int p = 0; p < persons_; ++p) {
    if (!persons->present(p)) continue;
    ps.push_back(p);
    for (const Capsule& c : bodyCapsules(persons->skeleton(p))) appendCapsule(ps, c);
  }
  framePersons_.push_back(std::move(ps));
  thin();
}

void ReplayRecorder::thin() {
  const int regular = static_cast<int>(frameT_.size()) - forcedFrames_;
  if (regular <= cfg_.maxFrames) return;
  // every other regular frame goes (the kept ones are the multiples of the doubled stride)
  stride_ *= 2;
  std::size_t w = 0;
  for (std::size_t r = 0; r < frameT_.size(); ++r) {
    if (!frameForced_[r] && frameCycle_[r] % static_cast<std::uint64_t>(stride_) != 0) continue;
    if (w == r) {  // (a vector moved onto itself is left empty)
      ++w;
      continue;
    }
    frameT_[w] = frameT_[r];
    frameCycle_[w] = frameCycle_[r];
    frameForced_[w] = frameForced_[r];
    frameCaps_[w] = std::move(frameCaps_[r]);
    framePersons_[w] = std::move(framePersons_[r]);
    ++w;
  }
  frameT_.resize(w);
  frameCycle_.resize(w);
  frameForced_.resize(w);
  frameCaps_.resize(w);
  framePersons_.resize(w);
}

void ReplayRecorder::write(const std::filesystem::path& file, const std::string& title) const {
  const double tEnd = cycles_ ? lastT_ + cycleTime_ : 0.0;
  std::ostringstream d;
  d << "{\"title\":" << io::jsonString(title) << ",\"cycles\":" << cycles_ << ",\"t_end\":" << num(tEnd)
    << ",\"stride\":" << stride_ << "," << scene_;
  d << ",\"ft\":[";
  for (std::size_t f = 0; f < frameT_.size(); ++f) d << (f ? "," : "") << num(frameT_[f]);
  d << "],\"fc\":[";
  for (std::size_t f = 0; f < frameCaps_.size(); ++f) {
    d << (f ? ",[" : "[");
    for (std::size_t k = 0; k < frameCaps_[f].size(); ++k) d << (k ? "," : "") << frameCaps_[f][k];
    d << "]";
  }
  // persons: per frame, each present person's index followed by its capsules' end points
  d << "],\"fp\":[";
  for (std::size_t f = 0; f < framePersons_.size(); ++f) {
    d << (f ? ",[" : "[");
    for (std::size_t k = 0; k < framePersons_[f].size(); ++k) d << (k ? "," : "") << framePersons_[f][k];
    d << "]";
  }
  auto rows = [&](const std::vector<std::vector<Segment>>& rs) {
    d << "[";
    for (std::size_t a = 0; a < rs.size(); ++a) {
      d << (a ? ",[" : "[");
      for (std::size_t k = 0; k < rs[a].size(); ++k) {
        const Segment& s = rs[a][k];
        d << (k ? "," : "") << "[" << num(s.t0) << "," << num(s.open ? tEnd : s.t1) << "," << s.level << "]";
      }
      d << "]";
    }
    d << "]";
  };
  d << "],\"rows\":";
  rows(armRows_);
  d << ",\"prows\":";
  rows(personRows_);
  d << ",\"stops\":[";
  for (std::size_t k = 0; k < stops_.size(); ++k) {
    const ReplayStop& s = stops_[k];
    // the frame that shows it: its own (kept while maxStopFrames allows), else the last before it
    const auto it = std::upper_bound(frameCycle_.begin(), frameCycle_.end(), stopCycle_[k]);
    const long f = std::max(0L, static_cast<long>(it - frameCycle_.begin()) - 1);
    d << (k ? "," : "") << "{\"a\":" << s.arm << ",\"t\":" << num(s.t) << ",\"cause\":" << io::jsonString(s.cause)
      << ",\"body\":" << io::jsonString(s.body) << ",\"other\":" << io::jsonString(s.other) << ",\"cap\":" << s.capsule
      << ",\"oc\":" << s.otherCapsule << ",\"ob\":" << s.obstacle << ",\"d\":" << num(s.distance)
      << ",\"ttc\":" << num(s.ttc) << ",\"f\":" << f << "}";
  }
  d << "]}";
  io::writeTextFile(file, [&](std::ostream& os) {
    os << R"HTML(<!DOCTYPE html>
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
const D = )HTML" << io::jsonForScript(d.str()) << R"HTML(;
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
  });
}

}  // namespace st::arm
