#include <sthighway/sumo_files.hpp>

#include <stio/input.hpp>

#include "xml_scanner.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace st::highway {

namespace {

using detail::number;
using detail::optionalNumber;
using detail::required;
using detail::XmlScanner;

std::vector<Vec2> parseShape(const XmlScanner& x, const XmlScanner::Tag& t, const std::string& text) {
  std::vector<Vec2> pts;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    if (i >= text.size()) break;
    std::size_t j = i;
    while (j < text.size() && !std::isspace(static_cast<unsigned char>(text[j]))) ++j;
    const std::string pt = text.substr(i, j - i);
    const std::size_t c1 = pt.find(',');
    if (c1 == std::string::npos) x.fail(t.line, "<" + t.name + "> shape point '" + pt + "' is not x,y");
    const std::size_t c2 = pt.find(',', c1 + 1);  // a z coordinate may follow
    const double px = number(x, t, "shape", pt.substr(0, c1));
    const double py = number(x, t, "shape", pt.substr(c1 + 1, c2 == std::string::npos ? std::string::npos : c2 - c1 - 1));
    pts.emplace_back(px, py);
    i = j;
  }
  return pts;
}

std::string fmtNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

RoadGeometry readSumoNet(const std::filesystem::path& path, std::vector<std::string>* leftOut, int* trafficLights) {
  XmlScanner x(path);
  RoadGeometry road;
  XmlScanner::Tag t;
  std::string edge;
  bool internal = false, sawNet = false;
  std::unordered_map<std::string, long> laneLines;  // lane id -> its line (an id given twice is an error)
  std::unordered_set<std::string> lights;           // <tlLogic> ids (one per light, programs aside)
  while (x.next(t)) {
    if (t.name == "net" && !t.closing) sawNet = true;
    if (t.name == "tlLogic" && !t.closing)
      if (const std::string* id = t.attr("id")) lights.insert(*id);
    if (t.name == "edge") {
      if (t.closing) {
        edge.clear();
        continue;
      }
      const std::string* id = t.attr("id");
      if (!id) x.fail(t.line, "<edge> lacks attribute 'id'");
      const std::string* fn = t.attr("function");
      edge = *id;
      internal = fn && (*fn == "internal" || *fn == "walkingarea" || *fn == "crossing");
      if (t.selfClosing) edge.clear();
    } else if (t.name == "lane" && !t.closing) {
      if (edge.empty()) x.fail(t.line, "<lane> outside an <edge>");
      Lane l;
      const std::string* id = t.attr("id");
      if (!id) x.fail(t.line, "<lane> lacks attribute 'id'");
      l.id = *id;
      l.edge = edge;
      l.index = static_cast<int>(required(x, t, "index"));
      if (l.id.empty()) x.fail(t.line, "<lane> attribute 'id' is empty");
      if (auto [at, fresh] = laneLines.emplace(l.id, t.line); !fresh)
        x.fail(t.line, "<lane id=\"" + l.id + "\"> given twice (first at line " + std::to_string(at->second) + ")");
      l.width = optionalNumber(x, t, "width", 3.2);
      l.length = optionalNumber(x, t, "length", 0.0);
      if (!(l.length >= 0.0)) x.fail(t.line, "<lane id=\"" + l.id + "\"> length must not be negative");
      if (!(l.width > 0.0)) x.fail(t.line, "<lane id=\"" + l.id + "\"> width must be positive");
      if (l.width > kNetMaxLaneWidth)
        x.fail(t.line, "<lane id=\"" + l.id + "\"> width " + fmtNumber(l.width) + " m is beyond any lane's (at most " +
                           fmtNumber(kNetMaxLaneWidth) + ")");
      if (l.length > kNetMaxCoordinate)
        x.fail(t.line, "<lane id=\"" + l.id + "\"> length " + fmtNumber(l.length) + " m is beyond any lane's (at most " +
                           fmtNumber(kNetMaxCoordinate) + ")");
      const std::string* shape = t.attr("shape");
      if (!shape) x.fail(t.line, "<lane id=\"" + l.id + "\"> lacks attribute 'shape'");
      l.shape = parseShape(x, t, *shape);
      if (l.shape.size() < 2) x.fail(t.line, "<lane id=\"" + l.id + "\"> shape needs at least two points");
      for (const Vec2& p : l.shape)
        if (!(std::abs(p.x()) <= kNetMaxCoordinate && std::abs(p.y()) <= kNetMaxCoordinate))
          x.fail(t.line, "<lane id=\"" + l.id + "\"> shape point (" + fmtNumber(p.x()) + ", " + fmtNumber(p.y()) +
                             ") is farther than " + fmtNumber(kNetMaxCoordinate) + " m from the network's origin");
      l.internal = internal;
      // pedestrian-only lanes (sidewalks) are not part of the carriageway
      const std::string* allow = t.attr("allow");
      if (allow && (*allow == "pedestrian" || *allow == "bicycle")) {
        if (leftOut) leftOut->push_back(l.id);
        continue;
      }
      road.lanes.push_back(std::move(l));
    }
  }
  if (trafficLights) *trafficLights = static_cast<int>(lights.size());
  if (!sawNet) throw InputError(path.string() + ":1: not a SUMO network (no <net> element)");
  return road;
}

