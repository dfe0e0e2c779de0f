#include <stcosim/ssm_validation.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>

#include <stcore/toi.hpp>
#include <sthighway/conflict.hpp>
#include <sthighway/report.hpp>
#include <stio/format.hpp>
#include <stio/xml.hpp>
#include <stcosim/scenario.hpp>

namespace st::cosim {
namespace {

namespace hw = st::highway;

std::vector<std::string> words(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  std::string w;
  while (in >> w) out.push_back(w);
  return out;
}

// a number of an SSM file's tag at `line`, or "NA" (NaN)
double parseNumber(const io::XmlScanner& x, long line, const std::string& w) {
  if (w == "NA") return std::numeric_limits<double>::quiet_NaN();
  try {
    std::size_t used = 0;
    const double v = std::stod(w, &used);
    if (used == w.size()) return v;
  } catch (...) {
  }
  x.fail(line, "SSM output has a malformed number '" + w + "'");
}

// "x,y" or "NA" (SSM writes a position or a velocity so)
Vec2 parsePoint(const io::XmlScanner& x, long line, const std::string& w) {
  if (w == "NA") return SsmConflict::kNoPoint;
  const auto comma = w.find(',');
  if (comma == std::string::npos || w.find(',', comma + 1) != std::string::npos)
    x.fail(line, "SSM output has a malformed position '" + w + "'");
  return {parseNumber(x, line, w.substr(0, comma)), parseNumber(x, line, w.substr(comma + 1))};
}

// A tag's attribute, `def` where it has none (or there is no tag)
std::string attrText(const io::XmlScanner::Tag* tag, const char* key, const char* def) {
  const std::string* v = tag ? tag->attr(key) : nullptr;
  return v ? *v : std::string(def);
}

// A conflict's <minTTC> or <PET>: none without the tag or where its value is "NA"
struct SsmMeasure {
  bool present = false;
  double value = 0.0, time = 0.0;
  int type = -1;
  Vec2 position = SsmConflict::kNoPoint;
};
SsmMeasure readMeasure(const io::XmlScanner& x, const io::XmlScanner::Tag* m) {
  SsmMeasure out;
  if (!m || attrText(m, "value", "NA") == "NA") return out;
  out.present = true;
  out.value = parseNumber(x, m->line, attrText(m, "value", "NA"));
  out.time = parseNumber(x, m->line, attrText(m, "time", "NA"));
  const double type = parseNumber(x, m->line, attrText(m, "type", "NA"));
  out.type = std::isfinite(type) ? static_cast<int>(type) : -1;
  out.position = parsePoint(x, m->line, attrText(m, "position", "NA"));
  return out;
}

// One <conflict> of an SSM output file and its children; errors name the file and the tag's line.
SsmConflict readConflict(const io::XmlScanner& x, const io::XmlScanner::Tag& conflict,
                         const std::vector<io::XmlScanner::Tag>& children) {
  auto child = [&](const std::string& name) -> const io::XmlScanner::Tag* {
    for (const auto& c : children)
      if (c.name == name) return &c;
    return nullptr;
  };
  auto numbers = [&](const char* name, auto&& into) {
    const io::XmlScanner::Tag* tag = child(name);
    for (const auto& w : words(attrText(tag, "values", ""))) into(parseNumber(x, tag->line, w));
  };
  auto points = [&](const char* name, std::vector<Vec2>& into) {
    const io::XmlScanner::Tag* tag = child(name);
    for (const auto& w : words(attrText(tag, "values", ""))) into.push_back(parsePoint(x, tag->line, w));
  };
  const long line = conflict.line;
  SsmConflict c;
  c.ego = attrText(&conflict, "ego", "");
  c.foe = attrText(&conflict, "foe", "");
  c.begin = parseNumber(x, line, attrText(&conflict, "begin", "0"));
  c.end = parseNumber(x, line, attrText(&conflict, "end", "0"));
  numbers("timeSpan", [&](double v) { c.times.push_back(v); });
  numbers("typeSpan", [&](double v) { c.types.push_back(static_cast<int>(v)); });
  numbers("TTCSpan", [&](double v) { c.ttc.push_back(v); });
  numbers("DRACSpan", [&](double v) { c.drac.push_back(v); });
  points("conflictPoint", c.conflictPoints);
  points("egoVelocity", c.egoVelocities);
  points("foeVelocity", c.foeVelocities);
  points("egoPosition", c.egoPositions);
  points("foePosition", c.foePositions);
  const std::size_t n = c.times.size();
  const bool sameLengths = c.types.size() == n && c.ttc.size() == n && (c.drac.empty() || c.drac.size() == n) &&
                           c.conflictPoints.size() == n && c.egoVelocities.size() == n && c.foeVelocities.size() == n &&
                           (c.egoPositions.empty() || c.egoPositions.size() == n) &&
                           (c.foePositions.empty() || c.foePositions.size() == n);
  if (!sameLengths)
    x.fail(line, "SSM conflict " + c.ego + "/" + c.foe +
                     " has time, type, TTC, conflict point and velocity series of different lengths (trajectories off?)");
  const SsmMeasure minTtc = readMeasure(x, child("minTTC"));
  c.hasMin = minTtc.present;
  if (c.hasMin)
    c.minTtc = minTtc.value, c.minTtcTime = minTtc.time, c.minTtcType = minTtc.type, c.minTtcPosition = minTtc.position;
  const SsmMeasure pet = readMeasure(x, child("PET"));
  c.hasPet = pet.present;
  if (c.hasPet) {
    c.pet = pet.value, c.petTime = pet.time, c.petType = pet.type, c.petPosition = pet.position;
    if (!std::isfinite(c.pet) || !std::isfinite(c.petTime))
      x.fail(child("PET")->line, "SSM conflict " + c.ego + "/" + c.foe + " has a PET without a time");
  }
  return c;
}

// Horizon for the box TTC of SSM's pairs (s): well beyond any TTC SSM logs as a conflict.
constexpr double kValidationHorizon = 1.0e4;

// Two headings apart by more than this are a turn (SUMO's angle on a straight lane is exact; on the
// intersection every pair below 0.01 deg agrees with SSM to 0.02 s, and none between 0.01 and 0.5).
constexpr double kSameHeadingDeg = 0.1;
bool sameHeading(const hw::Body& a, const hw::Body& b) {
  return a.axis.dot(b.axis) >= std::cos(kSameHeadingDeg * std::numbers::pi / 180.0);
}

}  // namespace

double SsmConflict::petOffPath() const {
  // the distance from the PET position to a path of fronts (NaN: none known; "NA" points skipped)
  auto away = [&](const std::vector<Vec2>& path) {
    double best = std::numeric_limits<double>::quiet_NaN();
    const Vec2* last = nullptr;
    for (const Vec2& q : path) {
      if (!std::isfinite(q.x())) continue;
      const Vec2 near = last ? closestPointOnSegment(Segment{*last, q}, petPosition) : q;
      const double d = (petPosition - near).norm();
      if (!(d >= best)) best = d;
      last = &q;
    }
    return best;
  };
  return std::max(away(egoPositions), away(foePositions));
}

std::vector<std::string> ssmArguments(const std::filesystem::path& file, double threshold) {
  std::ostringstream th;
  th << threshold;
  // DRAC's threshold (a conflict above it) out of reach: its values are written, the conflicts
  // SSM logs stay those of TTC and PET
  return {"--device.ssm.probability", "1", "--device.ssm.deterministic", "true", "--device.ssm.measures", "TTC DRAC PET",
          "--device.ssm.thresholds", th.str() + " 1e9 " + th.str(), "--device.ssm.trajectories", "true", "--device.ssm.file",
          std::filesystem::absolute(file).string(), "--precision", "6"};
}

std::vector<SsmConflict> readSsmOutput(const std::filesystem::path& path) {
  io::XmlScanner x(path, io::raiseAs<ScenarioError>);
  x.requireBalanced();  // a file SUMO did not close is not read as whole
  io::XmlScanner::Tag t;
  if (!x.next(t) || t.closing || t.name != "SSMLog")
    x.fail(std::max(t.line, 1L), "not an SSM output file (no <SSMLog>)");
  std::vector<SsmConflict> out;
  while (x.next(t)) {
    if (t.closing || t.name != "conflict" || x.depth() != 1) continue;
    const io::XmlScanner::Tag conflict = t;
    // its children by name (the first of each, as SSM writes each once)
    std::vector<io::XmlScanner::Tag> children;
    if (!conflict.selfClosing)
      while (x.next(t) && x.depth() > 1)
        if (!t.closing && x.depth() == 2 &&
            std::none_of(children.begin(), children.end(), [&](const auto& c) { return c.name == t.name; }))
          children.push_back(t);
    out.push_back(readConflict(x, conflict, children));
  }
  return out;
}

struct SsmValidator::Impl {
  struct Rec {
    int vid;
    hw::Body body;
    double mass;
    hw::VehicleClass cls;
    bool equipped;
  };
  struct Frame {
    double t;
    std::vector<Rec> recs;  // sorted by vid
  };

