// The synthetic robots (tools/synthetic) under the tests' names.
#pragma once

#include "tools/synthetic/random_urdf.h"

namespace igms::test {
using synthetic::RandomRobotOptions;
using synthetic::randomUrdf;
using synthetic::serialChainUrdf;
using synthetic::taperedChainUrdf;
}  // namespace igms::test
