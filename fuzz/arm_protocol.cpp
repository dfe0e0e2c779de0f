// Arm service protocol (starm/protocol.hpp): any payload decodes to a message or one error line;
// a decoded message encodes back to the same bytes, and the service's READINGS fast path agrees
// with the general decoder.
#include <cstdlib>
#include <string_view>

#include <starm/protocol.hpp>

namespace proto = st::arm::proto;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view payload(reinterpret_cast<const char*>(data), size);
  const proto::Decoded d = proto::decode(payload);
  if (d.ok != d.error.empty()) std::abort();  // a result, or why not: never both, never neither
  // in the payload's own version (what decodes has a version byte the decoder serves)
  const auto version = d.ok ? static_cast<std::uint8_t>(payload[0]) : proto::kVersion;
  if (d.ok && proto::encode(d.message, version) != payload) std::abort();
  // the hot path: same verdict as decode() on READINGS, the same readings
  proto::Readings r;
  r.arms.resize(3);  // storage left from an earlier message must not leak into this one
  const std::string e = proto::decodeReadings(payload, r);
  const bool isReadings = d.ok && std::holds_alternative<proto::Readings>(d.message);
  if (e.empty() != isReadings) std::abort();
  if (isReadings && proto::encode(r, version) != payload) std::abort();
  return 0;
}
