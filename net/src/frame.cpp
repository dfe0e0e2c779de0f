#include <stnet/frame.hpp>

#include <charconv>

namespace st::net {

void appendFrame(std::string& out, std::string_view payload) {
  const auto n = static_cast<std::uint32_t>(payload.size());
  const char h[kFrameHeader] = {static_cast<char>(n >> 24), static_cast<char>(n >> 16), static_cast<char>(n >> 8),
                                static_cast<char>(n)};
  out.append(h, kFrameHeader);
  out.append(payload);
}

std::string frame(std::string_view payload) {
  std::string out;
  out.reserve(kFrameHeader + payload.size());
  appendFrame(out, payload);
  return out;
}

FrameSplit splitFrame(std::string_view bytes, std::size_t maxPayload) {
  FrameSplit s;
  if (bytes.size() < kFrameHeader) return s;
  const auto b = [&](int i) { return static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i])); };
  s.length = (b(0) << 24) | (b(1) << 16) | (b(2) << 8) | b(3);
  if (s.length > maxPayload) {
    s.state = FrameSplit::State::TooLong;
    return s;
  }
  if (bytes.size() < kFrameHeader + s.length) return s;
  s.state = FrameSplit::State::Frame;
  s.payload = bytes.substr(kFrameHeader, s.length);
  s.consumed = kFrameHeader + s.length;
  return s;
}

std::optional<HostPort> parseHostPort(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) return std::nullopt;
  HostPort hp;
  hp.host = text.substr(0, colon);
  if (hp.host.front() == '[') {
    if (hp.host.size() < 3 || hp.host.back() != ']') return std::nullopt;
    hp.host = hp.host.substr(1, hp.host.size() - 2);
  }
  const std::string p = text.substr(colon + 1);
  unsigned v = 0;
  const auto [end, ec] = std::from_chars(p.data(), p.data() + p.size(), v);
  if (ec != std::errc() || end != p.data() + p.size() || v > 65535) return std::nullopt;
  hp.port = static_cast<std::uint16_t>(v);
  return hp;
}

}  // namespace st::net
