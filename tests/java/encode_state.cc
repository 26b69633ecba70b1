// Prints a robot_state_t encoded by the C++ types, as hex, for DecodeCheck.java.
#include <cstdio>
#include <vector>

#include "igms/robot_state_t.hpp"

int main() {
  igms::robot_state_t s{};
  s.seq = 4242;
  s.nq = 2;
  s.nv = 2;
  s.q = {0.125, -2.5};
  s.v = s.qdd = s.tau = {0.0, 0.0};
  s.nlinks = 2;
  s.link_poses = {{0, 0, 0, 1, 0, 0, 0}, {1, 2, 3.75, 1, 0, 0, 0}};
  std::vector<uint8_t> buf(static_cast<size_t>(s.getEncodedSize()));
  s.encode(buf.data(), 0, static_cast<int>(buf.size()));
  for (uint8_t b : buf) std::printf("%02x", b);
  std::printf("\n");
}
