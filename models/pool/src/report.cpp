#include <stpool/report.hpp>

#include <stio/format.hpp>
#include <stio/json.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace st::pool {

namespace {

using io::jsonString;

// one XML escaping for every output (st::io: UTF-8 and XML's forbidden characters too)
std::string xmlEscape(const std::string& s) { return io::xmlText(s); }

// a figure that does not apply (the energy drift of a run with friction): NaN, written as null
constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

// Table drawing in pixels: y up in the model, down on screen.
struct View {
  Rect box;
  double scale;  // px per metre
  double x(double m) const { return (m - box.min.x()) * scale; }
  double y(double m) const { return (box.max.y() - m) * scale; }
  double width() const { return box.extent().x() * scale; }
  double height() const { return box.extent().y() * scale; }
};

}  // namespace

std::string describe(const SpaceSpec& space) {
  std::ostringstream os;
  os << toString(space.kind);
  if (space.kind == SpaceKind::Tree)
    os << " df=" << (space.autoFactor ? std::string("auto") : std::to_string(space.decompositionFactor)) << " divisions=" << space.divisions << " max_depth="
       << (space.maxDepth < 0 ? std::string("auto") : std::to_string(space.maxDepth));
  if (space.kind == SpaceKind::Cells)
    os << " cell_size=" << space.cellSize << " margin=" << space.marginFactor() << (space.margin > 0.0 ? "" : "(auto)");
  return os.str();
}

RunRecord playScenario(Game& game, const Scenario& scenario, double untilOverride,
                       const std::function<bool()>& stopRequested, std::size_t maxEvents) {
  maxEvents = std::min(maxEvents, kMaxEvents);
  RunRecord run;
  run.scenario = scenario.name;
  run.spaceDescription = describe(scenario.space);
  run.initial = game.specs();
  auto record = [&](const PoolEvent& e) {
    if (stopRequested && stopRequested()) throw std::runtime_error("interrupted at t = " + io::number(e.t, 6) + " s");
    if (run.events.size() >= maxEvents) {
      run.eventLimitReached = true;
      throw std::runtime_error("until: stopped after " + std::to_string(maxEvents) + " events at t = " +
                               io::number(e.t, 6) + " s; the time limit asks for more (lower until or --until)");
    }
    run.events.push_back(e);
  };
  run.wallSeconds = wallSeconds([&] {
    try {
      if (scenario.shots.empty()) {
        run.shots.push_back(game.coast(untilOverride > 0 ? untilOverride : scenario.until, record));
      }
      for (const Shot& shot : scenario.shots) {
        const double limit = untilOverride > 0 ? untilOverride : shot.until > 0 ? shot.until : scenario.until;
        run.shots.push_back(game.play(shot, limit, record));
      }
    } catch (const std::runtime_error& e) {
      run.error = e.what();
      // the shot the limit stopped is recorded too: its initial energy and momentum are real
      if (game.stoppedShot()) run.shots.push_back(*game.stoppedShot());
    }
  });
  return run;
}

std::vector<std::uint64_t> eventCounts(const std::vector<PoolEvent>& events) {
  std::vector<std::uint64_t> n(static_cast<int>(PoolEventKind::Count), 0);
  for (const auto& e : events) ++n[static_cast<int>(e.kind)];
  return n;
}

void writeEventsCsv(std::ostream& os, const RunRecord& run, const Game& game) {
  os << "shot,time,kind,ball,number,other,x,y,vx,vy,other_x,other_y,other_vx,other_vy\n";
  os << std::setprecision(17);
  for (const auto& e : run.events) {
    if (!os) return;  // a failed write (a full disk): the rest cannot reach the file
    os << e.shot << ',' << e.t << ',' << toString(e.kind) << ',' << e.ball << ',' << game.specs()[e.ball].number << ','
       << e.other << ',' << e.p.x() << ',' << e.p.y() << ',' << e.v.x() << ',' << e.v.y();
    if (e.kind == PoolEventKind::Ball)
      os << ',' << e.otherP.x() << ',' << e.otherP.y() << ',' << e.otherV.x() << ',' << e.otherV.y();
    else
      os << ",,,,";
    os << '\n';
  }
}

