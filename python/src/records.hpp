#pragma once
// What Python reads of the results: a warning's hindsight and conflict fields as warnings.csv
// writes them (models/highway/src/report.cpp, warningCsvRow), and an FCD trace frame by frame.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>

#include <sthighway/monitor.hpp>
#include <sthighway/sumo_files.hpp>

#include "road.hpp"
#include "states.hpp"
#include "values.hpp"

namespace stpy {

// a warning's hindsight and conflict fields, as warnings.csv writes them -----------------
// (models/highway/src/report.cpp, warningCsvRow): None where its cell is empty

inline py::object judgedNumber(const hw::Warning& w, double x) {
  return w.verdict != hw::Verdict::Unjudged && std::isfinite(x) ? py::object(py::float_(x)) : py::object(py::none());
}
inline py::object vehicleJudged(const hw::Warning& w, double x) {
  return w.kind == hw::WarningKind::Vehicle ? judgedNumber(w, x) : py::object(py::none());
}
inline py::object roadJudged(const hw::Warning& w, bool b) {
  return w.verdict != hw::Verdict::Unjudged && w.kind != hw::WarningKind::Vehicle ? py::object(py::bool_(b))
                                                                                 : py::object(py::none());
}
// a conflict column: NaN (does not apply) is None; an infinite DRAC stays inf
inline py::object conflictNumber(double x) { return std::isnan(x) ? py::object(py::none()) : py::object(py::float_(x)); }

class Fcd {
 public:
  // with a net, each vehicle's lane attribute is read against it (as `stsim highway --fcd --net`)
  Fcd(const std::string& path, py::handle vtypes, py::handle net)
      : road_(net.is_none() ? std::nullopt : std::optional<hw::RoadGeometry>(roadOf(net))),
        reader_(path, typesOf(vtypes), {}, road_ ? &*road_ : nullptr) {}
  py::object next() {
    hw::FcdFrame frame;
    bool more = false;
    {
      py::gil_scoped_release free;
      more = reader_.next(frame);
    }
    if (!more) throw py::stop_iteration();
    py::list vs;
    for (const auto& v : frame.vehicles) vs.append(stateDict(v, road_ ? &*road_ : nullptr));
    return py::make_tuple(frame.time, vs);
  }

 private:
  static hw::VehicleTypes typesOf(py::handle vtypes) {
    if (vtypes.is_none()) return {};
    return hw::readSumoVehicleTypes(toStr(py::str(py::module_::import("os").attr("fspath")(vtypes)), "vtypes"));
  }
  std::optional<hw::RoadGeometry> road_;  // before reader_, which keeps a pointer to it
  hw::FcdReader reader_;
};

}  // namespace stpy
