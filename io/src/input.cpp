#include <stio/input.hpp>

#include <cstring>
#include <fstream>

namespace st::io {

namespace fs = std::filesystem;

bool readTextFile(const fs::path& file, std::string& text, std::string& error, std::size_t maxBytes) {
  text.clear();
  error.clear();
  std::error_code ec;
  const auto status = fs::status(file, ec);
  if (!fs::exists(status)) {
    error = file.string() + ": no such file";
    return false;
  }
  if (fs::is_directory(status)) {
    error = file.string() + ": is a directory, not a text file";
    return false;
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    error = file.string() + ": cannot read the file";
    return false;
  }
  // in chunks, checked as they come: a device that never ends is stopped at the first NUL or the bound
  char buf[1 << 16];
  while (in) {
    in.read(buf, sizeof buf);
    const auto n = static_cast<std::size_t>(in.gcount());
    if (std::memchr(buf, '\0', n) != nullptr) {
      error = file.string() + ": holds a NUL byte: not a text file";
      return false;
    }
    if (text.size() + n > maxBytes) {
      error = file.string() + ": longer than " + std::to_string(maxBytes >> 20) + " MiB: not a text file of stsim's";
      return false;
    }
    text.append(buf, n);
  }
  if (in.bad()) {
    error = file.string() + ": cannot read the file";
    return false;
  }
  return true;
}

}  // namespace st::io
