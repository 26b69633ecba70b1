// zlib (RFC 1950) for the files a session log carries: the server deflates the
// model file into session_info_t, a replay inflates it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace igms {

std::vector<uint8_t> deflateText(const std::string& text);

// `expected_size` is the length before compression, as logged; a stream that
// does not inflate to exactly that throws std::runtime_error naming `what`.
std::string inflateText(const uint8_t* data, size_t size, size_t expected_size, const std::string& what);

}  // namespace igms
