// The stiff and extreme cases of the accuracy report (igms-accuracy --extreme),
// in full (the long run's ensemble with 3 starts, not the report's 9): every
// row's own pass criterion must hold. Each row is printed, so
// the test log is the report's table.
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/support/test_models.h"
#include "tools/accuracy/extreme_cases.h"

namespace igms::accuracy {
namespace {

TEST(ExtremeCases, EveryCaseMeetsItsCriterion) {
  const auto rows = extremeCases(test::sourceDir(), /*quick=*/false, /*long_run_starts=*/3);
  EXPECT_GE(rows.size(), 40u);
  for (const auto& r : rows) {
    std::printf("%-4s %s | %s | %s | %s\n", r.pass ? "pass" : "FAIL", r.name.c_str(), r.method.c_str(),
                r.criterion.c_str(), r.figure.c_str());
    EXPECT_TRUE(r.pass) << r.name << " (" << r.method << "): " << r.criterion << "; measured " << r.figure;
    EXPECT_EQ(r.figure.find("nan"), std::string::npos) << "a NaN reached the report";
  }
}

}  // namespace
}  // namespace igms::accuracy
