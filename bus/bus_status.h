// A program's bus status (bus_status_t on IGMS_BUS_STATUS): its message
// verifier's counts. Built and sent off the real-time loops.
#pragma once

#include <cstdint>
#include <string>

#include "bus/message_verifier.h"
#include "igms/bus_status_t.hpp"

namespace igms::bus {

// Keyed when the verifier is (a program signs with the key it checks with).
bus_status_t busStatus(const std::string& program, const MessageVerifier& verifier, int64_t utime);

}  // namespace igms::bus
