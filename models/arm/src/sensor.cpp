#include <starm/sensor.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace st::arm {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::string fmt(double x) {
  std::ostringstream o;
  o << x;
  return o.str();
}

// Equal values, NaN equal to NaN (a repeated line is repeated; the reading's check names the NaN).
bool same(const std::vector<double>& a, const std::vector<double>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                    [](double x, double y) { return x == y || (std::isnan(x) && std::isnan(y)); });
}

// One line of the trace, at most 64 KiB (a 7-joint reading is some 300 bytes). A NUL byte or a
// longer line is no sensor trace: /dev/zero, a device of NULs without a newline, was read into one
// line for ever (`arm stream /dev/zero` and `trace: /dev/zero` hung and grew).
constexpr std::size_t kMaxLineBytes = 64 * 1024;
bool readLine(std::istream& in, std::string& line, const std::string& where) {
  line.clear();
  std::streambuf* buf = in.rdbuf();
  if (!in || buf == nullptr) return false;
  while (true) {
    const int c = buf->sbumpc();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      return !line.empty();
    }
    if (c == '\n') return true;
    if (c == '\0') throw InputError(where + ": a NUL byte: not a sensor trace (CSV text)");
    if (line.size() >= kMaxLineBytes) throw InputError(where + ": a line longer than 64 KiB: not a sensor trace");
    line.push_back(static_cast<char>(c));
  }
}

}  // namespace

CsvSensor::CsvSensor(const std::string& path, std::vector<std::string> armNames, std::vector<int> dofs)
    : in_(path), path_(path), names_(std::move(armNames)), dofs_(std::move(dofs)), last_(names_.size()) {
  // a directory opens as a stream that reads nothing: it was "0 cycles", exit 0
  if (std::filesystem::is_directory(path)) throw InputError(path + ": is a directory, not a sensor trace");
  if (!in_) throw InputError(path + ": cannot open the sensor trace");
}

bool CsvSensor::next(Reading& r) {
  std::string line;
  while (readLine(in_, line, path_ + ":" + std::to_string(line_ + 1))) {
    ++line_;
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(trim(cell));
    const std::string where = path_ + ":" + std::to_string(line_);
    if (line_ == 1 && !cells.empty() && cells[0] == "t") continue;  // header
    if (cells.size() < 2) throw InputError(where + ": expected t, arm, q..., qdot...");
    auto number = [&](std::size_t i, const char* what) {
      char* end = nullptr;
      const double v = std::strtod(cells[i].c_str(), &end);
      if (cells[i].empty() || *end != '\0') throw InputError(where + ": " + what + " '" + cells[i] + "' is not a number");
      return v;
    };
    r.t = number(0, "time");
    if (!std::isfinite(r.t)) throw InputError(where + ": time is not finite");
    r.arm = -1;
    for (std::size_t a = 0; a < names_.size(); ++a)
      if (names_[a] == cells[1]) r.arm = static_cast<int>(a);
    if (r.arm < 0) throw InputError(where + ": unknown arm '" + cells[1] + "'");
    const int n = dofs_[r.arm];
    if (static_cast<int>(cells.size()) != 2 + 2 * n)
      throw InputError(where + ": arm '" + cells[1] + "' has " + std::to_string(n) + " joints: expected " +
                       std::to_string(n) + " angles and " + std::to_string(n) + " rates, got " +
                       std::to_string(cells.size() - 2) + " values");
    r.q.resize(n);
    r.qdot.resize(n);
    for (int k = 0; k < n; ++k) {
      r.q[k] = number(2 + k, "joint angle");
      r.qdot[k] = number(2 + n + k, "joint rate");
    }
    Last& last = last_[r.arm];
    if (last.seen && last.t == r.t) {
      if (same(last.q, r.q) && same(last.qdot, r.qdot)) continue;  // a repeated line: nothing new
      throw InputError(where + ": arm '" + cells[1] + "' at t = " + cells[0] + " s differs from its reading at line " +
                       std::to_string(last.line) + " (one arm, one time, one state)");
    }
    last.seen = true;
    last.t = r.t;
    last.q = r.q;
    last.qdot = r.qdot;
    last.line = line_;
    r.where = where;
    return true;
  }
  return false;
}

WaypointSensor::WaypointSensor(std::vector<Script> scripts, double period, double duration)
    : scripts_(std::move(scripts)), period_(period), duration_(duration) {}

bool WaypointSensor::next(Reading& r) {
  if (scripts_.empty()) return false;
  if (script_ == scripts_.size()) {
    script_ = 0;
    ++step_;
  }
  const double t = static_cast<double>(step_) * period_;
  if (t > duration_ + 1e-12 * std::max(1.0, duration_)) return false;
  const Script& s = scripts_[script_++];
  const auto& w = s.waypoints;
  const std::size_t n = w.front().q.size();
  r.t = t;
  r.arm = s.arm;
  r.q.assign(n, 0.0);
  r.qdot.assign(n, 0.0);
  r.where = s.where;
  // the piece [w[k], w[k+1]) holding t; before the first / after the last waypoint, at rest
  if (t <= w.front().t) {
    r.q = w.front().q;
    return true;
  }
  if (t >= w.back().t) {
    r.q = w.back().q;
    return true;
  }
  std::size_t k = 0;
  while (w[k + 1].t <= t) ++k;
  const double span = w[k + 1].t - w[k].t;
  const double u = (t - w[k].t) / span;
  for (std::size_t j = 0; j < n; ++j) {
    r.q[j] = w[k].q[j] + u * (w[k + 1].q[j] - w[k].q[j]);
    r.qdot[j] = (w[k + 1].q[j] - w[k].q[j]) / span;
  }
  return true;
}

void validateReading(const ArmModel& m, const Reading& r) {
  if (static_cast<int>(r.q.size()) != m.dof() || static_cast<int>(r.qdot.size()) != m.dof())
    throw InputError(r.where + ": expected " + std::to_string(m.dof()) + " joint angles and rates, got " +
                     std::to_string(r.q.size()) + " and " + std::to_string(r.qdot.size()));
  validateJointState(m, r.q.data(), r.qdot.data(), r.where);
}

void validateJointState(const ArmModel& m, const double* q, const double* qdot, std::string_view where) {
  for (int k = 0; k < m.dof(); ++k) {
    const Joint& j = m.joints[k];
    if (std::isfinite(q[k]) && std::isfinite(qdot[k]) && std::abs(qdot[k]) <= j.maxRate && q[k] >= j.lower && q[k] <= j.upper)
      continue;
    const std::string at = std::string(where) + ": joint " + std::to_string(k + 1);
    if (!std::isfinite(q[k])) throw InputError(at + " angle is not a finite number");
    if (!std::isfinite(qdot[k])) throw InputError(at + " rate is not a finite number");
    if (std::abs(qdot[k]) > j.maxRate)
      throw InputError(at + " rate " + fmt(qdot[k]) + " rad/s is beyond its limit " + fmt(j.maxRate) + " rad/s");
    throw InputError(at + " angle " + fmt(q[k]) + " rad is beyond its limits [" + fmt(j.lower) + ", " + fmt(j.upper) + "]");
  }
}

}  // namespace st::arm
