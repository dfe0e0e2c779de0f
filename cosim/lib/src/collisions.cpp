#include <stcosim/collisions.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <stio/xml.hpp>

namespace st::cosim {

bool SumoCollision::contact() const { return !(gap > kContactGap); }

std::vector<std::size_t> CollisionCounter::step(const std::vector<SumoCollision>& reported) {
  reports_ += reported.size();
  std::vector<std::size_t> begun;
  std::set<std::pair<std::string, std::string>> touching;
  for (std::size_t i = 0; i < reported.size(); ++i) {
    std::pair<std::string, std::string> pair = std::minmax(reported[i].collider, reported[i].victim);
    if (!touching_.count(pair) && !touching.count(pair)) {
      distinct_++;
      begun.push_back(i);
    }
    touching.insert(std::move(pair));
  }
  touching_ = std::move(touching);
  return begun;
}

std::vector<SumoCollision> countCollisions(CollisionCounter& counter, const std::vector<SumoCollision>& reports,
                                           double stepLength) {
  std::vector<SumoCollision> firsts, step;
  auto flush = [&] {
    for (std::size_t i : counter.step(step)) firsts.push_back(step[i]);
    step.clear();
  };
  double stepTime = 0.0;
  for (const SumoCollision& c : reports) {
    if (!step.empty() && std::abs(c.time - stepTime) > 0.5 * stepLength) {
      flush();
      // a step or more without reports in between ends every contact
      if (c.time - stepTime > 1.5 * stepLength) counter.step({});
    }
    stepTime = c.time;
    step.push_back(c);
  }
  if (!step.empty()) flush();
  return firsts;
}

std::vector<CollisionWarning> collisionWarnings(const std::vector<SumoCollision>& firstReports, double stepLength,
                                                const std::vector<highway::Warning>& warnings) {
  // the vehicle warnings of each (ego, foe), by begin
  std::map<std::pair<std::string, std::string>, std::vector<const highway::Warning*>> byPair;
  for (const highway::Warning& w : warnings)
    if (w.kind == highway::WarningKind::Vehicle) byPair[{w.ego, w.foe}].push_back(&w);
  for (auto& [pair, list] : byPair)
    std::sort(list.begin(), list.end(), [](const auto* a, const auto* b) { return a->begin < b->begin; });
  std::vector<CollisionWarning> out;
  for (const SumoCollision& c : firstReports) {
    CollisionWarning cw{c, std::nullopt};
    const auto it = byPair.find({c.collider, c.victim});
    if (it != byPair.end()) {
      const auto& list = it->second;
      // the last episode begun by the collision, if it is still on then (times are whole steps up
      // to rounding: half a step absorbs it)
      const double slack = 0.5 * stepLength;
      std::size_t k = list.size();
      while (k > 0 && list[k - 1]->begin > c.time + slack) --k;
      if (k > 0 && (list[k - 1]->open || list[k - 1]->end >= c.time - stepLength - slack)) {
        double begin = list[k - 1]->begin;
        for (std::size_t j = k - 1; j > 0 && list[j - 1]->end >= begin - kWarningGapMerge; --j)
          begin = std::min(begin, list[j - 1]->begin);
        cw.leadTime = c.time - begin;
      }
    }
    out.push_back(std::move(cw));
  }
  return out;
}

std::vector<std::string> collisionOutputArguments(const std::filesystem::path& file) {
  return {"--collision-output", file.string()};
}

std::vector<SumoCollision> readCollisionOutput(const std::filesystem::path& file, double stepLength) {
  io::XmlScanner x(file, io::raiseAs<std::runtime_error>);
  x.requireBalanced();  // a file SUMO did not close is not read as whole
  io::XmlScanner::Tag t;
  if (!x.next(t) || t.closing || t.name != "collisions")
    throw std::runtime_error(file.string() + ": not a SUMO collision output (no <collisions>)");
  std::vector<SumoCollision> out;
  while (x.next(t)) {
    if (t.closing || t.name != "collision" || x.depth() != 1) continue;
    const std::string where = file.string() + ":" + std::to_string(t.line);
    auto attr = [&](const char* key) {
      const std::string* v = t.attr(key);
      if (!v) throw std::runtime_error(where + ": a <collision> has no '" + key + "' attribute");
      return *v;
    };
    auto number = [&](const char* key) {
      const std::string text = attr(key);
      try {
        std::size_t used = 0;
        const double v = std::stod(text, &used);
        if (used == text.size() && std::isfinite(v)) return v;
      } catch (const std::exception&) {
      }
      throw std::runtime_error(where + ": <collision " + key + "=\"" + text + "\">: not a number");
    };
    SumoCollision c;
    // the report's step plus one (as the plugin sees it), on SUMO's clock of whole milliseconds: the
    // double libsumo gives for that time (210.7 + 0.1 is 210.79999999999998; SUMO's 210.8 is 210.8),
    // so collisions.csv writes the same time either way
    c.time = std::round((number("time") + stepLength) * 1000.0) / 1000.0;
    c.collider = attr("collider");
    c.victim = attr("victim");
    c.type = attr("type");
    c.lane = attr("lane");
    c.pos = t.attr("pos") ? number("pos") : 0.0;
    c.colliderSpeed = number("colliderSpeed");
    c.victimSpeed = number("victimSpeed");
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace st::cosim