VehicleTypes readSumoVehicleTypes(const std::filesystem::path& path) {
  XmlScanner x(path);
  std::map<std::string, SumoTypeRecord> records;
  XmlScanner::Tag t;
  std::string current;
  auto positive = [&](const std::string& id, const char* key) -> std::optional<double> {
    const std::string* text = t.attr(key);
    if (!text) return std::nullopt;
    const double v = number(x, t, key, *text);
    if (!(v > 0)) x.fail(t.line, "<vType id=\"" + id + "\"> " + key + " must be positive");
    return v;
  };
  while (x.next(t)) {
    if (t.name == "vType" && !t.closing) {
      const std::string* id = t.attr("id");
      if (!id) x.fail(t.line, "<vType> lacks attribute 'id'");
      SumoTypeRecord r;
      if (const std::string* vc = t.attr("vClass")) r.vClass = *vc;
      r.length = positive(*id, "length");
      r.width = positive(*id, "width");
      r.mass = positive(*id, "mass");
      r.decel = positive(*id, "decel");
      records[*id] = r;
      current = t.selfClosing ? "" : *id;
    } else if (t.name == "vType" && t.closing) {
      current.clear();
    } else if (t.name == "param" && !t.closing && !current.empty()) {
      const std::string* key = t.attr("key");
      if (key && *key == "mass") {
        const std::string* v = t.attr("value");
        if (!v) x.fail(t.line, "<param key=\"mass\"> lacks attribute 'value'");
        const double m = number(x, t, "value", *v);
        if (!(m > 0)) x.fail(t.line, "<param key=\"mass\"> must be positive");
        records[current].mass = m;
      }
    }
  }
  VehicleTypes out;
  for (const auto& [id, r] : records) out[id] = toVehicleTypeInfo(r);
  return out;
}

