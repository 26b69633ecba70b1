// The replay device (an LCM log of haptic inputs played back as a device) and
// the device registry: devices by name, as --device NAME[:ARGS] finds them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "haptic_client/device/device_registry.h"
#include <algorithm>
#include <lcm/lcm-cpp.hpp>

#include "haptic_client/device/replay_device.h"
#include "igms/haptic_input_t.hpp"

namespace igms {
namespace {

TEST(ReplayDevice, PlaysBackTheRecordedTipMotionAndButtons) {
  const std::string path = ::testing::TempDir() + "/inputs.lcmlog";
  {
    lcm::LogFile log(path, "w");
    ASSERT_TRUE(log.good());
    for (int k = 0; k <= 100; ++k) {
      haptic_input_t m{};
      m.utime = 5'000'000 + k * 1000;  // 1 kHz
      m.seq = k;
      m.tip_position[0] = 0.001 * k;  // 1 m/s along x, scene frame
      m.mode = k >= 50 ? haptic_input_t::MODE_PULL : haptic_input_t::MODE_NONE;
      m.client_id = 1;
      // A 6-dof session: the tip turning about z at 1 rad/s.
      m.has_orientation = true;
      m.tip_orientation[0] = std::cos(0.0005 * k);
      m.tip_orientation[3] = std::sin(0.0005 * k);
      m.tip_angular_velocity[2] = 1.0;
      std::vector<uint8_t> buf(static_cast<size_t>(m.getEncodedSize()));
      m.encode(buf.data(), 0, static_cast<int>(buf.size()));
      lcm::LogEvent e;
      e.eventnum = k;
      e.timestamp = m.utime;
      e.channel = "IGMS_HAPTIC_INPUT";
      e.datalen = static_cast<int32_t>(buf.size());
      e.data = buf.data();
      log.writeEvent(&e);
      m.client_id = 2;  // another hand in the same log: not this device's
      m.tip_position[0] = -1.0;
      buf.assign(static_cast<size_t>(m.getEncodedSize()), 0);
      m.encode(buf.data(), 0, static_cast<int>(buf.size()));
      e.data = buf.data();
      log.writeEvent(&e);
    }
  }
  ReplayDevice d(path, WorkspaceMap{2.0, Vector3::Zero()});
  EXPECT_EQ(d.samples(), 101u);
  const DeviceReading r = d.read(0.0255);
  EXPECT_NEAR(r.position.x(), 0.0255 / 2.0, 1e-12);  // scene 0.0255 m at scale 2
  EXPECT_NEAR(r.velocity.x(), 0.5, 1e-9);
  EXPECT_EQ(r.buttons, 0);
  EXPECT_TRUE(r.has_orientation);
  EXPECT_NEAR(Eigen::AngleAxisd(r.orientation).angle(), 0.0255, 1e-9) << "the orientation, slerped";
  EXPECT_NEAR(r.angular_velocity.z(), 1.0, 1e-12);
  EXPECT_GT(d.limits().max_torque, 0.0) << "a 6-dof session's device renders torque";
  EXPECT_EQ(d.read(0.06).buttons, 1) << "a recorded pull replays as the button held";
  EXPECT_FALSE(d.finished(0.099));
  EXPECT_TRUE(d.finished(0.11));
  std::remove(path.c_str());
  EXPECT_THROW(ReplayDevice("/nonexistent.lcmlog", WorkspaceMap{}), std::runtime_error);
}


TEST(DeviceRegistry, FindsEachBuiltDeviceByNameAndNamesTheKnownOnesOnAMiss) {
  std::vector<std::string> names;
  for (const auto& e : DeviceRegistry::entries()) names.push_back(e.name);
  EXPECT_NE(std::find(names.begin(), names.end(), "scripted"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "replay"), names.end());
  const std::string script = ::testing::TempDir() + "/still.yaml";
  std::ofstream(script) << "waypoints:\n  - {t: 0.0, xyz: [0.1, 0.2, 0.3]}\nend: 1.0\n";
  const DeviceContext context{WorkspaceMap{}, [](const std::string&, SE3*) { return false; }};
  const auto d = DeviceRegistry::make("scripted:" + script, context);
  EXPECT_EQ(d->name(), "scripted:" + script);
  EXPECT_NEAR(d->read(0.5).position.y(), 0.2, 1e-12);
  try {
    DeviceRegistry::make("phantom:0", context);
    ADD_FAILURE() << "an unknown device must throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no device named 'phantom'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("replay, scripted"), std::string::npos) << e.what();
  }
  EXPECT_THROW(DeviceRegistry::make("scripted", context), std::runtime_error) << "scripted needs a file";
  EXPECT_NE(DeviceRegistry::usage().find("scripted:FILE"), std::string::npos);
  std::remove(script.c_str());
}

}  // namespace
}  // namespace igms
