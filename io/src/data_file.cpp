#include <stio/data_file.hpp>

#include <system_error>

namespace st::io {

namespace fs = std::filesystem;

fs::path dataFile(std::string_view name, const fs::path& inSourceTree, const fs::path& executable) {
  std::error_code ec;
  // the installed layout: bin/stsim beside share/stsim (GNUInstallDirs' defaults, as installed)
  const fs::path installed = executable.parent_path().parent_path() / "share" / "stsim" / name;
  if (!executable.empty() && fs::is_regular_file(installed, ec)) return installed;
  return inSourceTree;
}

fs::path dataFile(std::string_view name, const fs::path& inSourceTree) {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);  // Linux: the running executable
  return dataFile(name, inSourceTree, ec ? fs::path() : self);
}

}  // namespace st::io