VehicleRoutes readSumoRoutes(const std::filesystem::path& path) {
  XmlScanner x(path);
  XmlScanner::Tag t;
  VehicleRoutes out;
  std::unordered_map<std::string, std::vector<std::string>> named;  // top-level <route id edges>
  std::string vehicle;  // the open <vehicle>'s id
  auto edgesOf = [&](const std::string& text) {
    std::vector<std::string> edges;
    std::size_t i = 0;
    while (i < text.size()) {
      const std::size_t j = text.find(' ', i);
      if (j != i) edges.push_back(text.substr(i, j == std::string::npos ? std::string::npos : j - i));
      if (j == std::string::npos) break;
      i = j + 1;
    }
    if (edges.empty()) x.fail(t.line, "<route> has no edges");
    return edges;
  };
  bool any = false;
  while (x.next(t)) {
    if (t.name == "vehicle") {
      if (t.closing) {
        vehicle.clear();
        continue;
      }
      const std::string* id = t.attr("id");
      if (!id || id->empty()) x.fail(t.line, "<vehicle> lacks attribute 'id'");
      any = true;
      if (const std::string* route = t.attr("route")) {
        const auto it = named.find(*route);
        if (it == named.end()) x.fail(t.line, "<vehicle id=\"" + *id + "\"> route '" + *route + "' is not defined before it");
        out[*id] = it->second;
      }
      if (!t.selfClosing) vehicle = *id;
    } else if (t.name == "route" && !t.closing) {
      const std::string* edges = t.attr("edges");
      if (!edges) continue;  // a route distribution's reference
      if (!vehicle.empty()) {
        out[vehicle] = edgesOf(*edges);  // the last one a vehicle lists is the one it drove
      } else if (const std::string* id = t.attr("id")) {
        named[*id] = edgesOf(*edges);
      }
    }
  }
  if (!any) throw InputError(path.string() + ": holds no <vehicle> (a route file or sumo --vehroute-output?)");
  return out;
}

FcdChecks fcdChecksFor(const RoadGeometry& road, const std::vector<std::string>& leftOut, std::string netFile) {
  FcdChecks c;
  c.netFile = std::move(netFile);
  for (const Lane& l : road.lanes) {
    c.lanes.push_back(l.id);
    for (const Vec2& p : l.shape) {
      if (!c.bounded) c.lo = c.hi = p;
      c.lo = c.lo.cwiseMin(p);
      c.hi = c.hi.cwiseMax(p);
      c.bounded = true;
    }
  }
  c.lanes.insert(c.lanes.end(), leftOut.begin(), leftOut.end());
  std::sort(c.lanes.begin(), c.lanes.end());
  c.lanesChecked = true;
  return c;
}

struct FcdReader::Impl {
  XmlScanner x;
  VehicleTypes types;
  struct Last {
    double time;
    double posLat;     // NaN: not in the trace
    std::string lane;  // "" not in the trace
    int handle;  // dense, in order of first appearance: the monitor's handle for the vehicle
    int routeAt = -1;  // the index of its edge in its route (inside a junction: of the edge it left)
  };
  std::unordered_map<std::string, Last> last;
  std::unordered_map<std::string, Last> lastPerson;  // persons have ids of their own
  int nextHandle = 0;
  PathBodies bodies;  // each vehicle's body along its path, by its handle
  double lastTime = -std::numeric_limits<double>::infinity();
  FcdChecks checks;
  bool anyStep = false;
  long rootLine = 0;        // line of <fcd-export>, 0 if none
  bool rootClosed = false;  // </fcd-export> seen
  std::unordered_map<std::string, int> laneIndex;  // lane id -> index into the network's lanes
  const RoadGeometry* road = nullptr;
  const SignalLinks* signalLinks = nullptr;
  SignalStates* signalStates = nullptr;
  bool signalsNeedLanes = true;  // a record without lane and pos is an error (else: no next stop)
  const VehicleRoutes* routes = nullptr;
  std::unordered_map<std::string, int> edgeIndex;  // edge id -> index into edgeIds(*road)
  Impl(const std::filesystem::path& p, VehicleTypes t, FcdChecks c) : x(p), types(std::move(t)), checks(std::move(c)) {}

