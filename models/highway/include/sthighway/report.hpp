#pragma once
// Output files: warnings.csv (one row per episode) and events.csv (hindsight's near misses and
// crossings), streamed so a run that stops early leaves valid files, and summary.json.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <sthighway/monitor.hpp>
#include <stio/output.hpp>

namespace st::highway {

// A CSV file written row by row, flushed as the run goes, every write checked (st::io).
using CsvRowWriter = io::CsvRowWriter;

// warnings.csv. Columns: ego,foe,kind,zone,begin,end,min_ttc,min_ttc_time,safe_time,open, then hindsight's:
// verdict,clearance,clearance_time,deceleration,crossed,signalled, then SSAM's measures of a vehicle warning:
// conflict_x,conflict_y,foe_x,foe_y,max_s,delta_s,dr,max_d,conflict_angle,clock_angle,start_x,start_y,end_x,end_y,
// post_crash_speed,post_crash_heading,pet, then the conflict at the minimum TTC: x,y,lane,ego_speed,foe_speed,heading_angle,type,drac,max_delta_v,line,
// lateral_speed (models/highway/README.md; empty where a column does not apply).
class WarningsCsvWriter : public CsvRowWriter {
 public:
  explicit WarningsCsvWriter(const std::filesystem::path& path);
  void write(std::span<const Warning> warnings);
};

// trajectories.csv (--trajectories): each episode's TTC and DRAC at every tick it holds, one a row.
// Columns: ego,foe,kind,begin (the episode, as warnings.csv names it),time,ttc,drac (`inf` touching while closing).
class TrajectoriesCsvWriter : public CsvRowWriter {
 public:
  explicit TrajectoriesCsvWriter(const std::filesystem::path& path);
  void write(std::span<const TrajectoryPoint> points);
};

// events.csv: hindsight's near misses and unsignalled crossings (HindsightEvent), one a row.
// Columns: time,kind,ego,foe,x,y,lane,speed,gap,lateral_speed,warned,lead (empty where a column
// does not apply or, lead, no warning about it began by then).
class EventsCsvWriter : public CsvRowWriter {
 public:
  explicit EventsCsvWriter(const std::filesystem::path& path);
  void write(std::span<const HindsightEvent> events);
};
std::string eventsCsvHeader();
std::string eventCsvRow(const HindsightEvent& e);

// conflicts.csv: one row per conflict (Conflict: an unordered pair and one encounter below TTC*),
// first and second vehicle as SSAM names them, with SSAM's measures (docs/outputs.md).
class ConflictsCsvWriter : public CsvRowWriter {
 public:
  explicit ConflictsCsvWriter(const std::filesystem::path& path);
  void write(std::span<const Conflict> conflicts);
};
std::string conflictsCsvHeader();
std::string conflictCsvRow(const Conflict& c);

std::string warningsCsvHeader();
std::string warningCsvRow(const Warning& w);

// What summary.json says besides the monitor's counters.
struct RunInfo {
  std::string source;            // trace or scenario path
  std::string detector;
  std::string broadphase;
  std::string prediction;        // "road" or "straight" (Prediction)
  double simulatedSeconds = 0.0;
  double wallSeconds = 0.0;
  // Extra top-level fields for other front ends (e.g. SUMO time split): numbers and strings,
  // and raw JSON values (written verbatim).
  std::vector<std::pair<std::string, double>> numbers;
  std::vector<std::pair<std::string, std::string>> strings;
  std::vector<std::pair<std::string, std::string>> rawJson;
  HindsightConfig hindsight;     // the thresholds the run judged with
  ConflictConfig conflict;       // the thresholds its conflicts were counted against
};

// summary.json's "hindsight": thresholds, per kind judged / confirmed / precision, near misses
// with recall and lead times (null figures where there is nothing to count).
std::string hindsightJson(const MonitorCounters& counters, const HindsightConfig& config);
// One kind of actual event's recall, as summary.json writes it: {"events", "warned" (the lead time
// ahead), "recall" (null for no event), "lead_s": the warned ones' lead times, min, median and
// p90 (null for none)}.
std::string eventRecallJson(std::uint64_t events, std::uint64_t warned, const std::vector<double>& leads);

// summary.json's "conflicts": the conflicts of conflicts.csv (count, by type, per vehicle-km, by
// junction, with a bicycle), the thresholds TTC* and PET*, TET and TIT against TTC*, those left out by PET*.
std::string conflictsJson(const MonitorCounters& counters, const ConflictConfig& config);
// The conflicts counted (every type).
std::uint64_t conflictCount(const MonitorCounters& counters);
// The conflicts counted with a bicycle in them (car-bicycle and bicycle-bicycle, every type).
std::uint64_t conflictsWithBicycle(const MonitorCounters& counters);
// "N (rear_end N, lane_change N, crossing N, pedestrian N)" for a printed summary, followed, when
// any conflict has a bicycle in it, by "; with a bicycle N: rear_end N, ..., between two bicycles N".
std::string conflictCountText(const MonitorCounters& counters);

// summary.json: vehicles, vehicle_km, warnings (total, by kind, by zone, conflicts (SSAM's types), by conflict
// type, per vehicle-km),
// tet_s / tit_s2 by kind, handoffs, subdivisions, candidate_pairs, toi_checks, wall time.
std::string summaryJson(const MonitorCounters& counters, const RunInfo& info);
void writeSummaryJson(const std::filesystem::path& path, const MonitorCounters& counters,
                      const RunInfo& info);

// Removes from out every file a highway run may write (warnings.csv, conflicts.csv, events.csv, trajectories.csv, summary.json and, from SUMO
// runs, collisions.csv, collision_warnings.csv, validation.json, ssm.xml, sumo_collisions.xml,
// sumo.log; the conflict map), so that what is there after a run belongs to it. Throws std::runtime_error.
void removeRunOutputs(const std::filesystem::path& out);

// "rear_end N, lane_change N, crossing N; proximity N (zone occupied, no collision course); road N"
// (for a printed summary): SSAM's conflicts, then apart the warnings that are none.
std::string conflictTypeBreakdown(const MonitorCounters& counters);
// The finished warnings of the conflict types (kConflictTypes: on a collision course); summary.json's
// warnings.conflicts.
std::uint64_t conflictWarnings(const MonitorCounters& counters);

}  // namespace st::highway
