#pragma once
// Length-delimited frames: a 4-byte big-endian payload length, then the payload. Pure functions
// on bytes (no sockets), shared by the server, the client and their tests.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace st::net {

inline constexpr std::size_t kFrameHeader = 4;

// header + payload as one buffer
std::string frame(std::string_view payload);
void appendFrame(std::string& out, std::string_view payload);

// Splits frames off the front of a byte stream, refusing any longer than maxPayload.
struct FrameSplit {
  enum class State { Frame, NeedMore, TooLong };
  State state = State::NeedMore;
  std::string_view payload;  // State::Frame: the payload (a view into the input)
  std::size_t consumed = 0;  // bytes of the input it used (header + payload)
  std::uint32_t length = 0;  // the announced payload length (once the header is in)
};
FrameSplit splitFrame(std::string_view bytes, std::size_t maxPayload);

// "host:port" (IPv4 dotted, a name, or [v6]); port 0..65535. nullopt on anything else.
struct HostPort {
  std::string host;
  std::uint16_t port = 0;
};
std::optional<HostPort> parseHostPort(const std::string& text);

}  // namespace st::net