  // next()'s steps for one <timestep> and one <vehicle> or <person> in it (each fails naming the
  // line, in the order the checks are listed).
  // A <timestep>'s time (increasing, within kFcdMaxTime) into a fresh frame; the lights advanced to it.
  void beginStep(const XmlScanner::Tag& t, FcdFrame& frame);
  // The mover of tag t in the step at `time` (whose <timestep> is on stepLine), remembered for the next.
  VehicleState readMover(const XmlScanner::Tag& t, double time, long stepLine);
  // Its type (from the vTypes, guessed, or a pedestrian's), its lane checked against the network,
  // the trace's own length and width.
  VehicleTypeInfo typeOf(const XmlScanner::Tag& t, bool person, const std::string& what) const;
  // Its position (within the network's bounds), heading, speed, acceleration and signals.
  SumoVehicleRecord recordOf(const XmlScanner::Tag& t, const std::string& what) const;
  // Where a vehicle is along its route: the route (null: none known), the index of its edge in it
  // (-1: not found), that edge; the route's next kRouteAhead edges into `ahead`.
  struct RoutePlace {
    const std::vector<std::string>* route = nullptr;
    int at = -1;
    std::string edge;
  };
  RoutePlace placeOnRoute(const std::string& id, const std::string& lane, int lastAt,
                          std::array<int, kRouteAhead>& ahead) const;
  // r's next light or yield, from the lane and pos of tag t, as the live run reads it.
  void readNextSignal(const XmlScanner::Tag& t, const std::string& what, const std::string* lane,
                      const RoutePlace& place, SumoVehicleRecord& r) const;

  // FCD has no lateral speed (SUMO 1.15; sumo's --fcd-output.attributes knows no speedLat). In
  // the sublane model posLat is the centre's offset from its lane's line, so its change over the
  // step is what SUMO's lateral speed was: along one lane, or (the road known) into a lane beside
  // it on the same edge, the lanes' half widths between them added (if the centre moved less than
  // a quarter of the lines' distance: more is a lane change made in one step). Anything else, or
  // no posLat (SUMO without the sublane model reports no lateral speed): 0, as the live run reads it.
  double lateralSpeed(const Last& prev, const std::string* lane, double posLat, double time) const {
    if (!lane || !(time > prev.time) || std::isnan(posLat) || std::isnan(prev.posLat)) return 0.0;
    double offset = 0.0;  // the old lane's line seen from the new lane's
    if (*lane != prev.lane) {
      if (!road) return 0.0;
      const auto a = laneIndex.find(prev.lane), b = laneIndex.find(*lane);
      if (a == laneIndex.end() || b == laneIndex.end()) return 0.0;
      const Lane& from = road->lanes[static_cast<std::size_t>(a->second)];
      const Lane& to = road->lanes[static_cast<std::size_t>(b->second)];
      if (from.edge != to.edge || std::abs(from.index - to.index) != 1) return 0.0;
      offset = (to.index > from.index ? 0.5 : -0.5) * (from.width + to.width);
    }
    const double moved = posLat + offset - prev.posLat;
    // a lane change SUMO makes in one step (without the sublane model posLat stays 0 and the
    // centre jumps a lane width) is no lateral motion: SUMO reports none; a sublane crossing
    // moves a fraction of that
    if (offset != 0.0 && !(std::abs(moved) < 0.25 * std::abs(offset))) return 0.0;
    const double v = moved / (time - prev.time);
    return std::isfinite(v) ? v : 0.0;
  }
};

FcdReader::FcdReader(const std::filesystem::path& path, VehicleTypes types, FcdChecks checks, const RoadGeometry* road)
    : impl_(std::make_unique<Impl>(path, std::move(types), std::move(checks))) {
  impl_->road = road;
  if (road)
    for (std::size_t i = 0; i < road->lanes.size(); ++i) impl_->laneIndex.emplace(road->lanes[i].id, static_cast<int>(i));
}
FcdReader::~FcdReader() = default;

void FcdReader::useRoutes(const VehicleRoutes* routes) {
  if (!impl_->road) throw std::logic_error("FcdReader::useRoutes needs the network");
  impl_->routes = routes;
  const std::vector<std::string> ids = edgeIds(*impl_->road);
  for (std::size_t i = 0; i < ids.size(); ++i) impl_->edgeIndex.emplace(ids[i], static_cast<int>(i));
}

void FcdReader::useSignals(const SignalLinks* links, SignalStates* states, bool needLanes) {
  impl_->signalLinks = links;
  impl_->signalStates = states;
  impl_->signalsNeedLanes = needLanes;
}

