#pragma once
// Checked conversions of Python values: a wrong type is a TypeError naming what it is for.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <string>

namespace stpy {

namespace py = pybind11;

inline std::string typeName(py::handle h) { return py::str(py::type::handle_of(h).attr("__name__")); }

// A real number: int or float (NumPy scalars too), not bool, not str.
inline double toDouble(py::handle h, const std::string& what) {
  if (PyBool_Check(h.ptr()) || PyUnicode_Check(h.ptr()) || PyBytes_Check(h.ptr()) || !PyNumber_Check(h.ptr()) ||
      PyComplex_Check(h.ptr()))
    throw py::type_error(what + " must be a number, got " + typeName(h));
  const double x = PyFloat_AsDouble(h.ptr());
  if (x == -1.0 && PyErr_Occurred()) throw py::error_already_set();
  return x;
}

inline double toFinite(py::handle h, const std::string& what) {
  const double x = toDouble(h, what);
  if (!std::isfinite(x)) throw py::value_error(what + " must be finite, got " + std::to_string(x));
  return x;
}

inline long toInt(py::handle h, const std::string& what) {
  if (PyBool_Check(h.ptr()) || !PyIndex_Check(h.ptr())) throw py::type_error(what + " must be an integer, got " + typeName(h));
  return py::cast<long>(py::reinterpret_borrow<py::object>(h));
}

inline bool toBool(py::handle h, const std::string& what) {
  if (PyBool_Check(h.ptr())) return h.ptr() == Py_True;
  if (py::isinstance(h, py::module_::import("numpy").attr("bool_"))) return py::cast<bool>(h);
  if (PyIndex_Check(h.ptr()) && !PyFloat_Check(h.ptr())) {
    const long v = toInt(h, what);
    if (v == 0 || v == 1) return v == 1;
  }
  throw py::type_error(what + " must be a bool, got " + typeName(h));
}

inline std::string toStr(py::handle h, const std::string& what) {
  if (!PyUnicode_Check(h.ptr()) && !py::isinstance(h, py::module_::import("numpy").attr("str_")))
    throw py::type_error(what + " must be a str, got " + typeName(h));
  return py::cast<std::string>(h);
}

}  // namespace stpy
