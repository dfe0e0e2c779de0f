// The TraCI relay's framing checks (stcosim/traci_framing.hpp TraciFraming): the input is a
// conversation, records [u8 h] [h & 0x7f bytes], from libtraci (h < 0x80) or from the server. A
// reply is passed on only whole: what replies() accepts must be a run of frames whose length
// fields add up to it, each in [kMinReply, kMaxReply], one per pending request it removes; once
// it names a failure the relay ends, so the conversation does too.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <stcosim/traci_framing.hpp>

using st::cosim::TraciFraming;

namespace {

[[noreturn]] void finding(const char* what) {
  std::fprintf(stderr, "traci_relay: %s\n", what);
  std::abort();
}

std::uint32_t bigEndian32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  TraciFraming framing;
  std::vector<unsigned char> replies;  // the server's bytes not yet passed on
  bool passed = false;
  for (std::size_t i = 0; i < size;) {
    const bool fromServer = data[i] & 0x80;
    const std::size_t n = std::min<std::size_t>(data[i] & 0x7f, size - i - 1);
    const unsigned char* bytes = data + i + 1;
    i += 1 + n;
    if (!fromServer) {
      framing.request(bytes, n, TraciFraming::Clock::now());
      continue;
    }
    replies.insert(replies.end(), bytes, bytes + n);
    const std::size_t pendingBefore = framing.pending().size();
    std::string failure;
    const std::size_t whole = framing.replies(replies.data(), replies.size(), failure);
    if (whole > replies.size()) finding("accepted more bytes than there are");
    std::size_t frames = 0, at = 0;
    while (at < whole) {
      if (whole - at < 4) finding("accepted a cut length field");
      const std::uint32_t length = bigEndian32(replies.data() + at);
      if (length < TraciFraming::kMinReply || length > TraciFraming::kMaxReply) finding("accepted a bad length");
      at += length;
      ++frames;
    }
    if (at != whole) finding("accepted a cut reply");
    if (framing.pending().size() + frames != pendingBefore) finding("replies and pending requests do not match");
    passed = passed || frames > 0;
    if (framing.answered() != passed) finding("answered() is wrong");
    if (!failure.empty()) {
      if (failure.find('\n') != std::string::npos) finding("a failure of more than one line");
      break;  // the relay cuts the connection here
    }
    replies.erase(replies.begin(), replies.begin() + static_cast<std::ptrdiff_t>(whole));
  }
  return 0;
}
