#include "core/model_io/zlib_text.h"

#include <zlib.h>

#include <stdexcept>

namespace igms {

std::vector<uint8_t> deflateText(const std::string& text) {
  uLongf size = compressBound(static_cast<uLong>(text.size()));
  std::vector<uint8_t> out(size);
  if (compress2(out.data(), &size, reinterpret_cast<const Bytef*>(text.data()), static_cast<uLong>(text.size()),
                Z_BEST_COMPRESSION) != Z_OK)
    throw std::runtime_error("zlib: cannot compress");
  out.resize(size);
  return out;
}

std::string inflateText(const uint8_t* data, size_t size, size_t expected_size, const std::string& what) {
  // A logged size is untrusted: bound it before allocating (a model file is well under 64 MB).
  if (expected_size > (64u << 20)) throw std::runtime_error(what + ": implausible size " + std::to_string(expected_size));
  std::string out(expected_size, '\0');
  uLongf got = static_cast<uLongf>(expected_size);
  const int rc = uncompress(reinterpret_cast<Bytef*>(out.data()), &got, data, static_cast<uLong>(size));
  if (rc != Z_OK || got != expected_size)
    throw std::runtime_error(what + ": damaged (zlib " + std::to_string(rc) + ", " + std::to_string(got) + " of " +
                             std::to_string(expected_size) + " bytes)");
  return out;
}

}  // namespace igms