void FcdReader::Impl::beginStep(const XmlScanner::Tag& t, FcdFrame& frame) {
  anyStep = true;
  frame.time = required(x, t, "time");
  if (!(std::abs(frame.time) <= kFcdMaxTime))
    x.fail(t.line, "<timestep> time " + fmtNumber(frame.time) + " s is beyond any run's (at most " +
                       fmtNumber(kFcdMaxTime) + " s either side of 0)");
  if (!(frame.time > lastTime)) x.fail(t.line, "timestep times must increase");
  lastTime = frame.time;
  if (signalStates) signalStates->advanceTo(frame.time);
  frame.vehicles.clear();
}

VehicleTypeInfo FcdReader::Impl::typeOf(const XmlScanner::Tag& t, bool person, const std::string& what) const {
  const std::string* type = t.attr("type");
  // a person of no known type walks with SUMO's pedestrian defaults
  VehicleTypeInfo info = person ? defaultPersonType() : VehicleTypeInfo{};
  if (type) {
    auto it = types.find(*type);
    if (it == types.end() && checks.typesComplete && !person)
      x.fail(t.line, what + " type '" + *type + "' is not defined in " + checks.typesFile);
    if (it != types.end()) info = it->second;
    else if (!person) info = guessVehicleType(*type);
  }
  if (const std::string* lane = t.attr("lane");
      lane && checks.lanesChecked && !std::binary_search(checks.lanes.begin(), checks.lanes.end(), *lane))
    x.fail(t.line, what + " lane '" + *lane + "' is not in " + checks.netFile);
  // a trace's own length and width (fcd-output.attributes) stand for the vType's
  info.length = optionalNumber(x, t, "length", info.length);
  info.width = optionalNumber(x, t, "width", info.width);
  if (!(info.length > 0) || !(info.width > 0)) x.fail(t.line, what + " length and width must be positive");
  if (info.length > kFcdMaxSize || info.width > kFcdMaxSize)
    x.fail(t.line, what + " length and width must be at most " + fmtNumber(kFcdMaxSize) + " m");
  return info;
}

SumoVehicleRecord FcdReader::Impl::recordOf(const XmlScanner::Tag& t, const std::string& what) const {
  SumoVehicleRecord r;
  r.x = required(x, t, "x");
  r.y = required(x, t, "y");
  if (const FcdChecks& c = checks; c.bounded) {
    const double g = FcdChecks::kOutsideMargin;
    if (!(r.x >= c.lo.x() - g && r.x <= c.hi.x() + g && r.y >= c.lo.y() - g && r.y <= c.hi.y() + g))
      x.fail(t.line, what + " position (" + fmtNumber(r.x) + ", " + fmtNumber(r.y) +
                         ") is more than " + fmtNumber(g) + " m outside " + c.netFile + " (x " + fmtNumber(c.lo.x()) +
                         ".." + fmtNumber(c.hi.x()) + ", y " + fmtNumber(c.lo.y()) + ".." + fmtNumber(c.hi.y()) + ")");
  }
  // SUMO writes [0, 360) (360.00 where its rounding reaches it); 1e300 was taken and changed the
  // warnings, -90 was taken as 270
  r.angle = required(x, t, "angle");
  if (!(r.angle >= 0.0 && r.angle <= 360.0))
    x.fail(t.line, what + " angle " + fmtNumber(r.angle) + " is not a heading (degrees, 0..360)");
  r.speed = required(x, t, "speed");
  if (r.speed < 0.0)
    x.fail(t.line, what + " speed " + fmtNumber(r.speed) + " m/s is negative (SUMO's are >= 0)");
  if (!(std::abs(r.speed) <= kFcdMaxSpeed))
    x.fail(t.line, what + " speed " + fmtNumber(r.speed) + " m/s is beyond any vehicle's (at most " +
                       fmtNumber(kFcdMaxSpeed) + ")");
  r.acceleration = optionalNumber(x, t, "acceleration", 0.0);
  if (!(std::abs(r.acceleration) <= kFcdMaxAcceleration))
    x.fail(t.line, what + " acceleration " + fmtNumber(r.acceleration) +
                       " m/s^2 is beyond any vehicle's (at most " + fmtNumber(kFcdMaxAcceleration) + ")");
  if (const std::string* sig = t.attr("signals")) {
    const double bits = number(x, t, "signals", *sig);
    if (!(bits >= 0 && bits <= (1 << 30) && bits == std::floor(bits)))
      x.fail(t.line, what + " signals " + fmtNumber(bits) + " is not SUMO's signal bits");
    r.signals = static_cast<int>(bits);
  }
  return r;
}

