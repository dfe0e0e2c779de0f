// stsim._stsim: the highway model (models/highway) for Python, a thin layer over the parts in
// this folder: values.hpp (checked conversions), states (vehicle states in and out), settings
// (the monitor's settings from keywords), road, monitor.hpp (the monitor as Python holds it),
// records.hpp (warnings' fields, the FCD reader). Every bad input is a Python exception naming
// the vehicle and key; nothing is clamped or guessed.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <sthighway/report.hpp>
#include <sthighway/sumo_conversion.hpp>
#include <stsim/version.hpp>

#include "monitor.hpp"
#include "records.hpp"
#include "road.hpp"
#include "settings.hpp"
#include "states.hpp"
#include "values.hpp"

namespace py = pybind11;
namespace hw = st::highway;
using namespace stpy;

PYBIND11_MODULE(_stsim, m) {
  m.doc() = "stsim's smart-car collision warnings (the SUMO-free highway model)";
  m.attr("__version__") = STSIM_VERSION_STRING;
  py::register_exception<hw::InputError>(m, "InputError", PyExc_ValueError);

  py::class_<hw::HindsightEvent>(m, "HindsightEvent",
                                 "A near miss or an unsignalled line crossing that happened, and whether it was warned\n"
                                 "(what events.csv has: models/highway/README.md, Hindsight).")
      .def_property_readonly("kind", [](const hw::HindsightEvent& e) { return hw::toString(e.kind); }, "near_miss or crossing")
      .def_readonly("time", &hw::HindsightEvent::time)
      .def_readonly("ego", &hw::HindsightEvent::ego)
      .def_readonly("foe", &hw::HindsightEvent::foe, "near miss: the other vehicle; crossing: the line")
      .def_readonly("x", &hw::HindsightEvent::x)
      .def_readonly("y", &hw::HindsightEvent::y)
      .def_readonly("lane", &hw::HindsightEvent::lane)
      .def_readonly("speed", &hw::HindsightEvent::speed)
      .def_property_readonly("gap", [](const hw::HindsightEvent& e) { return conflictNumber(e.gap); }, "m, near miss: body to body")
      .def_property_readonly("lateral_speed", [](const hw::HindsightEvent& e) { return conflictNumber(e.lateralSpeed); },
                             "m/s, crossing: towards the line")
      .def_readonly("warned", &hw::HindsightEvent::warned, "a warning about it was open the lead time before")
      .def_property_readonly("lead", [](const hw::HindsightEvent& e) { return conflictNumber(e.lead); },
                             "s since the earliest warning about it began; None: not warned");

  auto episodeClass = py::class_<hw::Warning>(m, "WarningEpisode", "One warning episode: (ego, foe, kind) from its first tick to its end.")
      .def_readonly("ego", &hw::Warning::ego)
      .def_readonly("foe", &hw::Warning::foe)
      .def_property_readonly("kind", [](const hw::Warning& w) { return hw::toString(w.kind); })
      .def_property_readonly("zone", [](const hw::Warning& w) { return hw::toString(w.zone); })
      .def_readonly("begin", &hw::Warning::begin)
      .def_readonly("end", &hw::Warning::end)
      .def_readonly("min_ttc", &hw::Warning::minTtc)
      .def_readonly("min_ttc_time", &hw::Warning::minTtcTime)
      .def_readonly("safe_time", &hw::Warning::safeTimeAtMin)
      .def_readonly("open", &hw::Warning::open)
      // hindsight and the conflict record: what warnings.csv has in these columns, None where its
      // cell is empty (the column does not apply to the kind, or the episode is not judged)
      .def_property_readonly("verdict", [](const hw::Warning& w) { return hw::toString(w.verdict); },
                             "confirmed, nuisance, or '' (not judged: open, or hindsight off)")
      .def_property_readonly("clearance", [](const hw::Warning& w) { return vehicleJudged(w, w.clearance); },
                             "m, vehicle: the smallest body-to-body distance in the window")
      .def_property_readonly("clearance_time", [](const hw::Warning& w) { return judgedNumber(w, w.clearanceTime); },
                             "s, when (road: when the body touched the line)")
      .def_property_readonly("deceleration", [](const hw::Warning& w) { return vehicleJudged(w, w.deceleration); },
                             "m/s^2, vehicle: the strongest braking of either vehicle in the window")
      .def_property_readonly("crossed", [](const hw::Warning& w) { return roadJudged(w, w.crossed); },
                             "road: the body touched the line within the safe time")
      .def_property_readonly("signalled", [](const hw::Warning& w) { return roadJudged(w, w.signalled); },
                             "road: with the turn signal of that side on")
      .def_property_readonly("x", [](const hw::Warning& w) { return conflictNumber(w.x); }, "m, the ego's centre at the minimum TTC")
      .def_property_readonly("y", [](const hw::Warning& w) { return conflictNumber(w.y); })
      .def_readonly("lane", &hw::Warning::lane, "the ego's lane id, '' if unknown")
      .def_property_readonly("ego_speed", [](const hw::Warning& w) { return conflictNumber(w.egoSpeed); }, "m/s")
      .def_property_readonly("foe_speed", [](const hw::Warning& w) { return conflictNumber(w.foeSpeed); }, "m/s; None for road warnings")
      .def_property_readonly("heading_angle", [](const hw::Warning& w) { return conflictNumber(w.headingAngle); },
                             "deg between the headings; road: to the line; None for a hazard")
      .def_property_readonly("type", [](const hw::Warning& w) { return hw::toString(w.type); },
                             "rear_end, lane_change, crossing (SSAM's angles, on a collision course), proximity (only the detector's "
                             "zones meet or overlap: no collision course) or road")
      .def_property_readonly("drac", [](const hw::Warning& w) { return conflictNumber(w.drac); },
                             "m/s^2, deceleration rate to avoid the crash (inf at TTC 0 while closing); None for proximity")
      .def_property_readonly("max_delta_v", [](const hw::Warning& w) { return conflictNumber(w.maxDeltaV); },
                             "m/s, SSAM's MaxDeltaV; None for road warnings")
      .def_readonly("line", &hw::Warning::line, "road warnings: the curb, marker or hazard")
      .def_property_readonly("lateral_speed", [](const hw::Warning& w) { return conflictNumber(w.lateralSpeed); },
                             "m/s, road warnings: the ego's speed towards the line; None for vehicles")
      .def("__repr__", [](const hw::Warning& w) {
        return "<WarningEpisode " + w.ego + " -> " + w.foe + " " + hw::toString(w.kind) + " " + hw::toString(w.zone) + " [" +
               std::to_string(w.begin) + ", " + std::to_string(w.end) + "] min_ttc " + std::to_string(w.minTtc) + ">";
      });
  // SSAM's measures of a vehicle warning: warnings.csv's columns of the same names, None where empty
  struct SsamField {
    const char* name;
    double hw::Warning::*field;
    const char* doc;
  };
  static constexpr SsamField kSsamFields[] = {
      {"conflict_x", &hw::Warning::conflictX, "m, the predicted contact point (collision course only)"},
      {"conflict_y", &hw::Warning::conflictY, "m"},
      {"foe_x", &hw::Warning::foeX, "m, the foe's centre at the minimum TTC"},
      {"foe_y", &hw::Warning::foeY, "m"},
      {"max_s", &hw::Warning::maxSpeed, "m/s, SSAM's MaxS: either vehicle's largest speed over the episode"},
      {"delta_s", &hw::Warning::deltaSpeed, "m/s, SSAM's DeltaS: |v_ego - v_foe| at the minimum TTC"},
      {"dr", &hw::Warning::dr, "m/s^2, SSAM's DR: the ego's first negative acceleration after begin, else its lowest"},
      {"max_d", &hw::Warning::maxDecel, "m/s^2, SSAM's MaxD: the ego's lowest acceleration over the episode"},
      {"conflict_angle", &hw::Warning::conflictAngle, "deg, SSAM's conflict angle: the foe's heading relative to the ego's"},
      {"clock_angle", &hw::Warning::clockAngle, "h, the conflict angle as a clock position 1..12"},
      {"start_x", &hw::Warning::startX, "m, the ego's centre at begin"},
      {"start_y", &hw::Warning::startY, "m"},
      {"end_x", &hw::Warning::endX, "m, the ego's centre at end"},
      {"end_y", &hw::Warning::endY, "m"},
      {"post_crash_speed", &hw::Warning::postCrashSpeed, "m/s, the perfectly inelastic crash's common speed"},
      {"post_crash_heading", &hw::Warning::postCrashHeading, "deg counter-clockwise from +x, its heading"},
      {"pet", &hw::Warning::pet, "s, post-encroachment time of a lane_change or crossing conflict"}};
  for (const SsamField& f : kSsamFields)
    episodeClass.def_property_readonly(
        f.name, [field = f.field](const hw::Warning& w) { return conflictNumber(w.*field); }, f.doc);


  // conflicts.csv's row (sthighway/monitor.hpp, Conflict): every column an attribute of the same
  // name, None where the file leaves the cell empty
  auto conflictClass = py::class_<hw::Conflict>(
      m, "Conflict",
      "One conflict for the analyst, as a row of conflicts.csv: an unordered pair and one encounter below TTC*,\n"
      "first and second vehicle as SSAM names them (docs/outputs.md, conflicts.csv).");
  conflictClass.def_readonly("first", &hw::Conflict::first)
      .def_readonly("second", &hw::Conflict::second)
      .def_property_readonly("type", [](const hw::Conflict& c) { return hw::toString(c.type); },
                             "SSAM's class: rear_end, lane_change, crossing or pedestrian")
      .def_property_readonly(
          "encounter", [](const hw::Conflict& c) { return c.encounter == hw::EncounterType::Unknown ? "" : hw::toString(c.encounter); },
          "how the paths meet, from the lanes: following, merging, diverging, crossing, opposing, adjacent, pedestrian; '' unknown")
      .def_readonly("begin", &hw::Conflict::begin)
      .def_readonly("end", &hw::Conflict::end)
      .def_readonly("min_ttc", &hw::Conflict::minTtc)
      .def_readonly("min_ttc_time", &hw::Conflict::minTtcTime)
      .def_readonly("first_lane", &hw::Conflict::firstLane, "lane id, '' if unknown")
      .def_readonly("second_lane", &hw::Conflict::secondLane)
      .def_readonly("junction", &hw::Conflict::junction, "the SUMO junction either lane lies in, else the one the paths meet in; '' for none")
      .def_property_readonly("first_class", [](const hw::Conflict& c) { return hw::toString(c.firstClass); })
      .def_property_readonly("second_class", [](const hw::Conflict& c) { return hw::toString(c.secondClass); })
      .def_readonly("first_length", &hw::Conflict::firstLength)
      .def_readonly("second_length", &hw::Conflict::secondLength)
      .def_readonly("first_width", &hw::Conflict::firstWidth)
      .def_readonly("second_width", &hw::Conflict::secondWidth)
      .def_readonly("open", &hw::Conflict::open, "still going on when the run ended")
      .def("__repr__", [](const hw::Conflict& c) {
        return "<Conflict " + c.first + " / " + c.second + " " + hw::toString(c.type) + " [" + std::to_string(c.begin) +
               ", " + std::to_string(c.end) + "] min_ttc " + std::to_string(c.minTtc) + ">";
      });
  struct ConflictField {
    const char* name;
    double hw::Conflict::*field;
  };
  static constexpr ConflictField kConflictFields[] = {
      {"pet", &hw::Conflict::pet}, {"drac", &hw::Conflict::drac}, {"max_s", &hw::Conflict::maxSpeed},
      {"delta_s", &hw::Conflict::deltaSpeed}, {"dr", &hw::Conflict::dr}, {"max_d", &hw::Conflict::maxD},
      {"max_delta_v", &hw::Conflict::maxDeltaV}, {"first_delta_v", &hw::Conflict::firstDeltaV},
      {"second_delta_v", &hw::Conflict::secondDeltaV}, {"conflict_angle", &hw::Conflict::conflictAngle},
      {"clock_angle", &hw::Conflict::clockAngle}, {"post_crash_speed", &hw::Conflict::postCrashSpeed},
      {"post_crash_heading", &hw::Conflict::postCrashHeading}, {"conflict_x", &hw::Conflict::conflictX},
      {"conflict_y", &hw::Conflict::conflictY}, {"paths_meet_x", &hw::Conflict::pathsMeetX},
      {"paths_meet_y", &hw::Conflict::pathsMeetY}, {"first_x", &hw::Conflict::firstX}, {"first_y", &hw::Conflict::firstY},
      {"second_x", &hw::Conflict::secondX}, {"second_y", &hw::Conflict::secondY},
      {"first_speed", &hw::Conflict::firstSpeed}, {"second_speed", &hw::Conflict::secondSpeed},
      {"first_start_x", &hw::Conflict::firstStartX}, {"first_start_y", &hw::Conflict::firstStartY},
      {"first_end_x", &hw::Conflict::firstEndX}, {"first_end_y", &hw::Conflict::firstEndY},
      {"second_start_x", &hw::Conflict::secondStartX}, {"second_start_y", &hw::Conflict::secondStartY},
      {"second_end_x", &hw::Conflict::secondEndX}, {"second_end_y", &hw::Conflict::secondEndY},
      {"tet", &hw::Conflict::tet}, {"tit", &hw::Conflict::tit}};
  for (const ConflictField& f : kConflictFields)
    conflictClass.def_property_readonly(f.name,
                                        [field = f.field](const hw::Conflict& c) { return conflictNumber(c.*field); });
  // the columns of stsim highway's tables, from the writers' own headers (one source)
  auto columns = [](const std::string& header) {
    py::list out;
    std::size_t from = 0;
    for (std::size_t comma; (comma = header.find(',', from)) != std::string::npos; from = comma + 1)
      out.append(header.substr(from, comma - from));
    out.append(header.substr(from));
    return py::tuple(out);
  };
  m.attr("WARNING_COLUMNS") = columns(hw::warningsCsvHeader());
  m.attr("CONFLICT_COLUMNS") = columns(hw::conflictsCsvHeader());
  m.attr("EVENT_COLUMNS") = columns(hw::eventsCsvHeader());
  // SUMO's link-state letters read once, in sumo_conversion (the coupling's and the replay's reading)
  const auto letter = [](const std::string& s) {
    if (s.size() != 1) throw py::value_error("a SUMO link state is one letter, got '" + s + "'");
    return s[0];
  };
  m.def("gives_way_at", [letter](const std::string& s) { return hw::givesWayAt(letter(s)); }, py::arg("link_state"),
        "Whether a car on a link in this state gives way at its stop line or wait point (g m = s w).");
  m.def("enters_at", [letter](const std::string& s) { return hw::entersAt(letter(s)); }, py::arg("link_state"),
        "Whether a car on a link in this state may enter the junction (G g M m = O o).");

  py::class_<PyAlert>(m, "Alert", "An equipped car's worst current threat at the last step.")
      .def_readonly("vehicle", &PyAlert::vehicle, "index into the last step's vehicles")
      .def_readonly("ego", &PyAlert::ego)
      .def_property_readonly("kind", [](const PyAlert& a) { return hw::toString(a.kind); })
      .def_property_readonly("zone", [](const PyAlert& a) { return hw::toString(a.zone); })
      .def_readonly("ttc", &PyAlert::ttc)
      .def_readonly("safe_time", &PyAlert::safeTime)
      .def_readonly("foe", &PyAlert::foe, "the other vehicle's id (vehicle warnings, as WarningEpisode.foe), else ''")
      .def_readonly("foe_vehicle", &PyAlert::foeVehicle, "the other vehicle's index into the last step's vehicles, else -1")
      .def("__repr__", [](const PyAlert& a) {
        return "<Alert " + a.ego + " " + hw::toString(a.kind) + (a.foe.empty() ? "" : " " + a.foe) + " ttc " +
               std::to_string(a.ttc) + " safe " + std::to_string(a.safeTime) + ">";
      });

  static const std::string monitorDocText = monitorDoc();  // pybind11 keeps the pointer
  py::class_<Monitor>(m, "Monitor", monitorDocText.c_str())
      .def(py::init([](py::object net, py::object lanes, py::kwargs kw) {
             if (!net.is_none() && !lanes.is_none()) throw py::value_error("give net or lanes, not both");
             const hw::RoadGeometry road = lanes.is_none() ? roadOf(net) : roadOfLanes(lanes);
             return std::make_unique<Monitor>(road, configOf(kw));
           }),
           py::arg("net") = py::none(), py::kw_only(), py::arg("lanes") = py::none())
      .def("step", [](Monitor& self, double t, py::handle v) { self.step(t, v, Convention::Ours); }, py::arg("t"),
           py::arg("vehicles"),
           "Every vehicle's state at time t (s, increasing): a list of dicts or a dict of columns with keys\n"
           "id, x, y (centre, m), heading (rad from +x), speed (m/s); optional lateral_speed, acceleration,\n"
           "length, width, mass (default: the class's), decel (the vType's, m/s^2; default unknown), vehicle_class, signals (1 left, 2 right), equipped,\n"
           "lane (its lane id in the net: reported in the warnings' lane column; None: unknown).\n"
           "Vehicles absent have left.")
      .def("step_sumo", [](Monitor& self, double t, py::handle v) { self.step(t, v, Convention::Sumo); }, py::arg("t"),
           py::arg("vehicles"),
           "As step(), in SUMO's conventions: x, y of the front bumper, angle in navigational degrees,\n"
           "signals as SUMO's bits (1 right, 2 left), vehicle_class a SUMO vClass.")
      .def(
          "finish",
          [](Monitor& self, py::object t) { self.finish(t.is_none() ? self.lastTime() : toDouble(t, "t")); },
          py::arg("t") = py::none(), "Closes every open episode at time t (s); None: the last step's time.")
      .def_property_readonly("settings", &Monitor::settings,
                             "Every setting in effect, by its scenario key (stsim highway --settings lists them).")
      .def("take_finished", &Monitor::takeFinished, "Episodes that ended since the last call, in order of ending.")
      .def("take_events", &Monitor::takeEvents,
           "Near misses and unsignalled crossings hindsight found since the last call (HindsightEvent).")
      .def("open_warnings", &Monitor::openWarnings, "Episodes still going on at the last step (WarningEpisode, open).")
      .def("take_conflicts", &Monitor::takeConflicts,
           "Conflicts (conflicts.csv's rows: Conflict) settled since the last call; a conflict waits up to 5 s after\n"
           "its end for its PET, and finish() settles the rest.")
      .def("alerts", &Monitor::alerts, "Each warned car's worst current threat at the last step (Alert).")
      .def_property_readonly("counters", &Monitor::counters, "The monitor's work counters (pair tests, cells, ...), by name.")
      .def_property_readonly("last_time", &Monitor::lastTime, "The last step's time (s).")
      .def_property_readonly("feature_count", &Monitor::featureCount, "curbs, lane markers and hazards")
      .def_property_readonly("cell_count", &Monitor::cellCount);

  py::class_<Fcd>(m, "FcdReader",
                  "FcdReader(path, vtypes=None, net=None): iterates a SUMO FCD trace as (time, [vehicle dict]) in\n"
                  "our conventions (what Monitor.step takes), read as `stsim highway --fcd` reads it; with the\n"
                  "network (a .net.xml), each vehicle's 'lane' (its lane id, None for a lane the network lacks).")
      .def(py::init([](py::object path, py::object vtypes, py::object net) {
             return std::make_unique<Fcd>(toStr(py::str(py::module_::import("os").attr("fspath")(path)), "path"), vtypes, net);
           }),
           py::arg("path"), py::arg("vtypes") = py::none(), py::arg("net") = py::none())
      .def("__iter__", [](py::object self) { return self; })
      .def("__next__", &Fcd::next);
}

