#include "files.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include <stio/format.hpp>
#include <stio/input.hpp>

namespace st::batch::detail {

namespace fs = std::filesystem;

void writeFileAtomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(tmp.string() + ": cannot write");
    out << text;
    if (!out.flush()) throw std::runtime_error(tmp.string() + ": write failed");
  }
  fs::rename(tmp, path);
}

std::string readFile(const fs::path& p) {
  // bounded: a run's log or a record is kilobytes; whatever else sits there is not read whole
  std::string text, error;
  io::readFile(p, text, error);
  return text;
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