  double dt;
  hw::MonitorConfig base;
  std::vector<hw::HighwayMonitor> monitors;
  std::vector<std::vector<hw::Warning>> warnings;
  std::vector<hw::Conflict> conflicts;  // conflicts.csv's rows (the last monitor's: any finds them all)
  std::vector<hw::Conflict> settled;    // scratch

  void takeConflicts() {
    monitors.back().takeConflicts(settled);
    for (auto& c : settled) conflicts.push_back(std::move(c));
  }
  std::unordered_map<std::string, int> ids;
  std::vector<Frame> frames;

  const Rec* find(const std::string& id, double t) const {
    if (frames.empty()) return nullptr;
    const auto it = ids.find(id);
    if (it == ids.end()) return nullptr;
    const double k = std::round((t - frames.front().t) / dt);
    if (k < 0 || k >= static_cast<double>(frames.size())) return nullptr;
    const Frame& f = frames[static_cast<std::size_t>(k)];
    if (std::abs(f.t - t) > 0.25 * dt) return nullptr;
    const auto r = std::lower_bound(f.recs.begin(), f.recs.end(), it->second,
                                    [](const Rec& a, int v) { return a.vid < v; });
    return r != f.recs.end() && r->vid == it->second ? &*r : nullptr;
  }

  // The evaluation's stages (SsmValidator::evaluate), each filling its part of the report.
  using PairKey = std::pair<std::string, std::string>;
  using SsmByPair = std::map<PairKey, std::vector<const SsmConflict*>>;
  void followingSamples(const std::vector<SsmConflict>& ssm, ValidationReport& r) const;
  void recall(std::size_t d, const std::vector<SsmConflict>& ssm, DetectorValidation& dv) const;
  void precision(std::size_t d, const std::map<PairKey, std::vector<double>>& seen, DetectorValidation& dv) const;
  void petAgreement(const std::vector<SsmConflict>& ssm, ValidationReport& r) const;
  void conflictPetAgreement(const std::vector<SsmConflict>& ssm, ValidationReport& r) const;
  std::pair<const SsmConflict*, std::size_t> sampleAt(const SsmByPair& byPair, const hw::Warning& w, double t) const;
  // Calls visit(conflict, i, aIsEgo) on each of the pair's SSM samples at our tick t, a's device
  // first, until it returns true.
  template <class Visit>
  void pairSamplesAt(const SsmByPair& byPair, const std::string& a, const std::string& b, double t, Visit visit) const {
    for (const bool aIsEgo : {true, false}) {
      const auto it = byPair.find(aIsEgo ? PairKey{a, b} : PairKey{b, a});
      if (it == byPair.end()) continue;
      for (const SsmConflict* c : it->second)
        for (std::size_t i = 0; i < c->times.size(); ++i)
          if (std::abs(c->times[i] + dt - t) < 0.25 * dt && visit(*c, i, aIsEgo)) return;
    }
  }
  void conflictPoints(const SsmByPair& byPair, ValidationReport& r) const;
  void crossingPoints(const SsmByPair& byPair, ValidationReport& r) const;
  void pathsMeetPoints(const SsmByPair& byPair, ValidationReport& r) const;
  void encounterTypes(const SsmByPair& byPair, ValidationReport& r) const;
  void encounterPrecision(const std::map<PairKey, std::vector<double>>& seen, std::span<const SumoCollision> contacts,
                          ValidationReport& r) const;
};

SsmValidator::SsmValidator(const hw::RoadGeometry& road, const hw::MonitorConfig& base, double deltaT)
    : impl_(std::make_unique<Impl>()) {
  impl_->dt = deltaT;
  impl_->base = base;
  for (hw::DetectorKind k : {hw::DetectorKind::Concentric, hw::DetectorKind::FiveCircle, hw::DetectorKind::Box}) {
    hw::MonitorConfig c = base;
    c.detector.kind = k;
    impl_->monitors.emplace_back(road, c);
    impl_->warnings.emplace_back();
  }
}

SsmValidator::~SsmValidator() = default;

void SsmValidator::record(double t, std::span<const hw::VehicleState> states) {
  Impl::Frame f;
  f.t = t;
  f.recs.reserve(states.size());
  for (const auto& s : states) {
    auto [it, fresh] = impl_->ids.try_emplace(s.id, static_cast<int>(impl_->ids.size()));
    // SSM's following TTC is at constant speeds: the body without its braking to a red light
    hw::Body b = hw::bodyOf(s);
    b.stopAcceleration = 0.0;
    f.recs.push_back({it->second, b, s.mass, s.vehicleClass, s.equipped});
  }
  std::sort(f.recs.begin(), f.recs.end(), [](const Impl::Rec& a, const Impl::Rec& b) { return a.vid < b.vid; });
  impl_->frames.push_back(std::move(f));
  for (std::size_t i = 0; i < impl_->monitors.size(); ++i) {
    impl_->monitors[i].step(t, states);
    for (auto& w : impl_->monitors[i].takeFinished()) impl_->warnings[i].push_back(std::move(w));
  }
  impl_->takeConflicts();
}

void SsmValidator::finish(double t) {
  for (std::size_t i = 0; i < impl_->monitors.size(); ++i) {
    impl_->monitors[i].finish(t);
    for (auto& w : impl_->monitors[i].takeFinished()) impl_->warnings[i].push_back(std::move(w));
  }
  impl_->takeConflicts();
}

namespace {
// "ego>foe@t", as every worst case names its sample
std::string pairLabel(const std::string& ego, const std::string& foe, double t) {
  std::ostringstream os;
  os << ego << ">" << foe << "@" << t;
  return os.str();
}
}  // namespace

void SsmValidator::Impl::followingSamples(const std::vector<SsmConflict>& ssm, ValidationReport& r) const {
  // 1. following samples: box TTC at T + dt against SSM's TTC at T
  for (const auto& c : ssm) {
    for (std::size_t i = 0; i < c.times.size(); ++i) {
      if (c.types[i] != kSsmFollowingFollower || !std::isfinite(c.ttc[i])) continue;
      r.followingSamples++;
      for (int shifted = 1; shifted >= 0; --shifted) {
        const double t = c.times[i] + (shifted ? dt : 0.0);
        const auto* ego = find(c.ego, t);
        const auto* foe = find(c.foe, t);
        if (!ego || !foe) continue;
        const Impact hit = hw::boxTtc(ego->body, foe->body, hw::MotionModel::ConstantVelocity, kValidationHorizon);
        if (!hit.acts()) continue;
        const double box = hit.actTime();
        const double err = std::abs(box - c.ttc[i]);
        if (shifted) {
          // the sample's name only where it may become the worst (tens of thousands of samples)
          auto what = [&] { return c.ego + ">" + c.foe + "@" + io::number(t, 6); };  // as the other labels
          r.ttc.add(err, err > r.ttc.maxAbsError || r.ttc.matched == 0 ? what() : std::string());
          Agreement& part = sameHeading(ego->body, foe->body) ? r.ttcSameHeading : r.ttcTurning;
          part.add(err, err > part.maxAbsError || part.matched == 0 ? what() : std::string());
          if (i < c.drac.size() && std::isfinite(c.drac[i])) {
            // ours as conflicts.csv's: the rate the centre distance shrinks over twice the TTC
            r.dracSamples++;
            const Vec2 rel = foe->body.position - ego->body.position, vrel = foe->body.velocity - ego->body.velocity;
            const double dist = rel.norm();
            const double ours = hw::decelerationToAvoid(dist > 0.0 ? -rel.dot(vrel) / dist : vrel.norm(), box);
            if (std::isfinite(ours)) {
              const double dracErr = std::abs(ours - c.drac[i]);
              r.drac.add(dracErr, dracErr > r.drac.maxAbsError || r.drac.matched == 0 ? what() : std::string());
            }
          }
        } else {
          r.matchedUnshifted++;
          if (err <= r.ttc.tolerance) r.withinUnshifted++;
        }
      }
    }
  }
}

void SsmValidator::Impl::recall(std::size_t d, const std::vector<SsmConflict>& ssm, DetectorValidation& dv) const {
  // the car-car episodes of each ordered pair: (begin, end, one of SSAM's types)
  struct Span {
    double begin, end;
    bool conflict;
  };
  std::map<PairKey, std::vector<Span>> episodes;
  for (const auto& w : warnings[d])
    if (w.kind == hw::WarningKind::Vehicle) episodes[{w.ego, w.foe}].push_back({w.begin, w.end, hw::isSsamType(w.type)});
  // 2. recall over SSM conflicts below the ego's safe time
  for (const auto& c : ssm) {
    if (!c.hasMin || (c.minTtcType != kSsmFollowing && c.minTtcType != kSsmFollowingFollower &&
                      c.minTtcType != kSsmFollowingLeader))
      continue;
    const double t = c.minTtcTime + dt;
    const auto* ego = find(c.ego, t);
    const auto* foe = find(c.foe, t);
    if (!ego || !foe || !ego->equipped) continue;
    const Vec2 p = foe->body.position - ego->body.position;
    const Vec2 v = foe->body.velocity - ego->body.velocity;
    const double closing = p.norm() > 0.0 ? -p.dot(v) / p.norm() : 0.0;
    const double safe = base.safeTime.vehicleSafeTime(ego->mass, closing, ego->cls);
    if (!(c.minTtc < safe)) continue;
    dv.conflicts++;
    bool hit = false, byConflict = false;
    if (auto it = episodes.find({c.ego, c.foe}); it != episodes.end())
      for (const Span& s : it->second)
        if (s.begin <= t + 1e-6 && t <= s.end + 1e-6) {
          hit = true;
          byConflict = byConflict || s.conflict;
        }
    if (byConflict) dv.recalledByConflicts++;
    if (hit) dv.recalled++;
    else if (dv.missed.size() < 20) {
      std::ostringstream os;
      os << c.ego << ">" << c.foe << "@" << t << " ssm_ttc=" << c.minTtc << " safe=" << safe;
      dv.missed.push_back(os.str());
    }
  }
}

void SsmValidator::Impl::precision(std::size_t d, const std::map<PairKey, std::vector<double>>& seen, DetectorValidation& dv) const {
  // 3. precision over this detector's car-car warnings
  for (const auto& w : warnings[d]) {
    if (w.kind != hw::WarningKind::Vehicle) continue;
    dv.warnings++;
    bool confirmed = false;
    if (auto it = seen.find(std::minmax(w.ego, w.foe)); it != seen.end()) {
      const auto lo = std::lower_bound(it->second.begin(), it->second.end(), w.begin - dt - 1e-6);
      confirmed = lo != it->second.end() && *lo <= w.end + dt + 1e-6;
    }
    if (confirmed) dv.confirmed++;
    else dv.unseenByZone[static_cast<std::size_t>(w.zone)]++;
    if (hw::isSsamType(w.type)) {
      dv.conflictWarnings++;
      if (confirmed) dv.conflictsConfirmed++;
    }
  }
}

void SsmValidator::Impl::petAgreement(const std::vector<SsmConflict>& ssm, ValidationReport& r) const {
  // 4. PET: each SSM PET against the box episode of the same ordered pair with a PET, overlapping
  // in time (its PET horizon included), the one beginning nearest
  std::map<PairKey, std::vector<const hw::Warning*>> boxPets;
  for (const auto& w : warnings.back())
    if (w.kind == hw::WarningKind::Vehicle && std::isfinite(w.pet)) boxPets[{w.ego, w.foe}].push_back(&w), r.stsimPets++;
  for (const auto& c : ssm) {
    if (!c.hasPet) continue;
    r.ssmPets++;
    const auto it = boxPets.find({c.ego, c.foe});
    if (it == boxPets.end()) continue;
    const double begin = c.begin + dt, end = c.end + dt;
    const hw::Warning* best = nullptr;
    for (const hw::Warning* w : it->second) {
      if (w->begin > end + 1e-6 || w->end + hw::kPetHorizon < begin - 1e-6) continue;
      if (!best || std::abs(w->begin - begin) < std::abs(best->begin - begin)) best = w;
    }
    if (!best) continue;
    const std::string what = pairLabel(c.ego, c.foe, c.petTime + dt);
    r.pet.add(std::abs(best->pet - c.pet), what);
    if (c.petOffPath() > kSsmPetOffPath) r.petOffPath++;
    else r.petOnPaths.add(std::abs(best->pet - c.pet), what);
  }
}

void SsmValidator::Impl::conflictPetAgreement(const std::vector<SsmConflict>& ssm, ValidationReport& r) const {
  // 4b. the analyst's PET: each SSM encounter with a PET (once per pair and PET time) against the
  // conflict of the pair in conflicts.csv whose span holds SSM's PET time, the one beginning nearest
  std::map<PairKey, std::vector<const hw::Conflict*>> conflictPets;
  for (const auto& c : this->conflicts)
    if (std::isfinite(c.pet)) conflictPets[std::minmax(c.first, c.second)].push_back(&c), r.conflictPets++;
  std::set<std::pair<std::pair<std::string, std::string>, long long>> petsSeen;
  for (const auto& c : ssm) {
    if (!c.hasPet) continue;
    const auto pair = std::minmax(c.ego, c.foe);
    if (!petsSeen.insert({pair, std::llround(c.petTime / dt)}).second) continue;
    r.ssmPetEncounters++;
    const auto it = conflictPets.find(pair);
    if (it == conflictPets.end()) continue;
    const double at = c.petTime + dt;
    const hw::Conflict* best = nullptr;
    for (const hw::Conflict* k : it->second) {
      if (at < k->begin - 1e-6 || at > k->end + hw::kPetHorizon + 1e-6) continue;
      if (!best || std::abs(k->begin - at) < std::abs(best->begin - at)) best = k;
    }
    if (!best) continue;
    r.conflictPet.add(std::abs(best->pet - c.pet), pairLabel(pair.first, pair.second, at));
    if (c.petOffPath() > kSsmPetOffPath) r.conflictPetOffPath++;
    else r.conflictPetOnPaths.add(std::abs(best->pet - c.pet), pairLabel(pair.first, pair.second, at));
  }
}

std::pair<const SsmConflict*, std::size_t> SsmValidator::Impl::sampleAt(const SsmByPair& byPair, const hw::Warning& w,
                                                                        double t) const {
  const auto it = byPair.find({w.ego, w.foe});
  if (it != byPair.end())
    for (const SsmConflict* c : it->second) {
      const auto at = std::find_if(c->times.begin(), c->times.end(), [&](double x) { return std::abs(x + dt - t) < 0.25 * dt; });
      if (at != c->times.end()) return {c, static_cast<std::size_t>(at - c->times.begin())};
    }
  return {nullptr, 0};
}

void SsmValidator::Impl::conflictPoints(const SsmByPair& byPair, ValidationReport& r) const {
  // 5. the conflict point at each box episode's minimum-TTC tick, SSM's moved on to the contact
  for (const auto& w : warnings.back()) {
    if (w.kind != hw::WarningKind::Vehicle || !std::isfinite(w.conflictX)) continue;
    r.pointEpisodes++;
    // SSM's following point is a rear-end geometry: the leader's back (a lane change's contact is
    // a corner on a side)
    if (w.type != hw::ConflictType::RearEnd) continue;
    const auto [c, i] = sampleAt(byPair, w, w.minTtcTime);
    if (!c) continue;
    const bool egoLeads = c->types[i] == kSsmFollowingLeader;
    if ((c->types[i] != kSsmFollowingFollower && !egoLeads) || !std::isfinite(c->ttc[i]) ||
        !std::isfinite(c->conflictPoints[i].x()))
      continue;
    const Vec2 v = egoLeads ? c->egoVelocities[i] : c->foeVelocities[i];
    if (!std::isfinite(v.x())) continue;
    const Vec2 ssm = c->conflictPoints[i] + c->ttc[i] * v;
    const Vec2 d = Vec2(w.conflictX, w.conflictY) - ssm;
    const std::string what = pairLabel(w.ego, w.foe, w.minTtcTime);
    r.pointAnyTtc.add(d.norm(), what);
    if (std::abs(c->ttc[i] - w.minTtc) > r.ttc.tolerance) continue;
    r.point.add(d.norm(), what);
    r.pointUnconverted.add((Vec2(w.conflictX, w.conflictY) - c->conflictPoints[i]).norm(), what);
    // along the leader's path: its velocity's direction (its body's axis when it stands)
    const auto* leader = find(egoLeads ? w.ego : w.foe, w.minTtcTime);
    const Vec2 axis = v.norm() > 0.0 ? Vec2(v.normalized()) : leader ? leader->body.axis : Vec2(1.0, 0.0);
    r.pointAlong.add(std::abs(d.dot(axis)), what);
  }
}

void SsmValidator::Impl::crossingPoints(const SsmByPair& byPair, ValidationReport& r) const {
  // 6. where paths cross or merge: SSM's point (the follower's entry) along the follower's path
  for (const auto& w : warnings.back()) {
    if (w.kind != hw::WarningKind::Vehicle || !std::isfinite(w.conflictX) ||
        (w.type != hw::ConflictType::LaneChange && w.type != hw::ConflictType::Crossing))
      continue;
    r.crossingEpisodes++;
    const auto [c, i] = sampleAt(byPair, w, w.minTtcTime);
    if (!c || !std::isfinite(c->conflictPoints[i].x())) continue;
    const int type = c->types[i];
    const bool egoLeads = type == kSsmCrossingLeader || type == kSsmMergingLeader;
    if (!egoLeads && type != kSsmCrossingFollower && type != kSsmMergingFollower) continue;
    const Vec2 v = egoLeads ? c->foeVelocities[i] : c->egoVelocities[i];
    if (!std::isfinite(v.x()) || v.norm() == 0.0) continue;
    const Vec2 d = Vec2(w.conflictX, w.conflictY) - c->conflictPoints[i];
    const std::string what = pairLabel(w.ego, w.foe, w.minTtcTime);
    r.crossingAlong.add(std::abs(d.dot(v.normalized())), what);
    r.crossingPoint.add(d.norm(), what);
  }
}

void SsmValidator::Impl::pathsMeetPoints(const SsmByPair& byPair, ValidationReport& r) const {
  // 6b. SSM's point at a merge is the merge point; at a crossing, where one vehicle's front enters
  // the conflict area: half the other's width before the lanes' crossing, along its lane (SUMO
  // 1.15, measured on right-angle and oblique crossings alike: no 1 / sine). Whose entry: the
  // ego's as follower, once the foe is in the area, or once the ego has left it; else the foe's;
  // with both in it, the later one's (ours).
  for (const hw::Conflict& k : conflicts) {
    const bool merging = k.encounter == hw::EncounterType::Merging;
    if (!std::isfinite(k.pathsMeetX) ||
        (!merging && k.encounter != hw::EncounterType::Crossing && k.encounter != hw::EncounterType::Opposing))
      continue;
    r.pathsMeetConflicts++;
    const Vec2 meet(k.pathsMeetX, k.pathsMeetY);
    pairSamplesAt(byPair, k.first, k.second, k.minTtcTime, [&](const SsmConflict& c, std::size_t i, bool firstIsEgo) {
      const int t = c.types[i];
      if (!std::isfinite(c.conflictPoints[i].x()) ||
          !(t == kSsmMergingLeader || t == kSsmMergingFollower || (t >= kSsmCrossingLeader && t <= kSsmFoeLeftArea)))
        return false;
      const bool egoEnters = t == kSsmMergingFollower || t == kSsmCrossingFollower || t == kSsmFoeEnteredArea ||
                             t == kSsmEgoLeftArea;
      const bool foeEnters = t == kSsmMergingLeader || t == kSsmCrossingLeader || t == kSsmEgoEnteredArea ||
                             t == kSsmFoeLeftArea;
      const bool firstEnters = firstIsEgo ? egoEnters : foeEnters;
      const Vec2 entry = merging ? meet
                                 : Vec2(meet - 0.5 * (firstEnters ? k.secondWidth : k.firstWidth) *
                                                   (firstEnters ? k.firstAlong : k.secondAlong));
      const Vec2 ssm = c.conflictPoints[i];
      const std::string what = pairLabel(k.first, k.second, k.minTtcTime);
      r.pathsMeet.add((entry - ssm).norm(), what);
      // SSM's point off the other's lane (SUMO's left turn split at its wait point): not a point
      // on both paths, said apart
      if (!merging && std::abs(cross(firstEnters ? k.secondAlong : k.firstAlong, ssm - meet)) > kSsmPetOffPath)
        r.pathsMeetOffPath++;
      else
        r.pathsMeetOnPaths.add((entry - ssm).norm(), what);
      return true;
    });
  }
}

// The stages in order: 1. following samples, 2.-3. each detector's recall and precision, 4. the
// PETs, 5. the rear-end conflict points, 6. the crossing and merging points, 7.-8. the conflicts'
// encounters against SSM's classes and SSM's sight of them.
ValidationReport SsmValidator::evaluate(const std::vector<SsmConflict>& conflicts,
                                        std::span<const SumoCollision> contacts) const {
  const Impl& m = *impl_;
  ValidationReport r;
  r.deltaT = m.dt;
  r.ssmConflicts = conflicts.size();
  m.followingSamples(conflicts, r);
  // SSM's finite-TTC sample times (our clock) per unordered pair, for precision
  std::map<Impl::PairKey, std::vector<double>> seen;
  for (const auto& c : conflicts) {
    auto& v = seen[std::minmax(c.ego, c.foe)];
    for (std::size_t i = 0; i < c.times.size(); ++i)
      if (std::isfinite(c.ttc[i])) v.push_back(c.times[i] + m.dt);
  }
  for (auto& [k, v] : seen) std::sort(v.begin(), v.end());
  static const char* names[] = {"concentric", "five", "box"};
  for (std::size_t d = 0; d < m.monitors.size(); ++d) {
    DetectorValidation dv;
    dv.detector = names[d];
    m.recall(d, conflicts, dv);
    m.precision(d, seen, dv);
    r.detectors.push_back(std::move(dv));
  }
  m.petAgreement(conflicts, r);
  m.conflictPetAgreement(conflicts, r);
  // SSM's conflicts by ordered pair
  Impl::SsmByPair byPair;
  for (const auto& c : conflicts) byPair[{c.ego, c.foe}].push_back(&c);
  m.conflictPoints(byPair, r);
  m.crossingPoints(byPair, r);
  m.pathsMeetPoints(byPair, r);
  m.encounterTypes(byPair, r);
  m.encounterPrecision(seen, contacts, r);
  return r;
}

SsmEncounterClass ssmEncounterClass(int t) {
  if (t >= 1 && t <= 3) return SsmEncounterClass::Following;
  if (t == 4) return SsmEncounterClass::Adjacent;
  if (t >= 5 && t <= 8) return SsmEncounterClass::Merging;
  if (t >= 9 && t <= 11) return SsmEncounterClass::Crossing;
  if (t == 18) return SsmEncounterClass::FollowingPassed;
  if (t == 19) return SsmEncounterClass::MergingPassed;
  if (t == 20) return SsmEncounterClass::Oncoming;
  return SsmEncounterClass::None;
}

SsmEncounterClass ssmEncounterClassAt(const SsmConflict& c, std::size_t i) {
  const int t = c.types[i];
  const bool inArea = (t >= 12 && t <= 17) || t == 111;
  if (!inArea) return ssmEncounterClass(t);
  // in or past the conflict area, or colliding: the class the pair had before
  for (std::size_t k = i; k-- > 0;)
    if (const SsmEncounterClass x = ssmEncounterClass(c.types[k]); x != SsmEncounterClass::None) return x;
  return SsmEncounterClass::None;
}

const char* toString(SsmEncounterClass c) {
  switch (c) {
    case SsmEncounterClass::None: return "none";
    case SsmEncounterClass::Following: return "following";
    case SsmEncounterClass::Adjacent: return "adjacent";
    case SsmEncounterClass::Merging: return "merging";
    case SsmEncounterClass::Crossing: return "crossing";
    case SsmEncounterClass::FollowingPassed: return "following_passed";
    case SsmEncounterClass::MergingPassed: return "merging_passed";
    case SsmEncounterClass::Oncoming: return "oncoming";
  }
  return "?";
}

SsmEncounterClass ssmClassOf(hw::EncounterType e) {
  switch (e) {
    case hw::EncounterType::Following: return SsmEncounterClass::Following;
    case hw::EncounterType::Adjacent: return SsmEncounterClass::Adjacent;
    case hw::EncounterType::Merging: return SsmEncounterClass::Merging;
    case hw::EncounterType::Crossing:
    case hw::EncounterType::Opposing: return SsmEncounterClass::Crossing;
    case hw::EncounterType::Diverging: return SsmEncounterClass::FollowingPassed;
    case hw::EncounterType::Pedestrian:
    case hw::EncounterType::Unknown: return SsmEncounterClass::None;
  }
  return SsmEncounterClass::None;
}

void SsmValidator::Impl::encounterTypes(const SsmByPair& byPair, ValidationReport& r) const {
  // 7. each conflict's encounter against SSM's class of the pair at its minimum-TTC tick (either
  // vehicle's device: the first with a classed sample there)
  for (const hw::Conflict& k : conflicts) {
    if (k.encounter == hw::EncounterType::Unknown || k.encounter == hw::EncounterType::Pedestrian) continue;
    r.encounterConflicts++;
    SsmEncounterClass ssm = SsmEncounterClass::None;
    pairSamplesAt(byPair, k.first, k.second, k.minTtcTime, [&](const SsmConflict& c, std::size_t i, bool) {
      ssm = ssmEncounterClassAt(c, i);
      return ssm != SsmEncounterClass::None;
    });
    if (ssm == SsmEncounterClass::None) continue;
    r.encounterMatched++;
    if (ssmClassOf(k.encounter) == ssm) r.encounterAgree++;
    r.encounterPairs[std::string(hw::toString(k.encounter)) + "/" + toString(ssm)]++;
  }
}

void SsmValidator::Impl::encounterPrecision(const std::map<PairKey, std::vector<double>>& seen,
                                            std::span<const SumoCollision> contacts, ValidationReport& r) const {
  // 8. each conflict: did SSM log the pair with a finite TTC while it lasted, else did they touch,
  // else did they come closer than the clearance
  for (const hw::Conflict& k : conflicts) {
    const double from = k.begin - dt - 1e-6, to = k.end + dt + 1e-6;
    const PairKey pair = std::minmax(k.first, k.second);
    bool sawTtc = false;
    if (auto it = seen.find(pair); it != seen.end()) {
      const auto lo = std::lower_bound(it->second.begin(), it->second.end(), from);
      sawTtc = lo != it->second.end() && *lo <= to;
    }
    const bool collided = !sawTtc && std::any_of(contacts.begin(), contacts.end(), [&](const SumoCollision& c) {
      return PairKey(std::minmax(c.collider, c.victim)) == pair && c.time >= from && c.time <= to;
    });
    // else what SUMO did next: the two bodies at SUMO's positions, closer than hindsight's clearance
    // from the conflict's begin to the end of its PET horizon
    bool close = false;
    if (!sawTtc && !collided)
      for (double t = k.begin; t <= k.end + hw::kPetHorizon + 1e-6 && !close; t += dt) {
        const Rec* a = find(k.first, t);
        const Rec* b = find(k.second, t);
        close = a && b && distance(a->body.box(), b->body.box()) < base.hindsight.clearance;
      }
    const auto add = [&](ValidationReport::EncounterPrecision& p) {
      p.conflicts++;
      p.seen += sawTtc;
      p.collided += collided;
      p.close += close;
    };
    add(r.byEncounter[hw::toString(k.encounter)]);
    const SsmEncounterClass cls = ssmClassOf(k.encounter);
    if (cls == SsmEncounterClass::Following || cls == SsmEncounterClass::Merging || cls == SsmEncounterClass::Crossing)
      add(r.ssmModels);
  }
}

void Agreement::add(double absError, const std::string& what) {
  if (matched == 0 || absError > maxAbsError) {
    maxAbsError = absError;
    worst = what;
  }
  matched++;
  sumAbsError += absError;
  if (absError <= tolerance) within++;
}

double Agreement::meanAbsError() const {
  return matched == 0 ? std::numeric_limits<double>::quiet_NaN() : sumAbsError / static_cast<double>(matched);
}

double Agreement::withinFraction() const { return DetectorValidation::share(within, matched); }

namespace {
// matched, tolerance, within, share, max and mean error (in `unit`), the worst case
std::string agreementJson(const Agreement& a, const char* unit) {
  auto num = [](double x) { return io::jsonNumber(x, 10); };
  const std::string u = unit;
  std::ostringstream os;
  os << "\"matched\": " << a.matched << ", \"tolerance_" << u << "\": " << num(a.tolerance) << ", \"within_tolerance\": "
     << a.within << ", \"within_fraction\": " << num(a.withinFraction()) << ", \"max_abs_error_" << u
     << "\": " << num(a.maxAbsError) << ", \"mean_abs_error_" << u << "\": " << num(a.meanAbsError())
     << ", \"worst\": " << io::jsonString(a.worst);
  return os.str();
}
}  // namespace

std::string toJson(const ValidationReport& r) {
  auto num = [](double x) { return io::jsonNumber(x, 10); };
  std::ostringstream os;
  os << "{\n  \"delta_t_s\": " << num(r.deltaT) << ",\n  \"ssm_conflicts\": " << r.ssmConflicts
     << ",\n  \"following\": {\n    \"ssm_samples\": " << r.followingSamples << ",\n    \"matched_samples\": "
     << r.ttc.matched << ",\n    \"tolerance_s\": " << num(r.ttc.tolerance) << ",\n    \"within_tolerance\": " << r.ttc.within
     << ",\n    \"within_fraction\": " << num(r.ttc.withinFraction()) << ",\n    \"max_abs_error_s\": " << num(r.ttc.maxAbsError)
     << ",\n    \"mean_abs_error_s\": " << num(r.ttc.meanAbsError()) << ",\n    \"worst\": " << io::jsonString(r.ttc.worst)
     << ",\n    \"same_heading\": {" << agreementJson(r.ttcSameHeading, "s") << "},\n    \"turning\": {"
     << agreementJson(r.ttcTurning, "s") << "},\n    \"without_time_shift\": {\"matched_samples\": " << r.matchedUnshifted
     << ", \"within_tolerance\": " << r.withinUnshifted << "}\n  },\n  \"drac\": {\"ssm_samples\": " << r.dracSamples
     << ", " << agreementJson(r.drac, "m_s2") << "},\n  \"pet\": {\"ssm_pets\": " << r.ssmPets
     << ", \"stsim_pets\": " << r.stsimPets << ", " << agreementJson(r.pet, "s") << ", \"ssm_off_path\": " << r.petOffPath
     << ",\n    \"on_both_paths\": {" << agreementJson(r.petOnPaths, "s") << "},"
     << "\n    \"conflicts\": {\"ssm_encounters\": " << r.ssmPetEncounters << ", \"conflict_pets\": " << r.conflictPets
     << ", " << agreementJson(r.conflictPet, "s") << ", \"ssm_off_path\": " << r.conflictPetOffPath
     << ",\n      \"on_both_paths\": {" << agreementJson(r.conflictPetOnPaths, "s") << "}}},\n  \"conflict_point\": {\"box_episodes\": " << r.pointEpisodes << ", \"ssm_following\": "
     << r.pointAnyTtc.matched << ", " << agreementJson(r.point, "m") << ",\n    \"along_leader_path\": {"
     << agreementJson(r.pointAlong, "m") << "},\n    \"whatever_the_ttc\": {" << agreementJson(r.pointAnyTtc, "m")
     << "},\n    \"without_moving_on\": {\"matched\": " << r.pointUnconverted.matched << ", \"within_tolerance\": "
     << r.pointUnconverted.within << "},\n    \"crossing\": {\"box_episodes\": " << r.crossingEpisodes << ", "
     << agreementJson(r.crossingAlong, "m") << ",\n      \"distance\": {" << agreementJson(r.crossingPoint, "m")
     << "}},\n    \"paths_meet\": {\"conflicts\": " << r.pathsMeetConflicts << ", " << agreementJson(r.pathsMeet, "m")
     << ", \"ssm_off_path\": " << r.pathsMeetOffPath << ",\n      \"on_both_paths\": {"
     << agreementJson(r.pathsMeetOnPaths, "m") << "}}},\n  \"encounter\": {\"conflicts\": " << r.encounterConflicts << ", \"matched\": " << r.encounterMatched
     << ", \"agree\": " << r.encounterAgree << ", \"agree_fraction\": "
     << num(DetectorValidation::share(r.encounterAgree, r.encounterMatched)) << ", \"ours_ssm\": {";
  {
    bool first = true;
    for (const auto& [pair, n] : r.encounterPairs) {
      os << (first ? "" : ", ") << io::jsonString(pair) << ": " << n;
      first = false;
    }
  }
  const auto precisionJson = [&](const ValidationReport::EncounterPrecision& p) {
    os << "{\"conflicts\": " << p.conflicts << ", \"seen_by_ssm\": " << p.seen << ", \"collided\": " << p.collided
       << ", \"came_close\": " << p.close << ", \"precision\": " << num(DetectorValidation::share(p.seen + p.collided, p.conflicts))
       << ", \"confirmed\": " << num(DetectorValidation::share(p.seen + p.collided + p.close, p.conflicts)) << "}";
  };
  os << "},\n    \"where_ssm_models\": ";
  precisionJson(r.ssmModels);
  os << ",\n    \"by_encounter\": {";
  {
    bool first = true;
    for (const auto& [name, p] : r.byEncounter) {
      os << (first ? "" : ", ") << io::jsonString(name) << ": ";
      precisionJson(p);
      first = false;
    }
  }
  os << "}},\n  \"detectors\": [";
  for (std::size_t i = 0; i < r.detectors.size(); ++i) {
    const auto& d = r.detectors[i];
    os << (i ? "," : "") << "\n    {\"detector\": " << io::jsonString(d.detector)
       << ", \"ssm_conflicts_below_safe_time\": " << d.conflicts << ", \"recalled\": " << d.recalled
       << ", \"recall\": " << num(d.recall()) << ", \"warnings\": " << d.warnings << ", \"confirmed_by_ssm\": " << d.confirmed
       << ", \"precision\": " << num(d.precision()) << ",\n     \"conflicts\": {\"recalled\": " << d.recalledByConflicts
       << ", \"recall\": " << num(d.conflictRecall()) << ", \"warnings\": " << d.conflictWarnings
       << ", \"confirmed_by_ssm\": " << d.conflictsConfirmed << ", \"precision\": " << num(d.conflictPrecision())
       << "},\n     \"not_seen_by_ssm_by_zone\": {";
    bool first = true;
    for (int z = 0; z < highway::kZoneCount; ++z) {
      if (d.unseenByZone[static_cast<std::size_t>(z)] == 0) continue;
      os << (first ? "" : ", ") << io::jsonString(highway::toString(static_cast<highway::Zone>(z))) << ": "
         << d.unseenByZone[static_cast<std::size_t>(z)];
      first = false;
    }
    os << "},\n     \"missed\": [";
    for (std::size_t k = 0; k < d.missed.size(); ++k) os << (k ? ", " : "") << io::jsonString(d.missed[k]);
    os << "]}";
  }
  os << "\n  ]\n}\n";
  return os.str();
}

std::string summaryLine(const ValidationReport& r) {
  auto figure = [](double x, int decimals, const char* none) { return std::isnan(x) ? std::string(none) : io::fixed(x, decimals); };
  std::ostringstream os;
  os << r.ttc.matched << " following samples, ";
  if (r.ttc.matched == 0) os << "none matched by a box TTC;";
  else {
    os << io::fixed(100.0 * r.ttc.withinFraction(), 2) << " % within " << r.ttc.tolerance << " s of SSM's TTC";
    if (r.ttcTurning.matched > 0)
      os << " (" << io::fixed(100.0 * r.ttcSameHeading.withinFraction(), 2) << " % of the " << r.ttcSameHeading.matched
         << " on one heading, " << io::fixed(100.0 * r.ttcTurning.withinFraction(), 2) << " % of the " << r.ttcTurning.matched
         << " in a turn)";
    os << ";";
  }
  auto agreement = [&](const Agreement& a, const char* what, const char* unit) {
    os << " " << a.matched << " " << what << ", ";
    if (a.matched == 0) os << "none on both sides";
    else os << io::fixed(100.0 * a.withinFraction(), 2) << " % within " << a.tolerance << " " << unit << " of SSM's";
  };
  agreement(r.drac, "DRACs", "m/s²");
  os << ";";
  // the PETs whose SSM point lies off the other's path, said apart
  auto offPath = [&](std::uint64_t off, const Agreement& on) {
    if (off == 0) return;
    os << " (" << off << " with SSM's point off the other's path; of the " << on.matched << " on both paths ";
    if (on.matched == 0) os << "none to compare)";
    else os << io::fixed(100.0 * on.withinFraction(), 2) << " % within)";
  };
  agreement(r.pet, "PETs", "s");
  offPath(r.petOffPath, r.petOnPaths);
  os << ";";
  agreement(r.conflictPet, "conflicts' PETs", "s");
  offPath(r.conflictPetOffPath, r.conflictPetOnPaths);
  os << ";";
  agreement(r.point, "conflict points", "m");
  if (r.point.matched > 0) os << " (along the leader's path " << io::fixed(100.0 * r.pointAlong.withinFraction(), 2) << " %)";
  os << ";";
  agreement(r.crossingAlong, "crossing points", "m");
  if (r.crossingAlong.matched > 0) os << " along the follower's path";
  os << ";";
  agreement(r.pathsMeet, "conflicts' meeting points", "m");
  offPath(r.pathsMeetOffPath, r.pathsMeetOnPaths);
  os << "; " << r.encounterMatched << " conflicts' encounters typed by SSM too, ";
  if (r.encounterMatched == 0) os << "none to compare;";
  else os << r.encounterAgree << " of them alike;";
  const auto& m = r.ssmModels;
  os << " " << m.conflicts << " conflicts of encounters SSM models (following, merging, crossing), "
     << m.seen << " logged by SSM";
  if (m.collided > 0) os << " and " << m.collided << " that collided";
  os << ", " << m.close << " more came within the clearance (" << r.conflicts() - m.conflicts
     << " outside its model: diverging, adjacent, pedestrian, unknown);";
  for (const auto& d : r.detectors)
    os << " " << d.detector << " recall " << figure(d.recall(), 3, "n/a (no SSM conflict below the safe time)")
       << " precision " << figure(d.precision(), 3, "n/a (no car-car warning)") << " (conflicts alone: recall "
       << figure(d.conflictRecall(), 3, "n/a") << ", precision " << figure(d.conflictPrecision(), 3, "n/a") << ");";
  return os.str();
}

}  // namespace st::cosim
