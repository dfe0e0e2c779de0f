#include <sthighway/sumo_conversion.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <string_view>

#include <sthighway/tolerances.hpp>

namespace st::highway {

namespace {

// What SUMO 1.15 gives a vType of each vClass that sets no length, width or decel (read back
// through TraCI's vehicletype.getLength/getWidth/getDecel), so a vType file read beside a trace
// gives the bodies the live run had. Classes not listed take passenger's, as SUMO does.
struct SumoClassDefaults {
  std::string_view vClass;
  double length, width, decel;
};
constexpr SumoClassDefaults kSumoClassDefaults[] = {
    {"passenger", 5.0, 1.8, 4.5},   {"truck", 7.1, 2.4, 4.0},      {"trailer", 16.5, 2.55, 4.0},
    {"delivery", 6.5, 2.16, 4.5},   {"bus", 12.0, 2.5, 4.0},       {"coach", 14.0, 2.6, 4.0},
    {"motorcycle", 2.2, 0.9, 10.0}, {"moped", 2.1, 0.78, 7.0},     {"bicycle", 1.6, 0.65, 3.0},
    {"emergency", 6.5, 2.16, 4.5},  {"pedestrian", 0.215, 0.478, 2.0}, {"tram", 22.0, 2.4, 3.0},
    {"rail", 135.0, 2.84, 1.3},
};

SumoClassDefaults sumoClassDefaults(std::string_view vClass) {
  for (const SumoClassDefaults& d : kSumoClassDefaults)
    if (d.vClass == vClass) return d;
  return kSumoClassDefaults[0];
}

}  // namespace

VehicleTypeInfo toVehicleTypeInfo(const SumoTypeRecord& type) {
  VehicleTypeInfo t;
  const std::string_view vClass = type.vClass.empty() ? std::string_view("passenger") : std::string_view(type.vClass);
  t.vehicleClass = vehicleClassFromName(vClass);
  const SumoClassDefaults d = sumoClassDefaults(vClass);
  t.length = type.length.value_or(d.length);
  t.width = type.width.value_or(d.width);
  t.decel = type.decel.value_or(d.decel);
  t.mass = type.mass.value_or(classDefaults(t.vehicleClass).mass);
  return t;
}

VehicleTypeInfo defaultPersonType() {
  SumoTypeRecord r;
  r.vClass = "pedestrian";
  return toVehicleTypeInfo(r);
}

VehicleTypeInfo guessVehicleType(const std::string& typeName) {
  std::string name = typeName;
  for (char& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  auto has = [&](std::string_view needle) { return name.find(needle) != std::string::npos; };
  VehicleClass c = VehicleClass::Passenger;
  if (has("truck") || has("trailer") || has("lorry") || has("hgv"))
    c = VehicleClass::Truck;
  else if (has("bus") || has("coach"))
    c = VehicleClass::Bus;
  else if (has("moto") || has("moped"))
    c = VehicleClass::Motorcycle;
  else if (has("emergency") || has("ambulance"))
    c = VehicleClass::Emergency;
  const ClassDefaults d = classDefaults(c);
  VehicleTypeInfo t;
  t.vehicleClass = c;
  t.length = d.length;
  t.width = d.width;
  t.mass = d.mass;
  return t;  // decel unknown
}

std::uint8_t toTurnSignals(int sumoSignals) {
  std::uint8_t s = kSignalNone;
  if (sumoSignals & kSumoBlinkerLeft) s |= kSignalLeft;
  if (sumoSignals & kSumoBlinkerRight) s |= kSignalRight;
  return s;
}

double stopDistanceOf(const SumoVehicleRecord& v, double decel) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double d = std::max(0.0, v.nextSignalDistance);
  const double brake = decel > 0.0 ? decel : 4.5;
  switch (v.nextSignal) {
    case 'r':
    case 'u':
    case 's':
    case 'w':
      // unless it cannot stop even at an emergency's braking (twice its decel, SUMO's default
      // emergencyDecel): then it runs the light, as SUMO's drivers past that point do
      return v.speed * v.speed <= 4.0 * brake * d ? d : kInf;
    case 'y':
      return v.speed * v.speed <= 2.0 * brake * d ? d : kInf;  // it can stop: it does
    case 'g':
    case 'm':
    case '=':
      // it gives way there (priority rules: a left turn's wait point, a minor road's line) if it
      // can stop at its decel; one that cannot has taken its gap and goes on
      return v.speed * v.speed <= 2.0 * brake * (d + tol::kYieldStepSlack * std::abs(v.speed)) ? d : kInf;
    default:
      return kInf;
  }
}

bool givesWayAt(char s) { return s == 'g' || s == 'm' || s == '=' || s == 's' || s == 'w'; }

bool entersAt(char s) { return s == 'G' || s == 'g' || s == 'M' || s == 'm' || s == '=' || s == 'O' || s == 'o'; }

void toVehicleState(const SumoVehicleRecord& v, const VehicleTypeInfo& type, VehicleState& s) {
  s.vehicleClass = type.vehicleClass;
  s.length = type.length;
  s.width = type.width;
  s.mass = type.mass;
  s.decel = type.decel;
  s.heading = headingFromNavigationDegrees(v.angle);
  s.position = centreFromFrontBumper(Vec2(v.x, v.y), s.heading, s.length);
  s.speed = v.lateralSpeed == 0.0 ? v.speed : std::copysign(std::hypot(v.speed, v.lateralSpeed), v.speed);
  s.lateralSpeed = 0.0;
  s.acceleration = v.acceleration;
  s.signals = toTurnSignals(v.signals);
  s.stopDistance = stopDistanceOf(v, type.decel);
}

void PathBodies::fit(std::size_t key, double t, VehicleState& s) {
  if (s.vehicleClass == VehicleClass::Pedestrian) return;
  if (key >= trails_.size()) trails_.resize(key + 1);
  Trail& trail = trails_[key];
  std::vector<Vec2>& fronts = trail.fronts;
  const Vec2 u = s.direction();
  const Vec2 front = s.position + 0.5 * s.length * u;
  if (!front.allFinite() || !std::isfinite(t)) return;  // the caller refuses it
  if (!(t > trail.time)) fronts.clear();  // time went back: another run
  trail.time = t;
  if (!fronts.empty()) {
    const Vec2 step = front - fronts.back();
    if (step.norm() > tol::kTrailBreak) {
      fronts.clear();
    } else {
      // sideways of the way it was going: its last step's direction (its heading before it has
      // made a step long enough to tell one)
      const Vec2 last = fronts.size() >= 2 ? Vec2(fronts.back() - fronts[fronts.size() - 2]) : Vec2::Zero();
      const Vec2 way = last.norm() >= 0.1 * tol::kLaneJump ? Vec2(last.normalized()) : u;
      const double sideways = cross(way, step);
      if (std::abs(sideways) > tol::kLaneJump) {
        const Vec2 shift = sideways * Vec2(-way.y(), way.x());
        for (Vec2& p : fronts) p += shift;
      }
    }
  }
  if (fronts.empty() || front != fronts.back()) fronts.push_back(front);
  // the point `length` of path behind the front
  double left = s.length;
  for (std::size_t i = fronts.size() - 1; i > 0; --i) {
    const Vec2 a = fronts[i], b = fronts[i - 1];
    const double seg = (a - b).norm();
    if (seg < left) {
      left -= seg;
      continue;
    }
    const Vec2 back = a + (left / seg) * (b - a);
    // what is older than this segment is never needed again (a few points kept: fewer erases)
    if (i > 16) fronts.erase(fronts.begin(), fronts.begin() + static_cast<std::ptrdiff_t>(i - 1));
    const Vec2 r = front - back;
    const double along = r.dot(u);
    if (along >= s.length - tol::kChordSlack || along <= 0.0 || std::abs(cross(u, r)) > tol::kBackOffLine) return;
    s.length = along;
    s.position = front - 0.5 * along * u;
    return;
  }
}

std::string junctionOfLane(const std::string& laneId) {
  if (laneId.size() < 2 || laneId[0] != ':') return "";
  const std::size_t index = laneId.rfind('_');
  if (index == std::string::npos || index < 2) return "";
  const std::size_t link = laneId.rfind('_', index - 1);
  if (link == std::string::npos || link < 2) return "";
  return laneId.substr(1, link - 1);
}

}  // namespace st::highway
