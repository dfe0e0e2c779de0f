#include <sthighway/report.hpp>

#include <algorithm>
#include <cmath>

#include <stio/format.hpp>

#include <sstream>
#include <stdexcept>

namespace st::highway {

namespace {

// JSON has no NaN or infinity: null stands for them (in warnings.csv too, which has always said so).
std::string num(double x) { return io::jsonNumber(x); }
using io::csvField;
using io::jsonString;

// a share, or null when there is nothing to count
std::string share(std::uint64_t part, std::uint64_t whole) {
  return whole ? num(static_cast<double>(part) / static_cast<double>(whole)) : "null";
}

// lead times: min, median, 90th percentile (null when none)
std::string leadJson(std::vector<double> v) {
  if (v.empty()) return "null";
  std::sort(v.begin(), v.end());
  auto q = [&](double f) { return v[static_cast<std::size_t>(f * static_cast<double>(v.size() - 1) + 0.5)]; };
  return "{\"min\": " + num(v.front()) + ", \"median\": " + num(q(0.5)) + ", \"p90\": " + num(q(0.9)) + "}";
}

// a conflict column: empty where it does not apply (NaN), "inf" for an infinite DRAC
std::string conflictField(double x) {
  if (std::isnan(x)) return "";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return num(x);
}

// A measure derived from the inputs (an angle, a deceleration rate, a speed change, a point
// worked out, PET) to 0.001 of its unit: the shortest text that reads back exactly would print
// its rounding noise (a heading angle of 5.79e-13 deg). Trailing zeros dropped; -0 is 0.
std::string derivedField(double x) {
  if (!std::isfinite(x)) return conflictField(x);
  std::string s = io::fixed(x, 3);
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

}  // namespace

std::string hindsightJson(const MonitorCounters& c, const HindsightConfig& h) {
  if (!h.enabled) return "null";
  std::ostringstream os;
  os << "{\"clearance_m\": " << num(h.clearance) << ", \"evasive_deceleration\": " << num(h.evasiveDeceleration)
     << ", \"lead_s\": " << num(h.lead) << ", \"near_miss_ttc_s\": " << num(h.nearMissTtc) << ",\n    \"by_kind\": {";
  for (int k = 0; k < kWarningKindCount; ++k)
    os << (k ? ", " : "") << jsonString(toString(static_cast<WarningKind>(k))) << ": {\"judged\": " << c.judged[k]
       << ", \"confirmed\": " << c.confirmed[k] << ", \"precision\": " << share(c.confirmed[k], c.judged[k]) << "}";
  os << "},\n    \"near_misses\": " << eventRecallJson(c.nearMisses, c.nearMissesWarned, c.nearMissLeads)
     << ",\n    \"crossings\": " << eventRecallJson(c.crossings, c.crossingsWarned, c.crossingLeads) << "}";
  return os.str();
}

std::string eventRecallJson(std::uint64_t events, std::uint64_t warned, const std::vector<double>& leads) {
  return "{\"events\": " + std::to_string(events) + ", \"warned\": " + std::to_string(warned) +
         ", \"recall\": " + share(warned, events) + ", \"lead_s\": " + leadJson(leads) + "}";
}

std::string conflictsCsvHeader() {
  return "first,second,type,begin,end,min_ttc,min_ttc_time,pet,drac,max_s,delta_s,dr,max_d,max_delta_v,"
         "first_delta_v,second_delta_v,conflict_angle,clock_angle,post_crash_speed,post_crash_heading,conflict_x,conflict_y,"
         "first_x,first_y,second_x,second_y,first_speed,second_speed,first_start_x,first_start_y,first_end_x,first_end_y,"
         "second_start_x,second_start_y,second_end_x,second_end_y,first_lane,second_lane,junction,first_class,second_class,"
         "first_length,second_length,first_width,second_width,tet,tit,open";
}

std::string conflictCsvRow(const Conflict& c) {
  // as warnings.csv: what is read or copied from the inputs in full, what is worked out to 0.001
  std::ostringstream os;
  os << csvField(c.first) << ',' << csvField(c.second) << ',' << toString(c.type) << ',' << num(c.begin) << ','
     << num(c.end) << ',' << conflictField(c.minTtc) << ',' << num(c.minTtcTime) << ',' << derivedField(c.pet) << ','
     << derivedField(c.drac) << ',' << conflictField(c.maxSpeed) << ',' << derivedField(c.deltaSpeed) << ','
     << derivedField(c.dr) << ',' << derivedField(c.maxD) << ',' << derivedField(c.maxDeltaV) << ','
     << derivedField(c.firstDeltaV) << ',' << derivedField(c.secondDeltaV) << ',' << derivedField(c.conflictAngle) << ','
     << conflictField(c.clockAngle) << ',' << derivedField(c.postCrashSpeed) << ',' << derivedField(c.postCrashHeading)
     << ',' << derivedField(c.conflictX) << ',' << derivedField(c.conflictY) << ',' << conflictField(c.firstX) << ','
     << conflictField(c.firstY) << ',' << conflictField(c.secondX) << ',' << conflictField(c.secondY) << ','
     << conflictField(c.firstSpeed) << ',' << conflictField(c.secondSpeed) << ',' << conflictField(c.firstStartX) << ','
     << conflictField(c.firstStartY) << ',' << conflictField(c.firstEndX) << ',' << conflictField(c.firstEndY) << ','
     << conflictField(c.secondStartX) << ',' << conflictField(c.secondStartY) << ',' << conflictField(c.secondEndX) << ','
     << conflictField(c.secondEndY) << ',' << csvField(c.firstLane) << ',' << csvField(c.secondLane) << ','
     << csvField(c.junction) << ','
     << toString(c.firstClass) << ',' << toString(c.secondClass) << ',' << num(c.firstLength) << ','
     << num(c.secondLength) << ',' << num(c.firstWidth) << ',' << num(c.secondWidth) << ',' << derivedField(c.tet)
     << ',' << derivedField(c.tit) << ',' << (c.open ? 1 : 0);
  return os.str();
}

ConflictsCsvWriter::ConflictsCsvWriter(const std::filesystem::path& path) : CsvRowWriter(path, conflictsCsvHeader()) {}
void ConflictsCsvWriter::write(std::span<const Conflict> conflicts) {
  for (const Conflict& c : conflicts) row(conflictCsvRow(c));
}

std::uint64_t conflictCount(const MonitorCounters& c) {
  std::uint64_t n = 0;
  for (auto k : c.conflictsByType) n += k;
  return n;
}

std::string conflictCountText(const MonitorCounters& c) {
  std::string s = std::to_string(conflictCount(c)) + " (";
  for (ConflictType t : kConflictTypes)
    s += std::string(t == ConflictType::RearEnd ? "" : ", ") + toString(t) + " " +
         std::to_string(c.conflictsByType[static_cast<int>(t)]);
  return s + ")";
}

std::string conflictsJson(const MonitorCounters& c, const ConflictConfig& config) {
  const double km = c.vehicleMeters / 1000.0;
  const std::uint64_t n = conflictCount(c);
  std::ostringstream os;
  os << "{\"count\": " << n << ", \"per_vehicle_km\": " << num(km > 0 ? static_cast<double>(n) / km : 0.0)
     << ", \"max_ttc_s\": " << num(config.maxTtc) << ", \"max_pet_s\": " << num(config.maxPet) << ",\n    \"by_type\": {";
  bool firstType = true;
  for (ConflictType t : kConflictTypes) {
    os << (firstType ? "" : ", ") << jsonString(toString(t)) << ": " << c.conflictsByType[static_cast<int>(t)];
    firstType = false;
  }
  os << "},\n    \"per_vehicle_km_by_type\": {";
  firstType = true;
  for (ConflictType t : kConflictTypes) {
    os << (firstType ? "" : ", ") << jsonString(toString(t)) << ": "
       << num(km > 0 ? static_cast<double>(c.conflictsByType[static_cast<int>(t)]) / km : 0.0);
    firstType = false;
  }
  os << "},\n    \"by_junction\": {";
  bool firstJunction = true;
  std::uint64_t inJunctions = 0;
  for (const auto& [junction, byType] : c.conflictsByJunction) {
    std::uint64_t count = 0;
    for (auto k : byType) count += k;
    inJunctions += count;
    os << (firstJunction ? "" : ", ") << jsonString(junction) << ": {\"count\": " << count;
    for (ConflictType t : kConflictTypes) os << ", " << jsonString(toString(t)) << ": " << byType[static_cast<int>(t)];
    os << "}";
    firstJunction = false;
  }
  os << "}, \"outside_junctions\": " << n - inJunctions;
  os << ",\n    \"tet_s\": " << num(c.conflictTet) << ", \"tit_s2\": " << num(c.conflictTit)
     << ", \"over_max_pet\": " << c.conflictsOverMaxPet << "}";
  return os.str();
}

std::string warningsCsvHeader() {
  return "ego,foe,kind,zone,begin,end,min_ttc,min_ttc_time,safe_time,open,"
         "verdict,clearance,clearance_time,deceleration,crossed,signalled,"
         "conflict_x,conflict_y,foe_x,foe_y,max_s,delta_s,dr,max_d,conflict_angle,clock_angle,"
         "start_x,start_y,end_x,end_y,post_crash_speed,post_crash_heading,pet,"
         "x,y,lane,ego_speed,foe_speed,heading_angle,type,drac,max_delta_v,line,lateral_speed";
}

std::string warningCsvRow(const Warning& w) {
  std::ostringstream os;
  os << csvField(w.ego) << ',' << csvField(w.foe) << ',' << toString(w.kind) << ',' << toString(w.zone) << ','
     << num(w.begin) << ',' << num(w.end) << ',' << num(w.minTtc) << ',' << num(w.minTtcTime) << ','
     << num(w.safeTimeAtMin) << ',' << (w.open ? 1 : 0);
  // hindsight: empty where it does not apply (unjudged; a road warning's clearance, a vehicle
  // warning's crossing)
  auto field = [](double x) { return std::isfinite(x) ? num(x) : std::string(); };
  const bool judged = w.verdict != Verdict::Unjudged, vehicle = w.kind == WarningKind::Vehicle;
  os << ',' << toString(w.verdict) << ',' << (judged && vehicle ? field(w.clearance) : "") << ','
     << (judged ? field(w.clearanceTime) : "") << ',' << (judged && vehicle ? num(w.deceleration) : "") << ','
     << (judged && !vehicle ? (w.crossed ? "1" : "0") : "") << ',' << (judged && !vehicle ? (w.signalled ? "1" : "0") : "");
  // SSAM's measures (vehicle warnings)
  // (what is read or copied from the inputs in full; what is worked out from them to 0.001)
  os << ',' << derivedField(w.conflictX) << ',' << derivedField(w.conflictY) << ',' << conflictField(w.foeX) << ','
     << conflictField(w.foeY) << ',' << conflictField(w.maxSpeed) << ',' << derivedField(w.deltaSpeed) << ','
     << derivedField(w.dr) << ',' << derivedField(w.maxDecel) << ',' << derivedField(w.conflictAngle) << ','
     << conflictField(w.clockAngle) << ',' << conflictField(w.startX) << ',' << conflictField(w.startY) << ','
     << conflictField(w.endX) << ',' << conflictField(w.endY) << ',' << derivedField(w.postCrashSpeed) << ','
     << derivedField(w.postCrashHeading) << ',' << derivedField(w.pet);
  os << ',' << conflictField(w.x) << ',' << conflictField(w.y) << ',' << csvField(w.lane) << ',' << conflictField(w.egoSpeed) << ','
     << conflictField(w.foeSpeed) << ',' << derivedField(w.headingAngle) << ',' << toString(w.type) << ',' << derivedField(w.drac) << ','
     << derivedField(w.maxDeltaV) << ',' << csvField(w.line) << ',' << conflictField(w.lateralSpeed);
  return os.str();
}

WarningsCsvWriter::WarningsCsvWriter(const std::filesystem::path& path) : CsvRowWriter(path, warningsCsvHeader()) {}
void WarningsCsvWriter::write(std::span<const Warning> warnings) {
  for (const Warning& w : warnings) row(warningCsvRow(w));
}

TrajectoriesCsvWriter::TrajectoriesCsvWriter(const std::filesystem::path& path)
    : CsvRowWriter(path, "ego,foe,kind,begin,time,ttc,drac") {}
void TrajectoriesCsvWriter::write(std::span<const TrajectoryPoint> points) {
  for (const TrajectoryPoint& p : points)
    row(csvField(p.ego) + ',' + csvField(p.foe) + ',' + toString(p.kind) + ',' + num(p.begin) + ',' + num(p.time) + ',' +
        conflictField(p.ttc) + ',' + derivedField(p.drac));
}

std::string eventCsvRow(const HindsightEvent& e) {
  auto field = [](double x) { return std::isfinite(x) ? num(x) : std::string(); };
  std::ostringstream os;
  os << num(e.time) << ',' << toString(e.kind) << ',' << csvField(e.ego) << ',' << csvField(e.foe) << ',' << num(e.x) << ','
     << num(e.y) << ',' << csvField(e.lane) << ',' << num(e.speed) << ',' << field(e.gap) << ',' << field(e.lateralSpeed)
     << ',' << (e.warned ? 1 : 0) << ',' << field(e.lead);
  return os.str();
}

std::string eventsCsvHeader() { return "time,kind,ego,foe,x,y,lane,speed,gap,lateral_speed,warned,lead"; }

EventsCsvWriter::EventsCsvWriter(const std::filesystem::path& path) : CsvRowWriter(path, eventsCsvHeader()) {}
void EventsCsvWriter::write(std::span<const HindsightEvent> events) {
  for (const HindsightEvent& e : events) row(eventCsvRow(e));
}

std::string summaryJson(const MonitorCounters& c, const RunInfo& info) {
  std::ostringstream os;
  const double km = c.vehicleMeters / 1000.0;
  std::uint64_t total = 0;
  for (auto n : c.warningsByKind) total += n;
  os << "{\n";
  os << "  \"source\": " << jsonString(info.source) << ",\n";
  os << "  \"detector\": " << jsonString(info.detector) << ",\n";
  os << "  \"broadphase\": " << jsonString(info.broadphase) << ",\n";
  os << "  \"prediction\": " << jsonString(info.prediction) << ",\n";
  os << "  \"simulated_s\": " << num(info.simulatedSeconds) << ",\n";
  os << "  \"ticks\": " << c.ticks << ",\n";
  os << "  \"vehicles\": " << c.vehiclesSeen << ",\n";
  os << "  \"persons\": " << c.personsSeen << ",\n";
  os << "  \"vehicle_updates\": " << c.vehicleUpdates << ",\n";
  os << "  \"vehicle_km\": " << num(km) << ",\n";
  os << "  \"warnings\": {\n    \"total\": " << total << ",\n    \"per_vehicle_km\": " << num(km > 0 ? static_cast<double>(total) / km : 0.0)
     << ",\n    \"by_kind\": {";
  for (int k = 0; k < kWarningKindCount; ++k)
    os << (k ? ", " : "") << jsonString(toString(static_cast<WarningKind>(k))) << ": " << c.warningsByKind[k];
  os << "},\n    \"by_zone\": {";
  for (int z = 0; z < kZoneCount; ++z)
    os << (z ? ", " : "") << jsonString(toString(static_cast<Zone>(z))) << ": " << c.warningsByZone[z];
  os << "},\n    \"conflicts\": " << conflictWarnings(c) << ",\n    \"by_type\": {";
  for (int k = 0; k < kConflictTypeCount; ++k)
    os << (k ? ", " : "") << jsonString(toString(static_cast<ConflictType>(k))) << ": " << c.warningsByType[k];
  os << "},\n    \"per_vehicle_km_by_type\": {";
  for (int k = 0; k < kConflictTypeCount; ++k)
    os << (k ? ", " : "") << jsonString(toString(static_cast<ConflictType>(k))) << ": "
       << num(km > 0 ? static_cast<double>(c.warningsByType[k]) / km : 0.0);
  os << "},\n    \"per_vehicle_km_by_kind\": {";
  for (int k = 0; k < kWarningKindCount; ++k)
    os << (k ? ", " : "") << jsonString(toString(static_cast<WarningKind>(k))) << ": "
       << num(km > 0 ? static_cast<double>(c.warningsByKind[k]) / km : 0.0);
  os << "}\n  },\n";
  os << "  \"conflicts\": " << conflictsJson(c, info.conflict) << ",\n";
  os << "  \"tet_s\": {";
  for (int k = 0; k < kWarningKindCount; ++k)
    os << (k ? ", " : "") << jsonString(toString(static_cast<WarningKind>(k))) << ": " << num(c.tet[k]);
  os << "},\n  \"tit_s2\": {";
  for (int k = 0; k < kWarningKindCount; ++k)
    os << (k ? ", " : "") << jsonString(toString(static_cast<WarningKind>(k))) << ": " << num(c.tit[k]);
  os << "},\n";
  os << "  \"hindsight\": " << hindsightJson(c, info.hindsight) << ",\n";
  os << "  \"handoffs\": " << c.handoffs << ",\n";
  os << "  \"subdivisions\": " << c.subdivisions << ",\n";
  os << "  \"reunions\": " << c.reunions << ",\n";
  os << "  \"candidate_pairs\": " << c.candidatePairs << ",\n";
  os << "  \"toi_checks\": " << c.toiChecks << ",\n";
  os << "  \"feature_checks\": " << c.featureChecks << ",\n";
  // road prediction: updates predicted along a lane, and those in a straight line (no fitting lane, or stopped)
  os << "  \"road_predicted_updates\": " << c.roadPredicted << ",\n";
  os << "  \"route_predicted_updates\": " << c.routePredicted << ",\n";
  os << "  \"straight_fallback_updates\": " << c.straightFallbacks << ",\n";
  for (const auto& [k, v] : info.numbers) os << "  " << jsonString(k) << ": " << num(v) << ",\n";
  for (const auto& [k, v] : info.strings) os << "  " << jsonString(k) << ": " << jsonString(v) << ",\n";
  for (const auto& [k, v] : info.rawJson) os << "  " << jsonString(k) << ": " << v << ",\n";
  os << "  \"wall_s\": " << num(info.wallSeconds) << "\n}\n";
  return os.str();
}

std::string conflictTypeBreakdown(const MonitorCounters& c) {
  // SSAM's conflicts first, then apart what is none of them: proximity (zones only), road
  auto n = [&](ConflictType t) { return std::to_string(c.warningsByType[static_cast<int>(t)]); };
  std::string s;
  for (ConflictType t : kConflictTypes)
    s += std::string(t == ConflictType::RearEnd ? "" : ", ") + toString(t) + " " + n(t);
  return s + "; proximity " + n(ConflictType::Proximity) + " (zone occupied, no collision course); road " +
         n(ConflictType::Road);
}

std::uint64_t conflictWarnings(const MonitorCounters& c) {
  std::uint64_t n = 0;
  for (int k = 0; k < kConflictTypeCount; ++k)
    if (isConflictType(static_cast<ConflictType>(k))) n += c.warningsByType[k];
  return n;
}

void writeSummaryJson(const std::filesystem::path& path, const MonitorCounters& counters, const RunInfo& info) {
  io::writeTextFile(path, summaryJson(counters, info));
}

void removeRunOutputs(const std::filesystem::path& out) {
  for (const char* f : {"warnings.csv", "conflicts.csv", "events.csv", "trajectories.csv", "summary.json", "collisions.csv", "collision_warnings.csv", "validation.json", "exposure.csv",
                        "ssm.xml", "sumo_collisions.xml", "sumo.log", "conflict_map.png", "conflict_map.svg",
                        "conflict_map.log"}) {
    std::error_code ec;
    std::filesystem::remove(out / f, ec);
    if (ec) throw std::runtime_error("cannot remove the earlier " + (out / f).string() + ": " + ec.message());
  }
}

}  // namespace st::highway