void writeSummaryJson(std::ostream& os, const RunRecord& run, const Game& game) {
  const Simulator<2>& sim = game.simulator();
  const SimulatorCounters& c = sim.counters();
  const auto counts = eventCounts(run.events);
  io::JsonText j(17);
  const auto vec = [](const Vec2& v) {
    io::JsonText p(17);
    p << "[" << v.x() << ", " << v.y() << "]";
    return p;
  };
  j << "{\n";
  j << "  \"scenario\": " << run.scenario << ",\n";
  j << "  \"space\": " << run.spaceDescription << ",\n";
  j << "  \"balls\": " << game.specs().size() << ",\n";
  j << "  \"simulated_time_s\": " << sim.now() << ",\n";
  j << "  \"events\": {";
  std::uint64_t total = 0;
  for (int k = 0; k < static_cast<int>(PoolEventKind::Count); ++k) {
    if (k) j << ", ";
    j << toString(static_cast<PoolEventKind>(k)) << ": " << counts[k];
    total += counts[k];
  }
  j << ", \"total\": " << total << "},\n";
  j << "  \"simulator_events\": " << c.totalEvents() << ",\n";
  j << "  \"collision_checks\": " << c.pairChecks << ",\n";
  j << "  \"obstacle_checks\": " << c.staticChecks << ",\n";
  j << "  \"stale_predictions\": " << c.staleEvents << ",\n";
  // (none, the brute force, has no regions to count)
  if (const Space<2>* sp = sim.space(); sp->kind() != SpaceKind::None) {
    j << "  \"space_counters\": {\"subdivisions\": " << sp->counters().subdivisions
      << ", \"reunions\": " << sp->counters().reunions << ", \"transfers\": " << sp->counters().transfers
      << ", \"leaves_at_end\": " << sp->leaves().size() << "},\n";
  }
  j << "  \"pocketed\": [";
  for (std::size_t i = 0; i < game.pocketed().size(); ++i) {
    const Pocketing& p = game.pocketed()[i];
    if (i) j << ", ";
    j << "{\"number\": " << p.number << ", \"shot\": " << p.shot << ", \"pocket\": " << p.pocket
      << ", \"time_s\": " << p.t << "}";
  }
  j << "],\n";
  j << "  \"shots\": [";
  double worstDrift = 0.0;
  for (std::size_t i = 0; i < run.shots.size(); ++i) {
    const ShotSummary& s = run.shots[i];
    if (!s.friction) worstDrift = std::max(worstDrift, std::abs(s.energyDrift()));
    if (i) j << ",";
    j << "\n    {\"ball\": " << s.ball << ", \"start_s\": " << s.start << ", \"end_s\": " << s.end
      << ", \"ending\": " << toString(s.ending) << ", \"events\": " << s.events
      << ", \"kinetic_energy_initial_J\": " << s.keStart << ", \"kinetic_energy_final_J\": " << s.keEnd
      << ", \"kinetic_energy_pocketed_J\": " << s.kePocketed << ", \"momentum_initial\": " << vec(s.momentumStart)
      << ", \"momentum_final\": " << vec(s.momentumEnd) << ", \"energy_drift\": "
      << (s.friction ? kNone : s.energyDrift())
      << ", \"energy_dissipated_J\": " << s.keStart - s.keEnd - s.kePocketed << "}";
  }
  if (!run.shots.empty()) j << "\n  ";
  j << "],\n";
  const ShotSummary first = run.shots.empty() ? ShotSummary{} : run.shots.front();
  const ShotSummary last = run.shots.empty() ? ShotSummary{} : run.shots.back();
  j << "  \"kinetic_energy_initial_J\": " << first.keStart << ",\n";
  j << "  \"kinetic_energy_final_J\": " << last.keEnd << ",\n";
  j << "  \"momentum_initial\": " << vec(first.momentumStart) << ",\n";
  j << "  \"momentum_final\": " << vec(last.momentumEnd) << ",\n";
  j << "  \"friction_m_per_s2\": " << game.friction() << ",\n";
  j << "  \"energy_drift_max\": " << (game.friction() > 0.0 ? kNone : worstDrift)
    << ",\n";
  j << "  \"wall_time_s\": " << run.wallSeconds << ",\n";
  j << "  \"error\": ";
  if (run.error.empty()) j << "null";
  else j << run.error;
  j << "\n}\n";
  os << j.str();
}

