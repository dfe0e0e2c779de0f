#pragma once
// Files stsim ships beside its executable (the plot scripts). Installed, they are in
// <prefix>/share/stsim and the executable in <prefix>/bin; a build run from the tree has them in
// the source tree only. One lookup, so every caller finds them the same way.
#include <filesystem>
#include <string_view>

namespace st::io {

// <directory of the running executable>/../share/stsim/<name> if that file exists, else
// `inSourceTree` (which may not exist either: the caller says what is missing).
std::filesystem::path dataFile(std::string_view name, const std::filesystem::path& inSourceTree);

// The same lookup from a given executable path (tests; dataFile uses /proc/self/exe).
std::filesystem::path dataFile(std::string_view name, const std::filesystem::path& inSourceTree,
                               const std::filesystem::path& executable);

}  // namespace st::io
