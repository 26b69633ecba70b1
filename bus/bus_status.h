// A program's bus status (bus_status_t on IGMS_BUS_STATUS): the counts of
// its message verifiers, summed. Built and sent off the real-time loops.
#pragma once

#include <string>
#include <vector>

#include "bus/message_verifier.h"
#include "bus/signed_publisher.h"
#include "igms/bus_status_t.hpp"

namespace igms::bus {

bus_status_t busStatus(const std::string& program, bool keyed, const std::vector<const MessageVerifier*>& verifiers,
                       int64_t utime);

// Sums counts (a program with a verifier per receiving thread).
VerifierCounts sumCounts(const std::vector<const MessageVerifier*>& verifiers);

}  // namespace igms::bus
