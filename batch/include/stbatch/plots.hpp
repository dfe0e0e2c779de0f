#pragma once
#include <filesystem>
#include <string>

namespace st::batch {

// Plots and report.md via Debian's python3-matplotlib; returns false (with the reason) if unavailable.
bool writePlots(const std::filesystem::path& outDir, std::string& why);

}  // namespace st::batch
