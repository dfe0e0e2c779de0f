#include <stcosim/traci_framing.hpp>

#include <cstdio>

namespace st::cosim {
namespace {

std::uint32_t bigEndian32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
}

// The first bytes of a message, printable, for an error line: "HTTP/1.1" or "\x00\x00\x00\x03".
std::string preview(const unsigned char* b, std::size_t n) {
  std::string out = "\"";
  for (std::size_t i = 0; i < n && i < 8; ++i) {
    const unsigned char c = b[i];
    if (c >= 0x20 && c < 0x7f && c != '"' && c != '\\') {
      out += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
  }
  out += '"';
  return out;
}

}  // namespace

void TraciFraming::request(const unsigned char* bytes, std::size_t n, Clock::time_point now) {
  request_.insert(request_.end(), bytes, bytes + n);
  std::size_t used = 0;
  while (request_.size() - used >= 4) {
    // [length32] [command length | 0, length32] [command] ...; the shortest is 6 bytes (getVersion)
    const unsigned char* r = request_.data() + used;
    const std::size_t have = request_.size() - used;
    const std::uint32_t length = bigEndian32(r);
    if (length < 6 || (have > 4 && r[4] == 0 && length < 10)) {
      request_.clear();  // libtraci never sends this; stop tracking rather than guess
      return;
    }
    if (have < length) break;
    pending_.push_back({r[4] == 0 ? r[9] : r[5], now});
    used += length;
  }
  request_.erase(request_.begin(), request_.begin() + static_cast<std::ptrdiff_t>(used));
}

std::size_t TraciFraming::replies(const unsigned char* bytes, std::size_t n, std::string& failure) {
  std::size_t used = 0;
  const auto shown = [&] { return preview(bytes + used, n - used); };
  while (n - used >= 4) {
    const unsigned char* p = bytes + used;
    const std::uint32_t length = bigEndian32(p);
    if (length < kMinReply || length > kMaxReply) {
      failure = "not a TraCI server: reply length field " + std::to_string(length) + " (bytes " + shown() + ")";
      break;
    }
    if (n - used < length) break;
    // the status block: [len | 0, len32] [command] [result] [string: len32, bytes]
    const unsigned char* s = p + 4;
    const std::size_t header = s[0] == 0 ? 5 : 1;
    const std::size_t fixed = header + 2 + 4;
    bool sound = 4 + fixed <= length;
    if (sound) {
      const std::uint32_t blockLength = header == 5 ? bigEndian32(s + 1) : s[0];
      const int result = s[header + 1];
      const std::uint32_t text = bigEndian32(s + header + 2);
      sound = (result == 0x00 || result == 0x01 || result == 0xff) && text <= length &&
              blockLength == fixed + text && 4 + blockLength <= length;
    }
    if (!sound) {
      failure = "not a TraCI server: malformed status in a reply (bytes " + shown() + ")";
      break;
    }
    const int command = s[header];
    if (pending_.empty()) {
      failure = "not a TraCI server: a reply to no request (bytes " + shown() + ")";
      break;
    }
    if (command != pending_.front().command) {
      char msg[96];
      std::snprintf(msg, sizeof msg, "not a TraCI server: reply to command 0x%02x, asked 0x%02x", command,
                    pending_.front().command);
      failure = msg;
      break;
    }
    pending_.pop_front();
    answered_ = true;
    used += length;
  }
  return used;
}

}  // namespace st::cosim
