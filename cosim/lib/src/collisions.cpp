#include <stcosim/collisions.hpp>

#include <boost/property_tree/ptree.hpp>
#include <boost/property_tree/xml_parser.hpp>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace st::cosim {

void CollisionCounter::step(const std::vector<SumoCollision>& reported) {
  reports_ += reported.size();
  std::set<std::pair<std::string, std::string>> touching;
  for (const SumoCollision& c : reported) {
    std::pair<std::string, std::string> pair = std::minmax(c.collider, c.victim);
    if (!touching_.count(pair) && !touching.count(pair)) distinct_++;
    touching.insert(std::move(pair));
  }
  touching_ = std::move(touching);
}

void countCollisions(CollisionCounter& counter, const std::vector<SumoCollision>& reports, double stepLength) {
  std::vector<SumoCollision> step;
  double stepTime = 0.0;
  for (const SumoCollision& c : reports) {
    if (!step.empty() && std::abs(c.time - stepTime) > 0.5 * stepLength) {
      counter.step(step);
      // a step or more without reports in between ends every contact
      if (c.time - stepTime > 1.5 * stepLength) counter.step({});
      step.clear();
    }
    stepTime = c.time;
    step.push_back(c);
  }
  if (!step.empty()) counter.step(step);
}

std::vector<std::string> collisionOutputArguments(const std::filesystem::path& file) {
  return {"--collision-output", file.string()};
}

std::vector<SumoCollision> readCollisionOutput(const std::filesystem::path& file) {
  namespace pt = boost::property_tree;
  pt::ptree tree;
  try {
    pt::read_xml(file.string(), tree);
  } catch (const pt::xml_parser_error& e) {
    throw std::runtime_error(file.string() + ":" + std::to_string(e.line()) + ": " + e.message());
  }
  std::vector<SumoCollision> out;
  const auto root = tree.get_child_optional("collisions");
  if (!root) throw std::runtime_error(file.string() + ": not a SUMO collision output (no <collisions>)");
  for (const auto& [name, node] : *root) {
    if (name != "collision") continue;
    auto attr = [&](const char* key) {
      const auto v = node.get_optional<std::string>(std::string("<xmlattr>.") + key);
      if (!v) throw std::runtime_error(file.string() + ": a <collision> has no '" + key + "' attribute");
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
      throw std::runtime_error(file.string() + ": <collision " + key + "=\"" + text + "\">: not a number");
    };
    SumoCollision c;
    c.time = number("time");
    c.collider = attr("collider");
    c.victim = attr("victim");
    c.type = attr("type");
    c.lane = attr("lane");
    c.pos = node.get_optional<std::string>("<xmlattr>.pos") ? number("pos") : 0.0;
    c.colliderSpeed = number("colliderSpeed");
    c.victimSpeed = number("victimSpeed");
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace st::cosim
