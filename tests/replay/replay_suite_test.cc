// The replay suite: committed sessions recorded with the real server and
// client (a push, a pull, a push with 20 % of replies dropped, and the
// paper's push and pull experiments, gzip-compressed), re-simulated
// offline. The deviation from the recording stays within tolerance, and two
// re-simulations of one log give identical bits. When a change of behaviour
// is intended, re-record with scripts/record_replay_suite.sh (it shows the
// deviation first) and --accept.
#include <gtest/gtest.h>

#include <cstring>

#include "tests/support/test_models.h"
#include "tools/replay/resimulate.h"

namespace igms::test {
namespace {

// Same build, same machine kind: bit-identical. The tolerance only allows
// for another libm's last bits; behaviour changes move far more.
constexpr double kTolerance = 1e-9;

class ReplaySuite : public ::testing::TestWithParam<std::string> {};

TEST_P(ReplaySuite, ResimulationMatchesTheRecording) {
  const std::string path = sourceDir() + "/tests/replay/data/" + GetParam();
  const log::LogContents log = log::readAll(path);
  ASSERT_FALSE(log.damaged) << log.error;
  const ResimResult r = resimulate(log.events, sourceDir());
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.error.empty()) << r.error;
  EXPECT_GE(r.steps, 1000) << "the whole session";
  for (const auto& d : r.deviations) EXPECT_LE(d.max_abs, kTolerance) << d.field << " at step " << d.at_seq;
  EXPECT_EQ(r.model_hash_logged, r.model_hash_now) << "the model file changed since the recording";
}

TEST_P(ReplaySuite, TwoResimulationsGiveIdenticalBits) {
  const std::string path = sourceDir() + "/tests/replay/data/" + GetParam();
  const log::LogContents log = log::readAll(path);
  const ResimResult a = resimulate(log.events, sourceDir()), b = resimulate(log.events, sourceDir());
  ASSERT_TRUE(a.ok && b.ok);
  ASSERT_EQ(a.final_q.size(), b.final_q.size());
  EXPECT_EQ(0, std::memcmp(a.final_q.data(), b.final_q.data(), a.final_q.size() * sizeof(double)));
  EXPECT_EQ(a.steps, b.steps);
}

INSTANTIATE_TEST_SUITE_P(Sessions, ReplaySuite,
                         ::testing::Values("push.lcmlog", "pull.lcmlog", "dropped.lcmlog", "paper_push.lcmlog.gz",
                                           "paper_pull.lcmlog.gz", "paper_nominal.lcmlog.gz"),
                         [](const auto& info) {
                           std::string n = info.param;
                           return n.substr(0, n.find('.'));
                         });

}  // namespace
}  // namespace igms::test
