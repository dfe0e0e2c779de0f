#pragma once
// Reading a whole text file (a scenario, an experiment) with its size bounded and its bytes
// checked: /dev/zero or a binary given by mistake is one line naming the file, not a
// std::bad_alloc naming nothing.
#include <cstddef>
#include <filesystem>
#include <string>

namespace st::io {

constexpr std::size_t kMaxTextFile = 64u << 20;  // bytes; a scenario is kilobytes

// The file's text, or false with `error` naming the file: no such file, a directory, unreadable,
// longer than maxBytes, or holding a NUL byte (no text file does).
bool readTextFile(const std::filesystem::path& file, std::string& text, std::string& error,
                  std::size_t maxBytes = kMaxTextFile);

}  // namespace st::io
