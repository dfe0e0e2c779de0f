#include "settings.hpp"

#include <string>

#include <sthighway/settings.hpp>

#include "values.hpp"

namespace stpy {

namespace hw = st::highway;

namespace {

// Every key of sthighway/settings.hpp, by its YAML name ("safe_time.vehicle_reaction"), its flat
// spelling (safe_time_vehicle_reaction=1.0) or nested dicts (safe_time={"vehicle_reaction": 1.0}).
// The table's type decides what a value must be (TypeError); the table checks it (ValueError),
// in the words every front end uses.
void setFromPython(hw::MonitorConfig& cfg, const hw::Setting& s, py::handle value) {
  const std::string what = std::string("setting '") + s.key + "'";
  hw::SettingValue v;
  switch (s.type) {
    case hw::SettingType::Number:
    case hw::SettingType::Integer:
      v = toDouble(value, what);  // an int or a float (a whole number for an Integer: the table checks)
      break;
    case hw::SettingType::Boolean: v = toBool(value, what); break;
    case hw::SettingType::Choice: v = toStr(value, what); break;
  }
  try {
    hw::applySetting(cfg, s, v);
  } catch (const hw::SettingError& e) {
    throw py::value_error("setting '" + e.key() + "' " + e.problem());
  }
}

void setNested(hw::MonitorConfig& cfg, const std::string& name, py::handle value) {
  if (const hw::Setting* s = hw::findSetting(name)) return setFromPython(cfg, *s, value);
  bool section = false;
  for (const hw::Setting& s : hw::monitorSettings()) section = section || std::string(s.key).rfind(name + ".", 0) == 0;
  if (section && py::isinstance<py::dict>(value)) {
    for (auto [k, v] : py::reinterpret_borrow<py::dict>(value)) setNested(cfg, name + "." + toStr(k, "a key of setting '" + name + "'"), v);
    return;
  }
  if (section) {
    std::string msg = "setting '";
    msg.append(name).append("' must be a dict of its keys, got ").append(typeName(value));
    throw py::type_error(msg);
  }
  std::string msg = "Monitor() got an unknown setting '";
  msg.append(name).append("' (known:");
  for (const hw::Setting& s : hw::monitorSettings()) msg.append(" ").append(s.key);
  msg.append("; in a keyword '.' is written '_')");
  throw py::type_error(msg);
}

}  // namespace

hw::MonitorConfig configOf(const py::kwargs& kw) {
  hw::MonitorConfig cfg;
  for (auto [name, value] : kw) setNested(cfg, py::cast<std::string>(name), value);
  try {
    hw::checkSettings(cfg);
  } catch (const hw::SettingError& e) {
    throw py::value_error("setting '" + e.key() + "' " + e.problem());
  }
  return cfg;
}

std::string monitorDoc() {
  std::string doc =
      "Monitor(net=None, *, lanes=None, **settings): smart-car warnings, one step() per tick.\n"
      "net: a SUMO .net.xml (lane shapes and widths) or None (no road: car-car only);\n"
      "lanes: the same as a list of dicts {id, edge, index, shape, width, internal, length}.\n"
      "settings: the scenario's keys (docs/settings.md), nested as in the YAML\n"
      "(safe_time={'vehicle_reaction': 1.2}) or flat with '_' for '.' (safe_time_vehicle_reaction=1.2):\n";
  const hw::MonitorConfig defaults;
  for (const hw::Setting& s : hw::monitorSettings()) {
    doc.append("  ").append(s.key).append(" = ").append(hw::settingText(s.get(defaults)));
    doc.append("  (").append(hw::valuesText(s)).append("): ").append(s.doc).append("\n");
  }
  return doc;
}

}  // namespace stpy