// its route from the edge it is on (a lane "<edge>_<index>"; inside a junction, ':', the edge it
// left), found from where it was last (lastAt)
FcdReader::Impl::RoutePlace FcdReader::Impl::placeOnRoute(const std::string& id, const std::string& lane, int lastAt,
                                                          std::array<int, kRouteAhead>& ahead) const {
  RoutePlace p;
  p.at = lastAt;
  if (const auto rt = routes->find(id); rt != routes->end()) p.route = &rt->second;
  if (p.route && !lane.empty() && lane[0] != ':') {
    p.edge = lane.substr(0, lane.rfind('_'));
    const auto from = p.route->begin() + std::max(p.at, 0);
    auto k = std::find(from, p.route->end(), p.edge);
    if (k == p.route->end()) k = std::find(p.route->begin(), p.route->end(), p.edge);
    p.at = k == p.route->end() ? -1 : static_cast<int>(k - p.route->begin());
  } else if (p.route && p.at >= 0) {
    p.edge = (*p.route)[static_cast<std::size_t>(p.at)];
  }
  if (p.at >= 0)
    for (int j = 0; j < kRouteAhead && static_cast<std::size_t>(p.at + j) < p.route->size(); ++j) {
      const auto e = edgeIndex.find((*p.route)[static_cast<std::size_t>(p.at + j)]);
      if (e == edgeIndex.end()) break;
      ahead[static_cast<std::size_t>(j)] = e->second;
    }
  return p;
}

void FcdReader::Impl::readNextSignal(const XmlScanner::Tag& t, const std::string& what, const std::string* lane,
                                     const RoutePlace& place, SumoVehicleRecord& r) const {
  if (!lane || !t.attr("pos"))
    x.fail(t.line, what + " lacks attribute 'lane' or 'pos', which reading its traffic light needs "
                          "(sumo --fcd-output.attributes with lane,pos)");
  const double pos = required(x, t, "pos");
  if (place.route && place.at >= 0) {
    // as the live run: the link to the route's next edge; none past its last
    const bool more = static_cast<std::size_t>(place.at) + 1 < place.route->size();
    if (more) nextSignalOf(*signalLinks, *signalStates, *lane, pos, r.signals, r, &place.edge,
                           &(*place.route)[static_cast<std::size_t>(place.at) + 1]);
  } else {
    nextSignalOf(*signalLinks, *signalStates, *lane, pos, r.signals, r);
  }
}

