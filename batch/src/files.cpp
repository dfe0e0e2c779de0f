#include "files.hpp"

#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <stio/format.hpp>
#include <stio/input.hpp>

namespace st::batch::detail {

namespace fs = std::filesystem;

std::string readFile(const fs::path& p) {
  // bounded: a run's log or a record is kilobytes; whatever else sits there is not read whole
  std::string text, error;
  if (!io::readFile(p, text, error)) throw std::runtime_error(error);
  return text;
}

std::string lastLogLine(const fs::path& p) {
  std::string text, error;
  if (!io::readFile(p, text, error)) return "(" + error + ")";
  return lastLine(text);
}

std::string lastLine(const std::string& text) {
  std::istringstream in(text);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty() && line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  if (last.size() > 300) last = last.substr(0, 300) + "...";
  return last;
}

CsvTable readCsvTable(const fs::path& file) {
  CsvTable t;
  t.file = file;
  // bounded: a run's conflicts are megabytes at most
  std::string text, error;
  if (!io::readTextFile(file, text, error, std::size_t{256} << 20)) throw std::runtime_error(error);
  const std::string name = file.string();
  if (text.empty()) throw std::runtime_error(name + ":1: empty, no header line");
  std::size_t line = 0, at = 0;
  while (at < text.size()) {
    ++line;
    const std::size_t end = text.find('\n', at);
    if (end == std::string::npos)
      throw std::runtime_error(name + ":" + std::to_string(line) + ": the last line is cut short (no line end)");
    std::vector<std::string> fields = io::csvFields(std::string_view(text).substr(at, end - at));
    at = end + 1;
    if (line == 1) {
      t.header = std::move(fields);
      continue;
    }
    if (fields.size() != t.header.size())
      throw std::runtime_error(name + ":" + std::to_string(line) + ": " + std::to_string(fields.size()) +
                               " fields, the header has " + std::to_string(t.header.size()));
    t.rows.push_back(std::move(fields));
  }
  return t;
}

int CsvTable::find(const std::string& name) const {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return static_cast<int>(i);
  return -1;
}

std::size_t CsvTable::column(const std::string& name, const std::string& why) const {
  const int at = find(name);
  if (at < 0) throw std::runtime_error(file.string() + ": no " + name + " column (" + why + ")");
  return static_cast<std::size_t>(at);
}

double CsvTable::number(std::size_t row, std::size_t col) const {
  const std::string& cell = rows[row][col];
  if (cell.empty()) return std::numeric_limits<double>::quiet_NaN();
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  if (end != cell.c_str() + cell.size())
    throw std::runtime_error(file.string() + ":" + std::to_string(row + 2) + ": " + header[col] + ": " +
                             io::jsonString(cell) + " is not a number");
  return v;
}

double CsvTable::required(std::size_t row, std::size_t col) const {
  if (rows[row][col].empty())
    throw std::runtime_error(file.string() + ":" + std::to_string(row + 2) + ": " + header[col] + ": empty");
  return number(row, col);
}

std::string csvField(const std::string& s) { return io::csvField(io::oneLine(s)); }

std::string number(double v) { return io::number(v, 12); }

}  // namespace st::batch::detail
