#include <stio/input.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace st::io {

namespace fs = std::filesystem;

namespace {

// why a file of this mode is not read ("" when it is)
std::string modeReason(const fs::path& file, mode_t mode) {
  if (S_ISDIR(mode)) return file.string() + ": is a directory, not a file";
  if (S_ISFIFO(mode)) return file.string() + ": is a FIFO, not a file";
  if (S_ISSOCK(mode)) return file.string() + ": is a socket, not a file";
  return "";
}

// the size bound in words: MiB when it is a whole number of them, else bytes
std::string bound(std::size_t maxBytes) {
  if (maxBytes >= (1u << 20) && maxBytes % (1u << 20) == 0) return std::to_string(maxBytes >> 20) + " MiB";
  return std::to_string(maxBytes) + " bytes";
}

bool read(const fs::path& file, std::string& text, std::string& error, std::size_t maxBytes, bool textOnly) {
  text.clear();
  error.clear();
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) {
    error = file.string() + (errno == ENOENT || errno == ENOTDIR ? ": no such file" : ": cannot read the file: " +
                                                                          std::string(std::strerror(errno)));
    return false;
  }
  if (error = modeReason(file, st.st_mode); !error.empty()) return false;
  // O_NONBLOCK: a FIFO put in the file's place since the stat opens at once instead of waiting for
  // a writer, and is refused by the fstat below
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) {
    error = file.string() + ": cannot read the file: " + std::strerror(errno);
    return false;
  }
  if (::fstat(fd, &st) != 0 || !(error = modeReason(file, st.st_mode)).empty()) {
    if (error.empty()) error = file.string() + ": cannot read the file";
    ::close(fd);
    return false;
  }
  // in chunks, checked as they come: a device that never ends is stopped at the first NUL or the bound
  char buf[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      error = file.string() + ": cannot read the file: " + std::strerror(errno);
      break;
    }
    if (n == 0) break;
    const auto len = static_cast<std::size_t>(n);
    if (textOnly && std::memchr(buf, '\0', len) != nullptr) {
      error = file.string() + ": holds a NUL byte: not a text file";
      break;
    }
    if (text.size() + len > maxBytes) {
      error = file.string() + ": longer than " + bound(maxBytes) + ": not a file of stsim's";
      break;
    }
    text.append(buf, len);
  }
  ::close(fd);
  if (!error.empty()) text.clear();
  return error.empty();
}

}  // namespace

std::string notReadableReason(const fs::path& file) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) return file.string() + ": no such file";
  return modeReason(file, st.st_mode);
}

bool readFile(const fs::path& file, std::string& text, std::string& error, std::size_t maxBytes) {
  return read(file, text, error, maxBytes, false);
}

bool readTextFile(const fs::path& file, std::string& text, std::string& error, std::size_t maxBytes) {
  return read(file, text, error, maxBytes, true);
}

}  // namespace st::io