void writeTableSvg(std::ostream& os, const Game& game, const std::string& title) {
  const Table& t = game.table();
  const Simulator<2>& sim = game.simulator();
  const double pad = 0.08;
  const View v{{t.surface().min.array() - pad, t.surface().max.array() + pad}, 400.0};
  os << std::fixed << std::setprecision(2);
  os << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << v.width() << "\" height=\"" << v.height()
     << "\" viewBox=\"0 0 " << v.width() << ' ' << v.height() << "\">\n";
  os << "<title>" << xmlEscape(title) << ": final table at " << sim.now() << " s</title>\n";
  os << "<rect width=\"100%\" height=\"100%\" fill=\"#5b3a1e\"/>\n";
  os << "<rect x=\"" << v.x(0) << "\" y=\"" << v.y(t.spec.height) << "\" width=\"" << t.spec.width * v.scale
     << "\" height=\"" << t.spec.height * v.scale << "\" fill=\"#1f7a4a\"/>\n";
  // the space's regions (the report's Fig. 7; none, the brute force, has none)
  if (const Space<2>* sp = sim.space(); sp->kind() != SpaceKind::None) {
    os << "<g fill=\"none\" stroke=\"#d9f99d\" stroke-width=\"1\" stroke-dasharray=\"4 3\">\n";
    for (int leaf : sp->leaves()) {
      Rect b = sp->leafBounds(leaf);
      b.min = b.min.cwiseMax(v.box.min);
      b.max = b.max.cwiseMin(v.box.max);
      os << "<rect x=\"" << v.x(b.min.x()) << "\" y=\"" << v.y(b.max.y()) << "\" width=\""
         << (b.max.x() - b.min.x()) * v.scale << "\" height=\"" << (b.max.y() - b.min.y()) * v.scale << "\"/>\n";
    }
    os << "</g>\n";
  }
  for (const auto& p : t.pockets)
    os << "<circle cx=\"" << v.x(p.center.x()) << "\" cy=\"" << v.y(p.center.y()) << "\" r=\"" << p.radius * v.scale
       << "\" fill=\"#000\" fill-opacity=\"0.8\"/>\n";
  os << "<g stroke=\"#3b2412\" stroke-width=\"4\" stroke-linecap=\"round\">\n";
  for (const auto& s : t.cushions)
    os << "<line x1=\"" << v.x(s.a.x()) << "\" y1=\"" << v.y(s.a.y()) << "\" x2=\"" << v.x(s.b.x()) << "\" y2=\""
       << v.y(s.b.y()) << "\"/>\n";
  os << "</g>\n";
  for (const auto& j : t.jaws)
    os << "<circle cx=\"" << v.x(j.x()) << "\" cy=\"" << v.y(j.y()) << "\" r=\"3\" fill=\"#e5e7eb\"/>\n";
  for (std::size_t i = 0; i < game.specs().size(); ++i) {
    const BallState<2>& b = sim.ball(static_cast<int>(i));
    if (!b.active) continue;
    const BallSpec& s = game.specs()[i];
    const Vec2 p = b.positionAt(sim.now());
    const double r = b.radius * v.scale;
    os << "<g><circle cx=\"" << v.x(p.x()) << "\" cy=\"" << v.y(p.y()) << "\" r=\"" << r << "\" fill=\""
       << (s.pattern == Pattern::Striped ? "#f8f8f0" : hexOf(s.colour)) << "\" stroke=\"#000\" stroke-width=\"0.8\"/>";
    if (s.pattern == Pattern::Striped)
      os << "<rect x=\"" << v.x(p.x()) - r << "\" y=\"" << v.y(p.y()) - 0.45 * r << "\" width=\"" << 2 * r
         << "\" height=\"" << 0.9 * r << "\" fill=\"" << hexOf(s.colour) << "\"/>";
    if (s.number != 0)
      os << "<text x=\"" << v.x(p.x()) << "\" y=\"" << v.y(p.y()) + 0.3 * r << "\" font-size=\"" << 0.85 * r
         << "\" text-anchor=\"middle\" font-family=\"sans-serif\" fill=\""
         << (s.pattern == Pattern::Solid && s.colour != Colour::Yellow && s.colour != Colour::Orange ? "#fff" : "#000")
         << "\">" << s.number << "</text>";
    os << "</g>\n";
  }
  os << "</svg>\n";
}

