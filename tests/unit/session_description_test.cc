// What a log carries about its model (server/app/session_description) and how
// a replay reads it back (tools/replay/recorded_session): the model file
// byte for byte, and the meshes' hashes, which a replay compares with its own.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/model/robot_description.h"
#include "core/model_io/zlib_text.h"
#include "server/app/session_description.h"
#include "tests/support/test_models.h"
#include "tools/replay/recorded_session.h"

namespace igms::test {
namespace {

TEST(SessionDescription, CarriesTheModelFileByteForByte) {
  Simulation sim(loadScene(sourceDir() + "/scenes/puma_wall.yaml"));
  const session_info_t info = describeSession(sim, "lockstep");
  const std::string file = readModelFile(sim.scene().robots[0].model_path);
  ASSERT_EQ(info.model_size, static_cast<int32_t>(file.size()));
  EXPECT_LT(info.model_zlib_size, info.model_size / 3) << "compressed";
  EXPECT_EQ(inflateText(info.model_zlib.data(), info.model_zlib.size(), static_cast<size_t>(info.model_size), "x"),
            file);
  EXPECT_EQ(info.model_hash, textHash(file));
  EXPECT_EQ(info.nmeshes, 0) << "the PUMA has primitives only";
  // A damaged copy is an error that names it, never a wrong model.
  std::vector<uint8_t> damaged = info.model_zlib;
  damaged[damaged.size() / 2] ^= 0xff;
  EXPECT_THROW(inflateText(damaged.data(), damaged.size(), static_cast<size_t>(info.model_size), "the copy"),
               std::runtime_error);
  EXPECT_THROW(inflateText(info.model_zlib.data(), info.model_zlib.size(), size_t{1} << 40, "the copy"),
               std::runtime_error) << "an implausible size is refused before allocating";
  // Read back: the scene uses the log's copy.
  RecordedSession session;
  session.has_info = true;
  session.info = info;
  session.info.model_path = "/nowhere/puma560.urdf";
  const Scene back = recordedScene(session, sourceDir());
  EXPECT_EQ(back.robots[0].model_text, file);
}

// The push coupling's damper came with igms 0.2: a log of an older server re-simulates with its
// pushes as they were, eq. (3)'s spring alone; this build's logs keep their scene's damper.
TEST(SessionDescription, ALogFromBeforeTheCouplingDamperReplaysWithout) {
  EXPECT_TRUE(predatesCouplingDamper("igms 0.1.0 (151cbe82217f-dirty)"));
  EXPECT_TRUE(predatesCouplingDamper(""));
  EXPECT_FALSE(predatesCouplingDamper("igms 0.2.0 (4ceb0cf)"));
  EXPECT_FALSE(predatesCouplingDamper("igms 1.0.3 (abc)"));
  Simulation sim(loadScene(sourceDir() + "/scenes/puma_wall.yaml"));
  ASSERT_GT(sim.scene().push.b, 0.0) << "the scene's default damper";
  RecordedSession session;
  session.has_info = true;
  session.info = describeSession(sim, "lockstep");
  EXPECT_EQ(recordedScene(session, sourceDir()).push.b, sim.scene().push.b) << session.info.build_version;
  session.info.build_version = "igms 0.1.0 (151cbe82217f)";
  EXPECT_EQ(recordedScene(session, sourceDir()).push.b, 0.0);
}

TEST(SessionDescription, HashesTheMeshesAndAReplayNamesTheOnesThatDiffer) {
  if (!std::filesystem::exists(sourceDir() + "/third_party/example-robot-data/robots/panda_description"))
    GTEST_SKIP() << "example-robot-data not fetched (scripts/setup/fetch_robots.sh)";
  Simulation sim(loadScene(sourceDir() + "/scenes/panda_obstacle.yaml"));
  const session_info_t info = describeSession(sim, "lockstep");
  ASSERT_GT(info.nmeshes, 10);  // collision and visual meshes of the links
  ASSERT_EQ(info.mesh_hashes.size(), info.mesh_uris.size());
  for (size_t i = 0; i < info.mesh_uris.size(); ++i) EXPECT_NE(info.mesh_hashes[i], "missing") << info.mesh_uris[i];
  RecordedSession session;
  session.has_info = true;
  session.info = info;
  EXPECT_TRUE(meshDifferences(session, sim.model()).empty());
  session.info.mesh_hashes[3] = "0000000000000000";
  const std::vector<std::string> d = meshDifferences(session, sim.model());
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0], info.mesh_uris[3] + ": recorded 0000000000000000, here " + info.mesh_hashes[3]);
}

}  // namespace
}  // namespace igms::test
