#pragma once
// Output files that say when they fail. A full disk, a quota or a closed pipe is an exception
// naming the file ("write failed: PATH"), never a run that exits 0 with its results cut short.
// One writer for every command (pool, arm, highway, batch, the arm service and its client), so a
// file is checked the same way wherever it is written.
//
// A test seam: with STSIM_TEST_FULL_FILE=NAME in the environment, every output whose file name is
// NAME is opened as /dev/full instead, so a test can fail each file of a command in turn, even
// one in a folder the command empties or creates first (tests/app/full_disk_files.sh).
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <ostream>
#include <string>
#include <string_view>

namespace st::io {

// A CSV (or any line-based) file written row by row and flushed as the run goes: a run that
// stops early leaves whole rows. Every row and flush checks the stream: std::ofstream only sees
// a failed write when its buffer goes to the file, so the check after each is what catches it;
// the file is then trimmed back to its last whole row.
class CsvRowWriter {
 public:
  // Creates (truncates) the file and writes the header line (none if empty); throws
  // std::runtime_error naming the path.
  CsvRowWriter(const std::filesystem::path& path, const std::string& header);
  // Flushes what is buffered; a flush that fails (the run is ending on another file's error, the
  // disk full) trims the file back to its last whole row, without throwing.
  ~CsvRowWriter();
  CsvRowWriter(const CsvRowWriter&) = delete;
  CsvRowWriter& operator=(const CsvRowWriter&) = delete;
  CsvRowWriter(CsvRowWriter&&) = default;
  CsvRowWriter& operator=(CsvRowWriter&&) = default;
  void row(std::string_view line);  // one line, '\n' added
  void flush();
  std::uint64_t rows() const { return rows_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  void check();
  std::filesystem::path path_;
  std::ofstream out_;
  std::uint64_t rows_ = 0;
};

// The whole file at once (summary.json): written, flushed and checked; throws naming the path
// and removes what a failed write left (never a cut document).
void writeTextFile(const std::filesystem::path& path, std::string_view text);
// The same, the document streamed by WRITE (an SVG, an HTML page): removed if a write fails.
void writeTextFile(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

// The whole file, replacing the one there only once it is written whole: written to PATH.tmp,
// flushed and checked, then renamed over PATH. On a failed write the temporary file is removed,
// PATH keeps what it held, and the exception says "write failed: PATH". When PATH is not a regular
// file (a symlink, /dev/full, a pipe) the text goes to it in place, checked as writeTextFile does.
void writeFileAtomically(const std::filesystem::path& path, std::string_view text);

// FROM's bytes copied to TO (a batch merge's run folders), checked as writeTextFile: throws
// "cannot read FROM" or "write failed: TO", and removes a cut copy.
void copyFile(const std::filesystem::path& from, const std::filesystem::path& to);

// A line-based file (a CSV) written in one go by WRITE, which may stop early once the stream
// fails: checked as CsvRowWriter is, and on a failed write trimmed back to its last whole row;
// throws "write failed: PATH".
void writeRowsFile(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

}  // namespace st::io
