// Numbers that another program reads back (CSV files): every double with max_digits10 significant
// digits, so that it parses to the same bits. A stream's default is 6 digits: 1 um at 1 m from the
// origin, coarser than the creep and overlap figures the tests assert.
#pragma once

#include <limits>
#include <ostream>

namespace igms::cli {

inline std::ostream& roundTripDigits(std::ostream& s) {
  s.precision(std::numeric_limits<double>::max_digits10);
  return s;
}

}  // namespace igms::cli
