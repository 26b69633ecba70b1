// Prints a robot_state_t and a contacts_t encoded by the C++ types, as hex
// (a line each), for DecodeCheck.java.
#include <cstdio>
#include <vector>

#include "igms/contacts_t.hpp"
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
  igms::contacts_t c{};
  c.seq = 170;
  c.total = c.ncontacts = 1;
  c.link_a = {-1};
  c.link_b = {3};
  c.point = {{0.5, 0, 0.12}};
  c.normal = {{0, 0, 1}};
  c.force = {{0, 0, 2.9425}};
  c.distance = {-2.5e-5};
  buf.assign(static_cast<size_t>(c.getEncodedSize()), 0);
  c.encode(buf.data(), 0, static_cast<int>(buf.size()));
  for (uint8_t b : buf) std::printf("%02x", b);
  std::printf("\n");
}
