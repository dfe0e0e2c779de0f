#include <stio/output.hpp>

#include <cstdlib>
#include <stdexcept>

namespace st::io {

namespace {

// Where an output's bytes go: the file itself, or /dev/full when the test seam names it
// (STSIM_TEST_FULL_FILE, output.hpp). Errors still name the file the command meant to write.
bool onFullDevice(const std::filesystem::path& path) {
  const char* full = std::getenv("STSIM_TEST_FULL_FILE");
  return full != nullptr && *full != '\0' && path.filename() == full;
}
std::filesystem::path target(const std::filesystem::path& path) {
  return onFullDevice(path) ? std::filesystem::path("/dev/full") : path;
}

}  // namespace

CsvRowWriter::CsvRowWriter(const std::filesystem::path& path, const std::string& header)
    : path_(path), out_(target(path)) {
  if (!out_) throw std::runtime_error("cannot write " + path.string());
  if (!header.empty()) out_ << header << '\n';
  flush();
}

namespace {

// A file cut by a failed write (a buffer goes out in pieces) is trimmed back to its last whole
// line: what is left is complete rows, never half of one.
void trimToLastLine(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return;  // /dev/full, a pipe: nothing to trim
  std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size == 0) return;
  std::ifstream in(path, std::ios::binary);
  char buf[4096];
  std::uintmax_t keep = 0;
  for (std::uintmax_t end = size; end > 0 && in;) {
    const std::uintmax_t begin = end > sizeof buf ? end - sizeof buf : 0;
    in.seekg(static_cast<std::streamoff>(begin));
    in.read(buf, static_cast<std::streamsize>(end - begin));
    for (std::uintmax_t i = end - begin; i > 0; --i)
      if (buf[i - 1] == '\n') {
        keep = begin + i;
        end = 0;
        break;
      }
    if (end != 0) end = begin;
  }
  if (keep < size) std::filesystem::resize_file(path, keep, ec);
}

}  // namespace

void CsvRowWriter::check() {
  if (out_) return;
  // what is still buffered cannot reach the file either; then the cut row goes
  out_.close();
  trimToLastLine(target(path_));
  throw std::runtime_error("write failed: " + path_.string());
}

CsvRowWriter::~CsvRowWriter() {
  if (!out_.is_open()) return;
  out_.flush();
  if (out_) return;
  // the buffer went out in pieces: the cut row goes (a destructor does not throw)
  out_.close();
  trimToLastLine(target(path_));
}

void CsvRowWriter::row(std::string_view line) {
  out_ << line << '\n';
  ++rows_;
  check();
}

void CsvRowWriter::flush() {
  out_.flush();
  check();
}

void writeTextFile(const std::filesystem::path& path, std::string_view text) {
  writeTextFile(path, [&](std::ostream& os) { os << text; });
}

namespace {

// Half a JSON document is no document: none is left rather than a cut one.
void removeCutFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec)) std::filesystem::remove(path, ec);
}

// Writes `path` through `write` and flushes it. On a failed write what is still buffered cannot
// reach the file either: the stream is closed, `cut` handed what the file holds (to trim or
// remove it), and the failure thrown naming `path`.
void writeChecked(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write,
                  void (*cut)(const std::filesystem::path&)) {
  const std::filesystem::path to = target(path);
  std::ofstream out(to, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write " + path.string());
  write(out);
  out.flush();
  if (!out) {
    out.close();
    cut(to);
    throw std::runtime_error("write failed: " + path.string());
  }
}

}  // namespace

void writeRowsFile(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  writeChecked(path, write, trimToLastLine);  // the cut row goes
}

void writeTextFile(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  writeChecked(path, write, removeCutFile);
}

void copyFile(const std::filesystem::path& from, const std::filesystem::path& to) {
  std::ifstream in(from, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + from.string());
  writeTextFile(to, [&](std::ostream& out) {
    char buf[1 << 16];
    while (in.read(buf, sizeof buf) || in.gcount() > 0) {
      out.write(buf, in.gcount());
      if (!out) return;  // writeTextFile names the file
    }
    if (in.bad()) throw std::runtime_error("cannot read " + from.string());
  });
}

void writeFileAtomically(const std::filesystem::path& path, std::string_view text) {
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::symlink_status(path, ec);
  // a symlink or a device is written through, not replaced by a regular file beside it
  if (std::filesystem::exists(st) && !std::filesystem::is_regular_file(st)) {
    writeTextFile(path, text);
    return;
  }
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  {
    // the seam fails the temporary file of PATH, the one that holds PATH's bytes
    std::ofstream out(onFullDevice(path) ? target(path) : tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write " + path.string());
    out << text;
    out.flush();
    if (!out) {
      out.close();
      std::filesystem::remove(tmp, ec);
      throw std::runtime_error("write failed: " + path.string());
    }
  }
  if (onFullDevice(path)) return;  // unreachable: /dev/full fails every write
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    const std::string why = ec.message();
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error("cannot write " + path.string() + ": " + why);
  }
}

}  // namespace st::io
