#pragma once
// File helpers the batch's parts share: whole files read, a run's folder, the tables' cells.
// Files are written through st::io (io::writeFileAtomically), as every command's are.
#include <filesystem>
#include <string>

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
// Cells of the tables: line breaks become spaces, so every row is one line of the file.
std::string csvField(const std::string& s);
std::string number(double v);
inline std::filesystem::path runDir(const std::filesystem::path& outDir, const RunSpec& r) {
  return outDir / "runs" / r.id;
}

}  // namespace st::batch::detail
