#pragma once
// Shared by the fuzz targets: readers that take a path get the input as a file of their own.
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>

namespace st::fuzz {

// Writes the input to a per-process file with the given extension; returns its path.
inline std::string asFile(const std::uint8_t* data, std::size_t size, const char* ext) {
  const std::string path = "/tmp/stsim_fuzz_" + std::to_string(::getpid()) + ext;
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                                static_cast<std::streamsize>(size));
  return path;
}

}  // namespace st::fuzz