VehicleState FcdReader::Impl::readMover(const XmlScanner::Tag& t, double time, long stepLine) {
  const bool person = t.name == "person";
  const std::string tag = "<" + t.name + ">";
  VehicleState v;
  const std::string* id = t.attr("id");
  if (!id) x.fail(t.line, tag + " lacks attribute 'id'");
  if (id->empty()) x.fail(t.line, tag + " attribute 'id' is empty");
  v.id = *id;
  const std::string what = "<" + t.name + " id=\"" + v.id + "\">";
  const VehicleTypeInfo info = typeOf(t, person, what);
  SumoVehicleRecord r = recordOf(t, what);
  const std::string* lane = t.attr("lane");
  auto& seen = person ? lastPerson : last;
  auto it = seen.find(v.id);
  RoutePlace place;
  place.at = it != seen.end() ? it->second.routeAt : -1;
  if (routes && !person && lane) place = placeOnRoute(v.id, *lane, place.at, v.route);
  if (signalStates && !person && (signalsNeedLanes || (lane && t.attr("pos")))) readNextSignal(t, what, lane, place, r);
  if (lane && !laneIndex.empty()) {
    auto li = laneIndex.find(*lane);
    if (li != laneIndex.end()) v.lane = li->second;
  }
  // times increase strictly, so a vehicle last seen at this frame's time is listed twice in it
  if (it != seen.end() && it->second.time == time)
    x.fail(t.line, t.name + " '" + v.id + "' appears twice in the timestep (line " + std::to_string(stepLine) + ")");
  double posLat = std::numeric_limits<double>::quiet_NaN();
  if (t.attr("posLat")) posLat = required(x, t, "posLat");
  if (it != seen.end() && !person) r.lateralSpeed = lateralSpeed(it->second, lane, posLat, time);
  toVehicleState(r, info, v);
  if (person) {
    v.lane = -1;         // a sidewalk or crossing: not a lane it is predicted along
    v.equipped = false;  // a foe, as the live run has it
  }
  v.handle = it != seen.end() ? it->second.handle : nextHandle++;
  if (!person) bodies.fit(static_cast<std::size_t>(v.handle), time, v);  // as the live run
  Last& l = it != seen.end() ? it->second : seen[v.id];
  l.time = time;
  l.posLat = posLat;
  l.lane = lane ? *lane : std::string();
  l.handle = v.handle;
  l.routeAt = place.at;
  return v;
}

bool FcdReader::next(FcdFrame& frame) {
  Impl& m = *impl_;
  XmlScanner& x = m.x;
  XmlScanner::Tag t;
  bool inStep = false;
  long stepLine = 0;
  long openVehicle = 0;  // line of a <vehicle ...> not yet closed by </vehicle>
  while (x.next(t)) {
    if (openVehicle && !(t.name == "vehicle" && t.closing) && t.name != "person" && t.name != "container")
      x.fail(openVehicle, "<vehicle> is not closed (expected \"/>\" or </vehicle> before line " + std::to_string(t.line) + ")");
    if (t.name == "vehicle" && t.closing) {
      if (!openVehicle) x.fail(t.line, "</vehicle> without <vehicle>");
      openVehicle = 0;
      continue;
    }
    if (t.name == "fcd-export") {
      if (t.closing) m.rootClosed = true;
      else if (!t.selfClosing) m.rootLine = t.line;
      continue;
    }
    if (t.name == "timestep") {
      if (t.closing) {
        if (!inStep) x.fail(t.line, "</timestep> without <timestep>");
        return true;
      }
      if (inStep) x.fail(t.line, "<timestep> inside <timestep>");
      m.beginStep(t, frame);
      if (t.selfClosing) return true;
      inStep = true;
      stepLine = t.line;
      continue;
    }
    // a person (or container) inside an open <vehicle> rides it (SUMO nests passengers): no foe
    if ((t.name == "person" || t.name == "container") && openVehicle) continue;
    if (t.name != "vehicle" && t.name != "person") continue;
    if (!inStep) x.fail(t.line, "<" + t.name + "> outside a <timestep>");
    if (!t.selfClosing && t.name != "person") openVehicle = t.line;
    frame.vehicles.push_back(m.readMover(t, frame.time, stepLine));
  }
  if (openVehicle) x.fail(openVehicle, "<vehicle> is not closed (expected \"/>\" or </vehicle>)");
  if (inStep) x.fail(stepLine, "unterminated <timestep>");
  if (!m.anyStep) throw InputError(x.path() + ": holds no <timestep> (not a SUMO FCD trace, sumo --fcd-output?)");
  // a trace cut short (a SUMO that was killed, a copy that stopped) ends without its root's close
  if (m.rootLine && !m.rootClosed)
    x.fail(m.rootLine, "<fcd-export> is not closed (no </fcd-export>: the trace is cut short)");
  return false;
}

}  // namespace st::highway
