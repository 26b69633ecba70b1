// A scene whose state message would not fit one LCM datagram is refused at load, naming the sizes;
// the 216-sphere pile fits.
#include <gtest/gtest.h>

#include "core/scene/resolved_scene.h"
#include "server/app/state_publisher.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

std::string spheres(int n) {
  std::string yaml = "ground: true\nbodies:\n";
  for (int k = 0; k < n; ++k)
    yaml += "  - {name: s" + std::to_string(k) + ", shape: sphere, radius: 0.05, mass: 1, xyz: [" +
            std::to_string(0.2 * k) + ", 0, 0.05]}\n";
  return yaml;
}

TEST(StateSize, ThePileFitsOneDatagram) {
  const ResolvedScene pile = resolveScene(loadScene(test::sourceDir() + "/scenes/sphere_pile.yaml"));
  robot_state_t msg = sizedStateMessage(*pile.model);
  std::printf("the pile's state: %d bytes\n", msg.getEncodedSize());
  EXPECT_EQ(stateTooLarge(*pile.model, "sphere_pile.yaml"), "");
}

TEST(StateSize, ALargerSceneIsRefusedNamingTheSizes) {
  const ResolvedScene big = resolveScene(parseScene(spheres(300), "big.yaml", "."));
  const std::string why = stateTooLarge(*big.model, "big.yaml");
  EXPECT_NE(why.find("big.yaml: its state message would be"), std::string::npos) << why;
  EXPECT_NE(why.find("nq 2100"), std::string::npos) << why;
  EXPECT_NE(why.find("65499"), std::string::npos) << why;
}

}  // namespace
}  // namespace igms
