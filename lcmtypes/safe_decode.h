// Decoding bytes that came over the bus or from a log. LCM 1.3.1's generated
// decoders throw (a string whose length field is 0 becomes
// std::length_error, a huge array length std::bad_alloc or length_error): a
// failed or throwing decode is a rejection the caller counts, never fatal.
#pragma once

#include <climits>
#include <cstddef>

namespace igms {

template <typename Message>
bool safeDecode(const void* data, size_t size, Message* out) noexcept {
  if (size > static_cast<size_t>(INT_MAX)) return false;
  try {
    return out->decode(data, 0, static_cast<int>(size)) >= 0;
  } catch (...) {
    return false;
  }
}

}  // namespace igms
