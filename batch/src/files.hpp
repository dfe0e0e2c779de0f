#pragma once
// File helpers the batch's parts share: whole files written atomically, a run's folder, the
// tables' cells.
#include <filesystem>
#include <string>

#include <stbatch/experiment.hpp>

namespace st::batch::detail {

// Writes path.tmp and renames it over path: a reader sees the old file or the whole new one.
void writeFileAtomically(const std::filesystem::path& path, const std::string& text);
// The file's bytes (bounded by st::io), "" when it cannot be read (missing, not a file, too long).
std::string readFile(const std::filesystem::path& p);
// The last non-blank line of a log, cut at 300 characters (a failed run's error).
std::string lastLine(const std::string& text);
// Cells of the tables: line breaks become spaces, so every row is one line of the file.
std::string csvField(const std::string& s);
std::string number(double v);
inline std::filesystem::path runDir(const std::filesystem::path& outDir, const RunSpec& r) {
  return outDir / "runs" / r.id;
}

}  // namespace st::batch::detail
