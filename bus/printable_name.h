// A name from the wire (a channel's) made safe for a terminal: bytes outside
// printable ASCII become \xNN, so no escape sequence that arrived on the bus
// reaches a person's terminal, and the name is cut at kPrintableNameChars
// (marked "..."). Writes into a caller's buffer: usable where nothing may
// allocate (a verifier's first-refusal line).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace igms::bus {

inline constexpr size_t kPrintableNameChars = 120;
inline constexpr size_t kPrintableNameBytes = 4 * kPrintableNameChars + 4;

// Writes the printable form and a terminating NUL into `out` (kPrintableNameBytes).
void printableName(std::string_view name, char (&out)[kPrintableNameBytes]);
// The same for any text from the wire (a status's program name, a summary line), cut at `max_chars`.
std::string printableName(std::string_view text, size_t max_chars = kPrintableNameChars);

}  // namespace igms::bus
