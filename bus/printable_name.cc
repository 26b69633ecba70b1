#include "bus/printable_name.h"

namespace igms::bus {

namespace {

// Writes at most 4 max_chars + 4 bytes.
void escape(std::string_view name, size_t max_chars, char* out) {
  static constexpr char kHex[] = "0123456789abcdef";
  size_t n = 0;
  const size_t shown = name.size() < max_chars ? name.size() : max_chars;
  for (size_t i = 0; i < shown; ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    if (c >= 0x20 && c < 0x7f && c != '\\') {
      out[n++] = static_cast<char>(c);
    } else {
      out[n++] = '\\';
      out[n++] = 'x';
      out[n++] = kHex[c >> 4];
      out[n++] = kHex[c & 15];
    }
  }
  if (shown < name.size())
    for (int k = 0; k < 3; ++k) out[n++] = '.';
  out[n] = '\0';
}

}  // namespace

void printableName(std::string_view name, char (&out)[kPrintableNameBytes]) { escape(name, kPrintableNameChars, out); }

std::string printableName(std::string_view text, size_t max_chars) {
  std::string out(4 * max_chars + 4, '\0');
  escape(text, max_chars, out.data());
  out.resize(std::char_traits<char>::length(out.c_str()));
  return out;
}

}  // namespace igms::bus
