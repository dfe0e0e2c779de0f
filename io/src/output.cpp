#include <stio/output.hpp>

#include <stdexcept>

namespace st::io {

CsvRowWriter::CsvRowWriter(const std::filesystem::path& path, const std::string& header) : path_(path), out_(path) {
  if (!out_) throw std::runtime_error("cannot write " + path.string());
  if (!header.empty()) out_ << header << '\n';
  flush();
}

void CsvRowWriter::check() {
  if (!out_) throw std::runtime_error("write failed: " + path_.string());
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
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write " + path.string());
  out << text;
  out.flush();
  if (!out) throw std::runtime_error("write failed: " + path.string());
}

}  // namespace st::io
