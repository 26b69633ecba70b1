// The replay suite: committed sessions recorded with the real server and
// client (a push, a pull, a push with 20 % of replies dropped, and the
// paper's push and pull experiments, gzip-compressed), re-simulated
// offline. The deviation from the recording stays within tolerance, and two
// re-simulations of one log give identical bits. When a change of behaviour
// is intended, re-record with scripts/sessions/record_replay_suite.sh (it shows the
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
                                           "paper_pull.lcmlog.gz", "paper_nominal.lcmlog.gz",
                                           "paper_two_hands.lcmlog.gz"),
                         [](const auto& info) {
                           std::string n = info.param;
                           return n.substr(0, n.find('.'));
                         });

}  // namespace
}  // namespace igms::test

#include "channels.h"
#include "core/simulation/simulation.h"
#include "tools/replay/recorded_session.h"

namespace igms::test {
namespace {

// A log whose messages do not decode (a zero-length string, which LCM 1.3.1's
// decoder throws on; bytes of another message type) is read without a throw,
// and re-simulation says why it has nothing to compare.
TEST(RecordedSession, UndecodableMessagesAreCountedAndNamedNotFatal) {
  const std::string path = sourceDir() + "/tests/replay/data/push.lcmlog";
  log::LogContents log = log::readAll(path);
  ASSERT_FALSE(log.events.empty());
  int poisoned = 0;
  for (auto& e : log.events) {
    if (e.channel == channels::kSessionInfo) {
      for (size_t k = 24; k < 28; ++k) e.data[k] = 0;  // fingerprint, utime, session_token: then build_version's length
      ++poisoned;
    } else if (e.channel == channels::kRobotState && poisoned < 50) {
      e.data[0] ^= 0xff;  // another type's fingerprint
      ++poisoned;
    }
  }
  const RecordedSession session = readRecordedSession(log.events);
  EXPECT_FALSE(session.has_info);
  EXPECT_EQ(session.undecodable, poisoned);
  const ResimResult r = resimulate(log.events, sourceDir());
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("did not decode"), std::string::npos) << r.error;
}

// A server started with an absolute scene path: the scene's relative model path resolves from the
// scene's own folder, whatever the base folder (it used to be joined to it: ".//abs/...: cannot open").
TEST(RecordedSession, AnAbsoluteScenePathResolvesWithoutTheBaseFolder) {
  log::LogContents log = log::readAll(sourceDir() + "/tests/replay/data/push.lcmlog");
  RecordedSession session = readRecordedSession(log.events);
  ASSERT_TRUE(session.has_info);
  session.info.scene_path = sourceDir() + "/scenes/puma_wall.yaml";
  const Scene scene = recordedScene(session, "/nonexistent-base");
  EXPECT_NE(scene.robots[0].floating_base, true);
  EXPECT_EQ(Simulation(scene).model().nv, 6) << "the PUMA loaded from ../models beside the scene";
}

}  // namespace
}  // namespace igms::test
