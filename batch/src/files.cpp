#include "files.hpp"

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

std::string csvField(const std::string& s) { return io::csvField(io::oneLine(s)); }

std::string number(double v) { return io::number(v, 12); }

}  // namespace st::batch::detail