namespace {

// The animation's data (the page's const D): the table, and per ball its keyframes.
io::JsonText animationData(const RunRecord& run, const Game& game) {
  const Table& t = game.table();
  const auto& specs = game.specs();
  // per ball: keyframes [t, x, y, vx, vy] at every change of velocity, and the time it left
  std::vector<double> gone(specs.size(), -1.0);
  // the table at 9 significant digits, the keyframes at 12 (io::JsonText: NaN, infinities as null)
  io::JsonText data(9);
  data << "{\"width\":" << t.spec.width << ",\"height\":" << t.spec.height << ",\"end\":" << game.simulator().now()
       << ",\"title\":" << run.scenario + " (" + run.spaceDescription + ")" << ",\"cushions\":[";
  for (std::size_t i = 0; i < t.cushions.size(); ++i) {
    if (i) data << ",";
    data << "[" << t.cushions[i].a.x() << "," << t.cushions[i].a.y() << "," << t.cushions[i].b.x() << ","
         << t.cushions[i].b.y() << "]";
  }
  data << "],\"pockets\":[";
  for (std::size_t i = 0; i < t.pockets.size(); ++i) {
    if (i) data << ",";
    data << "[" << t.pockets[i].center.x() << "," << t.pockets[i].center.y() << "," << t.pockets[i].radius << "]";
  }
  data << "],\"balls\":[";
  // keyframes from the event log
  std::vector<io::JsonText> k(specs.size(), io::JsonText(12));
  const auto key = [&](std::size_t ball, double at, const Vec2& p, const Vec2& v) {
    if (!k[ball].empty()) k[ball] << ",";
    k[ball] << "[" << at << "," << p.x() << "," << p.y() << "," << v.x() << "," << v.y() << "]";
  };
  for (std::size_t i = 0; i < specs.size(); ++i) key(i, 0.0, specs[i].position, specs[i].velocity);
  for (const auto& e : run.events) {
    if (e.kind == PoolEventKind::Boundary) continue;  // path unchanged
    if (e.kind == PoolEventKind::Pocket) {
      gone[e.ball] = e.t;
      continue;
    }
    key(e.ball, e.t, e.p, e.v);
    if (e.kind == PoolEventKind::Ball) key(e.other, e.t, e.otherP, e.otherV);
  }
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (i) data << ",";
    io::JsonText goneAt(17);  // the time the ball left the table: null if it stayed
    goneAt << (gone[i] < 0 ? kNone : gone[i]);
    data << "{\"n\":" << specs[i].number << ",\"r\":" << specs[i].radius << ",\"a\":" << game.friction()
         << ",\"c\":" << hexOf(specs[i].colour) << ",\"s\":" << (specs[i].pattern == Pattern::Striped ? 1 : 0)
         << ",\"gone\":" << goneAt << ",\"k\":[" << k[i] << "]}";
  }
  data << "]}";
  return data;
}

}  // namespace

