#pragma once
// File helpers the batch's parts share: whole files read, a run's folder, the tables' cells.
// Files are written through st::io (io::writeFileAtomically), as every command's are.
#include <filesystem>
#include <string>
#include <vector>

#include <stbatch/experiment.hpp>

namespace st::batch::detail {

// The file's bytes (bounded by st::io); throws std::runtime_error naming the file when it cannot
// be read (missing, not a file, too long).
std::string readFile(const std::filesystem::path& p);
// The last non-blank line of a log, cut at 300 characters (a failed run's error).
std::string lastLine(const std::string& text);
// lastLine of the log at p, or why it cannot be read (naming it): the log explains a failure,
// and one that cannot be read says so rather than nothing.
std::string lastLogLine(const std::filesystem::path& p);
// A run's CSV file (conflicts.csv, exposure.csv) read whole and checked: a header line and rows
// of as many fields, every line ended. Anything else is a std::runtime_error of one line naming
// the file and, where there is one, the line: "F: no such file", "F:1: empty, no header line",
// "F:7: 3 fields, the header has 5", "F:9: the last line is cut short (no line end)". A run that
// was done wrote its files whole, so a file that is not is an error, never skipped.
struct CsvTable {
  std::filesystem::path file;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  // rows[i] is the file's line i + 2

  // the header's index of `name`, or -1
  int find(const std::string& name) const;
  // find, and throws "F: no NAME column (why)" when there is none
  std::size_t column(const std::string& name, const std::string& why) const;
  // The cell as a number: an empty cell (a value that does not apply) is NaN; "inf" and "nan"
  // are numbers; other text throws "F:L: COLUMN: \"TEXT\" is not a number".
  double number(std::size_t row, std::size_t col) const;
  // number, and an empty cell is an error too ("F:L: COLUMN: empty")
  double required(std::size_t row, std::size_t col) const;
};
CsvTable readCsvTable(const std::filesystem::path& file);

// Cells of the tables: line breaks become spaces, so every row is one line of the file.
std::string csvField(const std::string& s);
std::string number(double v);
inline std::filesystem::path runDir(const std::filesystem::path& outDir, const RunSpec& r) {
  return outDir / "runs" / r.id;
}

}  // namespace st::batch::detail
