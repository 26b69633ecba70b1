// The digits-against-conditioning measurement (tools/accuracy) under the tests' names.
#pragma once

#include "tools/accuracy/fd_digits.h"

namespace igms::test {
using accuracy::FdDigits;
using accuracy::measureFdDigits;
}  // namespace igms::test
