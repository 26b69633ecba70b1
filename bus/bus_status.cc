#include "bus/bus_status.h"

#include "bus/bus_key.h"
#include "bus/message_signer.h"

namespace igms::bus {

static_assert(sizeof(bus_status_t::refused) / sizeof(int64_t) == kRefusals, "bus_status_t.refused: one per reason");

bus_status_t busStatus(const std::string& program, const MessageVerifier& verifier, int64_t utime) {
  bus_status_t s{};
  s.utime = utime;
  s.program = program;
  s.keyed = verifier.keyed();
  if (s.keyed) s.sender = hexOf(processSender().data(), 8);
  const VerifierCounts c = verifier.counts();
  s.accepted = c.accepted;
  for (int k = 0; k < kRefusals; ++k) s.refused[k] = c.refused[static_cast<size_t>(k)];
  s.signed_unchecked = c.signed_unchecked;
  return s;
}

}  // namespace igms::bus
