#include <stio/output.hpp>

#include <stdexcept>

namespace st::io {

CsvRowWriter::CsvRowWriter(const std::filesystem::path& path, const std::string& header) : path_(path), out_(path) {
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
  trimToLastLine(path_);
  throw std::runtime_error("write failed: " + path_.string());
}

CsvRowWriter::~CsvRowWriter() {
  if (!out_.is_open()) return;
  out_.flush();
  if (out_) return;
  // the buffer went out in pieces: the cut row goes (a destructor does not throw)
  out_.close();
  trimToLastLine(path_);
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

void writeRowsFile(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write " + path.string());
  write(out);
  out.flush();
  if (!out) {
    // what is still buffered cannot reach the file either; then the cut row goes
    out.close();
    trimToLastLine(path);
    throw std::runtime_error("write failed: " + path.string());
  }
}

void writeTextFile(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write " + path.string());
  write(out);
  out.flush();
  if (!out) {
    // half a JSON document is no document: none is left rather than a cut one
    out.close();
    std::error_code ec;
    if (std::filesystem::is_regular_file(path, ec)) std::filesystem::remove(path, ec);
    throw std::runtime_error("write failed: " + path.string());
  }
}

}  // namespace st::io
