#pragma once
// Monitor settings from Python keywords: the scenario's keys (sthighway/settings.hpp), nested
// dicts or flat with '_' for '.'.
#include <pybind11/pybind11.h>

#include <sthighway/monitor.hpp>

namespace stpy {

// A wrong type is a TypeError, a value the table refuses a ValueError, in the table's words.
st::highway::MonitorConfig configOf(const pybind11::kwargs& kw);

// Monitor's docstring: its signature and every setting from the table, with its values and default.
std::string monitorDoc();

}  // namespace stpy
