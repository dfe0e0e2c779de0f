#include "road.hpp"

#include <string>

#include <sthighway/sumo_files.hpp>

#include "values.hpp"

namespace stpy {

namespace hw = st::highway;

hw::RoadGeometry roadOf(py::handle net) {
  if (net.is_none()) return {};
  if (!PyUnicode_Check(net.ptr()) && !py::isinstance(net, py::module_::import("os").attr("PathLike")))
    throw py::type_error("net must be a path to a .net.xml or None, got " + typeName(net));
  const std::string path = py::str(py::module_::import("os").attr("fspath")(net));
  return hw::readSumoNet(path);
}

hw::RoadGeometry roadOfLanes(py::handle lanes) {
  hw::RoadGeometry road;
  if (!py::isinstance<py::sequence>(lanes)) throw py::type_error("lanes must be a list of dicts, got " + typeName(lanes));
  std::size_t i = 0;
  for (py::handle item : lanes) {
    const std::string where = "lane " + std::to_string(i++);
    if (!py::isinstance<py::dict>(item)) throw py::type_error(where + " must be a dict, got " + typeName(item));
    const auto d = py::reinterpret_borrow<py::dict>(item);
    hw::Lane l;
    for (auto [k, v] : d) {
      const std::string key = py::isinstance<py::str>(k) ? py::cast<std::string>(k) : std::string(py::repr(k));
      const std::string what = where + ": '" + key + "'";
      if (key == "id") l.id = toStr(v, what);
      else if (key == "edge") l.edge = toStr(v, what);
      else if (key == "index") l.index = static_cast<int>(toInt(v, what));
      else if (key == "width") l.width = toFinite(v, what);
      else if (key == "internal") l.internal = toBool(v, what);
      else if (key == "length") {
        l.length = toFinite(v, what);
        if (l.length < 0.0) throw py::value_error(what + ": must not be negative");
      }
      else if (key == "shape") {
        for (py::handle p : v) {
          const auto xy = py::reinterpret_borrow<py::sequence>(p);
          if (py::len(xy) != 2) throw py::value_error(what + ": points must be (x, y)");
          l.shape.emplace_back(toFinite(xy[0], what), toFinite(xy[1], what));
        }
      } else throw py::value_error(what + ": unknown key (known: id, edge, index, shape, width, internal, length)");
    }
    road.lanes.push_back(std::move(l));
  }
  return road;
}


}  // namespace stpy
