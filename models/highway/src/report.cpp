#include <sthighway/report.hpp>

#include <algorithm>
#include <cmath>
#include <span>

#include <stio/format.hpp>
#include <stio/json.hpp>

#include <sstream>
#include <stdexcept>

namespace st::highway {

namespace {

// JSON has no NaN or infinity: null stands for them (in warnings.csv too, which has always said so).
std::string num(double x) { return io::jsonNumber(x); }
using io::csvField;

using io::JsonText;

// a share, or null when there is nothing to count
JsonText share(std::uint64_t part, std::uint64_t whole) {
  JsonText j;
  if (whole)
    j << static_cast<double>(part) / static_cast<double>(whole);
  else
    j << io::jsonRaw("null");
  return j;
}

// per vehicle-km (0 when no distance was driven)
double perKm(std::uint64_t n, double km) { return km > 0 ? static_cast<double>(n) / km : 0.0; }

// lead times: min, median, 90th percentile (null when none)
JsonText leadJson(std::vector<double> v) {
  JsonText j;
  if (v.empty()) {
    j << io::jsonRaw("null");
    return j;
  }
  std::sort(v.begin(), v.end());
  auto q = [&](double f) { return v[static_cast<std::size_t>(f * static_cast<double>(v.size() - 1) + 0.5)]; };
  j << "{\"min\": " << v.front() << ", \"median\": " << q(0.5) << ", \"p90\": " << q(0.9) << "}";
  return j;
}

// {"a": x, "b": y, ...}: each of keys by its name, x = value(its index): one line of summary.json
template <class Enum, class Value>
JsonText byEnum(std::span<const Enum> keys, Value value) {
  JsonText j;
  j << "{";
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (i) j << ", ";
    j << toString(keys[i]) << ": " << value(static_cast<int>(keys[i]));
  }
  j << "}";
  return j;
}

// The same over all of an enum's count values, in order.
template <class Enum, class Value>
JsonText byEnum(int count, Value value) {
  std::vector<Enum> keys;
  for (int k = 0; k < count; ++k) keys.push_back(static_cast<Enum>(k));
  return byEnum(std::span<const Enum>(keys), value);
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
  JsonText j;
  j << "{\"clearance_m\": " << h.clearance << ", \"evasive_deceleration\": " << h.evasiveDeceleration
    << ", \"lead_s\": " << h.lead << ", \"near_miss_ttc_s\": " << h.nearMissTtc << ",\n    \"by_kind\": ";
  j << byEnum<WarningKind>(kWarningKindCount, [&](int k) {
    JsonText kind;
    kind << "{\"judged\": " << c.judged[k] << ", \"confirmed\": " << c.confirmed[k]
         << ", \"precision\": " << share(c.confirmed[k], c.judged[k]) << "}";
    return kind;
  });
  j << ",\n    \"near_misses\": " << io::jsonRaw(eventRecallJson(c.nearMisses, c.nearMissesWarned, c.nearMissLeads))
    << ",\n    \"crossings\": " << io::jsonRaw(eventRecallJson(c.crossings, c.crossingsWarned, c.crossingLeads)) << "}";
  return j.str();
}

std::string eventRecallJson(std::uint64_t events, std::uint64_t warned, const std::vector<double>& leads) {
  JsonText j;
  j << "{\"events\": " << events << ", \"warned\": " << warned << ", \"recall\": " << share(warned, events)
    << ", \"lead_s\": " << leadJson(leads) << "}";
  return j.str();
}

std::string conflictsCsvHeader() {
  return "first,second,type,encounter,begin,end,min_ttc,min_ttc_time,pet,drac,max_s,delta_s,dr,max_d,max_delta_v,"
         "first_delta_v,second_delta_v,conflict_angle,clock_angle,post_crash_speed,post_crash_heading,conflict_x,conflict_y,"
         "paths_meet_x,paths_meet_y,first_x,first_y,second_x,second_y,first_speed,second_speed,first_start_x,first_start_y,first_end_x,first_end_y,"
         "second_start_x,second_start_y,second_end_x,second_end_y,first_lane,second_lane,junction,first_class,second_class,"
         "first_length,second_length,first_width,second_width,tet,tit,open";
}

std::string conflictCsvRow(const Conflict& c) {
  // as warnings.csv: what is read or copied from the inputs in full, what is worked out to 0.001
  std::ostringstream os;
  os << csvField(c.first) << ',' << csvField(c.second) << ',' << toString(c.type) << ','
     << (c.encounter == EncounterType::Unknown ? "" : toString(c.encounter)) << ',' << num(c.begin) << ','
     << num(c.end) << ',' << conflictField(c.minTtc) << ',' << num(c.minTtcTime) << ',' << derivedField(c.pet) << ','
     << derivedField(c.drac) << ',' << conflictField(c.maxSpeed) << ',' << derivedField(c.deltaSpeed) << ','
     << derivedField(c.dr) << ',' << derivedField(c.maxD) << ',' << derivedField(c.maxDeltaV) << ','
     << derivedField(c.firstDeltaV) << ',' << derivedField(c.secondDeltaV) << ',' << derivedField(c.conflictAngle) << ','
     << conflictField(c.clockAngle) << ',' << derivedField(c.postCrashSpeed) << ',' << derivedField(c.postCrashHeading)
     << ',' << derivedField(c.conflictX) << ',' << derivedField(c.conflictY) << ',' << derivedField(c.pathsMeetX) << ','
     << derivedField(c.pathsMeetY) << ',' << conflictField(c.firstX) << ','
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

std::uint64_t conflictsWithBicycle(const MonitorCounters& c) {
  std::uint64_t n = 0;
  for (auto k : c.conflictsWithBicycle) n += k;
  return n;
}

std::string conflictCountText(const MonitorCounters& c) {
  std::string s = std::to_string(conflictCount(c)) + " (";
  for (ConflictType t : kConflictTypes)
    s += std::string(t == ConflictType::RearEnd ? "" : ", ") + toString(t) + " " +
         std::to_string(c.conflictsByType[static_cast<int>(t)]);
  // the bicycles' share, only when there is one (a run without bicycles reads as before)
  if (const std::uint64_t bikes = conflictsWithBicycle(c)) {
    s += "; with a bicycle " + std::to_string(bikes) + ":";
    for (ConflictType t : kConflictTypes)
      s += std::string(t == ConflictType::RearEnd ? " " : ", ") + toString(t) + " " +
           std::to_string(c.conflictsWithBicycle[static_cast<int>(t)]);
    s += ", between two bicycles " + std::to_string(c.conflictsBetweenBicycles);
  }
  return s + ")";
}

// the conflicts with a bicycle: their count, those between two bicycles, by type
JsonText withBicycleJson(const MonitorCounters& c) {
  JsonText j;
  j << "{\"count\": " << conflictsWithBicycle(c) << ", \"between_bicycles\": " << c.conflictsBetweenBicycles
    << ", \"by_type\": " << byEnum(std::span<const ConflictType>(kConflictTypes), [&](int k) { return c.conflictsWithBicycle[k]; })
    << "}";
  return j;
}

// the conflicts' count per junction (each type and all), and the count outside junctions
JsonText junctionsJson(const MonitorCounters& c, std::uint64_t total) {
  JsonText j;
  j << "{";
  bool first = true;
  std::uint64_t inJunctions = 0;
  for (const auto& [junction, byType] : c.conflictsByJunction) {
    std::uint64_t count = 0;
    for (auto k : byType) count += k;
    inJunctions += count;
    if (!first) j << ", ";
    j << junction << ": {\"count\": " << count;
    for (ConflictType t : kConflictTypes) j << ", " << toString(t) << ": " << byType[static_cast<int>(t)];
    j << ", \"by_approach\": {";
    bool firstApproach = true;
    if (const auto it = c.conflictsByApproach.find(junction); it != c.conflictsByApproach.end())
      for (const auto& [edge, n] : it->second) {
        if (!firstApproach) j << ", ";
        j << edge << ": " << n;
        firstApproach = false;
      }
    j << "}}";
    first = false;
  }
  j << "}, \"outside_junctions\": " << total - inJunctions;
  return j;
}

std::string conflictsJson(const MonitorCounters& c, const ConflictConfig& config) {
  const double km = c.vehicleMeters / 1000.0;
  const std::uint64_t n = conflictCount(c);
  const std::span<const ConflictType> types(kConflictTypes);
  JsonText j;
  j << "{\"count\": " << n << ", \"per_vehicle_km\": " << perKm(n, km) << ", \"max_ttc_s\": " << config.maxTtc
    << ", \"max_pet_s\": " << config.maxPet << ",\n    \"by_type\": "
    << byEnum(types, [&](int k) { return c.conflictsByType[k]; })
    << ",\n    \"per_vehicle_km_by_type\": "
    << byEnum(types, [&](int k) { return perKm(c.conflictsByType[k], km); })
    << ",\n    \"by_encounter\": " << byEnum<EncounterType>(kEncounterTypeCount, [&](int k) { return c.conflictsByEncounter[k]; })
    << ",\n    \"by_junction\": " << junctionsJson(c, n);
  j << ",\n    \"with_bicycle\": " << withBicycleJson(c);
  j << ",\n    \"tet_s\": " << c.conflictTet << ", \"tit_s2\": " << c.conflictTit
    << ", \"over_max_pet\": " << c.conflictsOverMaxPet << "}";
  return j.str();
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

// summary.json's "warnings": total, by kind, zone and type, per vehicle-km
JsonText warningsJson(const MonitorCounters& c, double km) {
  std::uint64_t total = 0;
  for (auto n : c.warningsByKind) total += n;
  JsonText j;
  j << "{\n    \"total\": " << total << ",\n    \"per_vehicle_km\": " << perKm(total, km)
    << ",\n    \"by_kind\": " << byEnum<WarningKind>(kWarningKindCount, [&](int k) { return c.warningsByKind[k]; })
    << ",\n    \"by_zone\": " << byEnum<Zone>(kZoneCount, [&](int z) { return c.warningsByZone[z]; })
    << ",\n    \"conflicts\": " << conflictWarnings(c)
    << ",\n    \"by_type\": " << byEnum<ConflictType>(kConflictTypeCount, [&](int k) { return c.warningsByType[k]; })
    << ",\n    \"per_vehicle_km_by_type\": "
    << byEnum<ConflictType>(kConflictTypeCount, [&](int k) { return perKm(c.warningsByType[k], km); })
    << ",\n    \"per_vehicle_km_by_kind\": "
    << byEnum<WarningKind>(kWarningKindCount, [&](int k) { return perKm(c.warningsByKind[k], km); }) << "\n  }";
  return j;
}

std::string summaryJson(const MonitorCounters& c, const RunInfo& info) {
  const double km = c.vehicleMeters / 1000.0;
  JsonText j;
  j << "{\n";
  j << "  \"source\": " << info.source << ",\n";
  j << "  \"detector\": " << info.detector << ",\n";
  j << "  \"broadphase\": " << info.broadphase << ",\n";
  j << "  \"prediction\": " << info.prediction << ",\n";
  j << "  \"simulated_s\": " << info.simulatedSeconds << ",\n";
  j << "  \"ticks\": " << c.ticks << ",\n";
  j << "  \"vehicles\": " << c.vehiclesSeen << ",\n";
  j << "  \"persons\": " << c.personsSeen << ",\n";
  j << "  \"vehicle_updates\": " << c.vehicleUpdates << ",\n";
  j << "  \"vehicle_km\": " << km << ",\n";
  j << "  \"warnings\": " << warningsJson(c, km) << ",\n";
  j << "  \"conflicts\": " << io::jsonRaw(conflictsJson(c, info.conflict)) << ",\n";
  j << "  \"tet_s\": " << byEnum<WarningKind>(kWarningKindCount, [&](int k) { return c.tet[k]; }) << ",\n";
  j << "  \"tit_s2\": " << byEnum<WarningKind>(kWarningKindCount, [&](int k) { return c.tit[k]; }) << ",\n";
  j << "  \"hindsight\": " << io::jsonRaw(hindsightJson(c, info.hindsight)) << ",\n";
  j << "  \"handoffs\": " << c.handoffs << ",\n";
  j << "  \"subdivisions\": " << c.subdivisions << ",\n";
  j << "  \"reunions\": " << c.reunions << ",\n";
  j << "  \"candidate_pairs\": " << c.candidatePairs << ",\n";
  j << "  \"toi_checks\": " << c.toiChecks << ",\n";
  j << "  \"feature_checks\": " << c.featureChecks << ",\n";
  // road prediction: updates predicted along a lane, and those in a straight line (no fitting lane, or stopped)
  j << "  \"road_predicted_updates\": " << c.roadPredicted << ",\n";
  j << "  \"route_predicted_updates\": " << c.routePredicted << ",\n";
  j << "  \"straight_fallback_updates\": " << c.straightFallbacks << ",\n";
  for (const auto& [k, v] : info.numbers) j << "  " << k << ": " << v << ",\n";
  for (const auto& [k, v] : info.strings) j << "  " << k << ": " << v << ",\n";
  for (const auto& [k, v] : info.rawJson) j << "  " << k << ": " << io::jsonRaw(v) << ",\n";
  j << "  \"wall_s\": " << info.wallSeconds << "\n}\n";
  return j.str();
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
