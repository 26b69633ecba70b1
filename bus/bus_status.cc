#include "bus/bus_status.h"

#include "bus/message_signer.h"

namespace igms::bus {

static_assert(sizeof(bus_status_t::refused) / sizeof(int64_t) == kRefusals, "bus_status_t.refused: one per reason");

VerifierCounts sumCounts(const std::vector<const MessageVerifier*>& verifiers) {
  VerifierCounts sum;
  for (const MessageVerifier* v : verifiers) {
    const VerifierCounts c = v->counts();
    sum.accepted += c.accepted;
    sum.signed_unchecked += c.signed_unchecked;
    for (int k = 0; k < kRefusals; ++k) sum.refused[static_cast<size_t>(k)] += c.refused[static_cast<size_t>(k)];
  }
  return sum;
}

bus_status_t busStatus(const std::string& program, bool keyed, const std::vector<const MessageVerifier*>& verifiers,
                       int64_t utime) {
  bus_status_t s{};
  s.utime = utime;
  s.program = program;
  s.keyed = keyed;
  if (keyed) {
    static const char* digits = "0123456789abcdef";
    for (size_t i = 0; i < 8; ++i) {
      s.sender += digits[processSender()[i] >> 4];
      s.sender += digits[processSender()[i] & 15];
    }
  }
  const VerifierCounts c = sumCounts(verifiers);
  s.accepted = c.accepted;
  for (int k = 0; k < kRefusals; ++k) s.refused[k] = c.refused[static_cast<size_t>(k)];
  s.signed_unchecked = c.signed_unchecked;
  return s;
}

}  // namespace igms::bus