void writeAnimationHtml(std::ostream& os, const RunRecord& run, const Game& game) {
  const io::JsonText data = animationData(run, game);
  os << R"HTML(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>stsim pool</title>
<style>
body{background:#222;color:#ddd;font:14px sans-serif;margin:12px}
canvas{display:block;margin-top:8px;background:#5b3a1e}
button,input{vertical-align:middle}
</style></head><body>
<div><b id="title"></b></div>
<div><button id="play">pause</button>
<label>speed <input id="speed" type="range" min="-3" max="3" step="1" value="0"> <span id="sx">1x</span></label>
<input id="scrub" type="range" min="0" max="1000" value="0" style="width:40%">
<label><input id="trails" type="checkbox" checked> trails</label>
<span id="clock"></span></div>
<canvas id="c"></canvas>
<script>
const D = )HTML" << io::jsonForScript(data.str()) << R"HTML(;
// position of ball b at time t: the last keyframe before t, moved in a straight line
function state(b, t) {
  if (b.gone !== null && t >= b.gone) return null;
  let lo = 0, hi = b.k.length - 1;
  while (lo < hi) { const m = (lo + hi + 1) >> 1; if (b.k[m][0] <= t) lo = m; else hi = m - 1; }
  const k = b.k[lo], s = Math.hypot(k[3], k[4]);
  let dt = t - k[0], f = 1;
  // rolling resistance: speed falls by a per second until the ball stops
  if (b.a > 0 && s > 0) { dt = Math.min(dt, s / b.a); f = 1 - 0.5 * b.a * dt / s; }
  return [k[1] + k[3] * dt * f, k[2] + k[4] * dt * f];
}
const pad = 0.08, S = Math.min(1100 / (D.width + 2 * pad), 700 / (D.height + 2 * pad));
const cv = document.getElementById('c'), g = cv.getContext('2d');
cv.width = Math.ceil((D.width + 2 * pad) * S); cv.height = Math.ceil((D.height + 2 * pad) * S);
const X = x => (x + pad) * S, Y = y => (D.height + pad - y) * S;
document.getElementById('title').textContent = D.title;
let t = 0, playing = true, speed = 1, last = null;
const trail = D.balls.map(() => []);
function draw() {
  g.fillStyle = '#5b3a1e'; g.fillRect(0, 0, cv.width, cv.height);
  g.fillStyle = '#1f7a4a'; g.fillRect(X(0), Y(D.height), D.width * S, D.height * S);
  g.fillStyle = '#000';
  for (const p of D.pockets) { g.beginPath(); g.arc(X(p[0]), Y(p[1]), p[2] * S, 0, 7); g.fill(); }
  g.strokeStyle = '#3b2412'; g.lineWidth = 4; g.lineCap = 'round';
  for (const c of D.cushions) { g.beginPath(); g.moveTo(X(c[0]), Y(c[1])); g.lineTo(X(c[2]), Y(c[3])); g.stroke(); }
  const showTrails = document.getElementById('trails').checked;
  D.balls.forEach((b, i) => {
    const s = state(b, t);
    if (!s) return;
    if (showTrails) {
      const tr = trail[i];
      if (!tr.length || Math.hypot(tr[tr.length - 1][0] - s[0], tr[tr.length - 1][1] - s[1]) > 0.01) tr.push(s);
      if (tr.length > 400) tr.shift();
      g.strokeStyle = b.c; g.globalAlpha = 0.35; g.lineWidth = 1.5; g.beginPath();
      tr.forEach((q, j) => j ? g.lineTo(X(q[0]), Y(q[1])) : g.moveTo(X(q[0]), Y(q[1]))); g.stroke(); g.globalAlpha = 1;
    }
    const r = b.r * S;
    g.beginPath(); g.arc(X(s[0]), Y(s[1]), r, 0, 7); g.fillStyle = b.s ? '#f8f8f0' : b.c; g.fill();
    if (b.s) { g.save(); g.clip(); g.fillStyle = b.c; g.fillRect(X(s[0]) - r, Y(s[1]) - 0.45 * r, 2 * r, 0.9 * r); g.restore(); }
    g.strokeStyle = '#000'; g.lineWidth = 0.8; g.stroke();
    if (b.n && r > 6) { g.fillStyle = (b.c === '#f5c518' || b.c === '#f77f00' || b.s) ? '#000' : '#fff';
      g.font = Math.round(r) + 'px sans-serif'; g.textAlign = 'center'; g.fillText(b.n, X(s[0]), Y(s[1]) + 0.35 * r); }
  });
  document.getElementById('clock').textContent = t.toFixed(3) + ' s / ' + D.end.toFixed(3) + ' s';
  document.getElementById('scrub').value = Math.round(1000 * t / Math.max(D.end, 1e-9));
}
function frame(now) {
  if (last !== null && playing) { t = Math.min(D.end, t + speed * (now - last) / 1000); if (t >= D.end) playing = false; }
  last = now; document.getElementById('play').textContent = playing ? 'pause' : 'play';
  draw(); requestAnimationFrame(frame);
}
document.getElementById('play').onclick = () => { if (t >= D.end) { t = 0; trail.forEach(a => a.length = 0); } playing = !playing; };
document.getElementById('speed').oninput = e => { speed = Math.pow(2, +e.target.value); document.getElementById('sx').textContent = speed + 'x'; };
document.getElementById('scrub').oninput = e => { t = D.end * e.target.value / 1000; trail.forEach(a => a.length = 0); };
requestAnimationFrame(frame);
</script></body></html>
)HTML";
}

}  // namespace st::pool
