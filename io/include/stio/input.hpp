#pragma once
// Reading a whole file (a scenario, an experiment, a page, a SUMO configuration) with its size
// bounded: /dev/zero, a FIFO or a binary given by mistake is one line naming the file, not a read
// that never ends or a std::bad_alloc naming nothing. Every whole-file read of stsim goes through
// here.
//
// What may be read: a regular file, or a device (read up to the bound; /dev/zero stops at its
// first NUL in readTextFile). Refused with one line: no such file, a directory, a FIFO (opening one
// waits for a writer for ever), a socket.
#include <cstddef>
#include <filesystem>
#include <string>

namespace st::io {

constexpr std::size_t kMaxTextFile = 64u << 20;  // bytes; a scenario is kilobytes

// "" when `file` is something readFile reads, else why not, naming it: "F: no such file",
// "F: is a directory, not a file", "F: is a FIFO, not a file", "F: is a socket, not a file".
// For readers that stream a file themselves (the XML scanner), before they open it.
std::string notReadableReason(const std::filesystem::path& file);

// The file's bytes, or false with `error` naming the file: notReadableReason's cases, unreadable,
// or longer than maxBytes ("F: longer than N MiB").
bool readFile(const std::filesystem::path& file, std::string& text, std::string& error,
              std::size_t maxBytes = kMaxTextFile);

// readFile, and the bytes must be text: a NUL byte (no text file has one) is refused too.
bool readTextFile(const std::filesystem::path& file, std::string& text, std::string& error,
                  std::size_t maxBytes = kMaxTextFile);

}  // namespace st::io
