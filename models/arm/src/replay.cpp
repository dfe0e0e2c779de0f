#include <starm/replay.hpp>

#include <algorithm>
#include <cmath>

#include <starm/person.hpp>
#include <starm/ssm.hpp>
#include <stio/format.hpp>
#include <stio/output.hpp>

#include "replay_page.hpp"

namespace st::arm {

namespace {

// a pose coordinate in whole millimetres (the page's unit of exchange: 1 mm is far below what
// the views resolve, and it keeps a frame of 24 capsules near 1 kB)
std::int32_t mm(double x) { return static_cast<std::int32_t>(std::lround(std::clamp(x, -1e6, 1e6) * 1000.0)); }

// the page's numbers to 6 significant digits (io::JsonText: NaN and infinities as null)
constexpr int kDigits = 6;
using io::JsonText;

JsonText vec(const Vec3& p) {
  JsonText j(kDigits);
  j << "[" << p.x() << "," << p.y() << "," << p.z() << "]";
  return j;
}

// [f(0),f(1),...,f(n-1)]
template <class F>
JsonText array(std::size_t n, F f) {
  JsonText j(kDigits);
  j << "[";
  for (std::size_t i = 0; i < n; ++i) {
    if (i) j << ",";
    j << f(i);
  }
  j << "]";
  return j;
}

// an obstacle as the page draws it: name, velocity, and its shape (sphere, capsule, or a box's corners)
JsonText obstacleJson(const Obstacle& ob) {
  JsonText j(kDigits);
  j << "{\"n\":" << ob.name << ",\"v\":" << vec(ob.velocity);
  switch (ob.kind) {
    case ShapeKind::Sphere:
      j << ",\"k\":\"s\",\"c\":" << vec(ob.sphere.center) << ",\"r\":" << ob.sphere.radius;
      break;
    case ShapeKind::Capsule:
      j << ",\"k\":\"c\",\"a\":" << vec(ob.capsule.a) << ",\"b\":" << vec(ob.capsule.b) << ",\"r\":" << ob.capsule.radius;
      break;
    case ShapeKind::Box:
      j << ",\"k\":\"b\",\"p\":" << array(8, [&](std::size_t c) {
        const Vec3 h((c & 1 ? 1 : -1) * ob.box.halfExtents.x(), (c & 2 ? 1 : -1) * ob.box.halfExtents.y(),
                     (c & 4 ? 1 : -1) * ob.box.halfExtents.z());
        return vec(ob.box.center + ob.box.rotation * h);
      });
      break;
  }
  j << "}";
  return j;
}

// the scene: what does not change from frame to frame (arms, capsules, obstacles, persons' parts)
JsonText sceneJson(const Monitor& m, const PersonSet* persons) {
  const auto capsules = static_cast<std::size_t>(m.capsuleCount());
  const std::size_t personCount = persons ? static_cast<std::size_t>(persons->size()) : 0;
  const auto arms = static_cast<std::size_t>(m.armCount());
  const auto cap = [](std::size_t i) { return static_cast<int>(i); };
  JsonText j(kDigits);
  j << "\"arms\":" << array(arms, [&](std::size_t a) { return m.arm(static_cast<int>(a)).name; })
    << ",\"cap_arm\":" << array(capsules, [&](std::size_t i) { return m.capsuleArm(cap(i)); })
    << ",\"cap_link\":" << array(capsules, [&](std::size_t i) {
         return bodyName(m.arm(m.capsuleArm(cap(i))).model, m.capsuleBody(cap(i)));
       })
    << ",\"cap_r\":" << array(capsules, [&](std::size_t i) { return m.movingCapsule(cap(i)).c.radius; })
    << ",\"obs\":" << array(m.obstacles().size(), [&](std::size_t o) { return obstacleJson(m.obstacles()[o]); })
    << ",\"persons\":" << array(personCount, [&](std::size_t p) { return persons->name(static_cast<int>(p)); })
    << ",\"parts\":" << array(kBodyParts, [&](std::size_t k) { return std::string_view(bodyParts()[k].name); })
    << ",\"part_r\":" << array(kBodyParts, [&](std::size_t k) { return bodyParts()[k].radius; })
    << ",\"safe_time\":" << m.safety().safeTime() << ",\"min_separation\":" << m.safety().minSeparation;
  return j;
}

void appendCapsule(std::vector<std::int32_t>& out, const Capsule& c) {
  for (const Vec3* p : {&c.a, &c.b})
    for (int k = 0; k < 3; ++k) out.push_back(mm((*p)[k]));
}

// [a,b,...] of whole numbers (pose coordinates in mm, person indices)
JsonText intArray(const std::vector<std::int32_t>& v) {
  return array(v.size(), [&](std::size_t k) { return v[k]; });
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

  scene_ = sceneJson(m, persons).str();
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
        st.cause = w.outcome == Outcome::Overlapping ? "separation" : "collision";
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
  const std::string data = dataJson(title).str();
  io::writeTextFile(file, [&](std::ostream& os) { os << kPageHead << io::jsonForScript(data) << kPageTail; });
}

io::JsonText ReplayRecorder::dataJson(const std::string& title) const {
  const double tEnd = cycles_ ? lastT_ + cycleTime_ : 0.0;
  JsonText d(kDigits);
  d << "{\"title\":" << title << ",\"cycles\":" << cycles_ << ",\"t_end\":" << tEnd << ",\"stride\":" << stride_
    << "," << io::jsonRaw(scene_);
  d << ",\"ft\":" << array(frameT_.size(), [&](std::size_t f) { return frameT_[f]; });
  d << ",\"fc\":" << array(frameCaps_.size(), [&](std::size_t f) { return intArray(frameCaps_[f]); });
  // persons: per frame, each present person's index followed by its capsules' end points
  d << ",\"fp\":" << array(framePersons_.size(), [&](std::size_t f) { return intArray(framePersons_[f]); });
  d << ",\"rows\":" << rowsJson(armRows_, tEnd) << ",\"prows\":" << rowsJson(personRows_, tEnd);
  d << ",\"stops\":" << array(stops_.size(), [&](std::size_t k) { return stopJson(k); }) << "}";
  return d;
}

// per arm, its level segments [t0, t1, level] (an open one ends at tEnd)
io::JsonText ReplayRecorder::rowsJson(const std::vector<std::vector<Segment>>& rows, double tEnd) {
  return array(rows.size(), [&](std::size_t a) {
    return array(rows[a].size(), [&](std::size_t k) {
      const Segment& s = rows[a][k];
      JsonText j(kDigits);
      j << "[" << s.t0 << "," << (s.open ? tEnd : s.t1) << "," << s.level << "]";
      return j;
    });
  });
}

io::JsonText ReplayRecorder::stopJson(std::size_t k) const {
  const ReplayStop& s = stops_[k];
  // the frame that shows it: its own (kept while maxStopFrames allows), else the last before it
  const auto it = std::upper_bound(frameCycle_.begin(), frameCycle_.end(), stopCycle_[k]);
  const long f = std::max(0L, static_cast<long>(it - frameCycle_.begin()) - 1);
  JsonText j(kDigits);
  j << "{\"a\":" << s.arm << ",\"t\":" << s.t << ",\"cause\":" << s.cause << ",\"body\":" << s.body
    << ",\"other\":" << s.other << ",\"cap\":" << s.capsule << ",\"oc\":" << s.otherCapsule << ",\"ob\":" << s.obstacle
    << ",\"d\":" << s.distance << ",\"ttc\":" << s.ttc << ",\"f\":" << f << "}";
  return j;
}

}  // namespace st::arm
