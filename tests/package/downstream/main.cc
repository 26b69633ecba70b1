// igms as a library: the PUMA's inverse dynamics at rest (gravity torques) and
// a robot_state_t through its wire format. Prints both; exits 1 on a mismatch.
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/dynamics/rnea.h"
#include "core/model_io/model_loader.h"
#include "igms/robot_state_t.hpp"
#include "safe_decode.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: downstream PUMA_URDF\n");
    return 2;
  }
  const igms::Model model = igms::loadModel(argv[1]);
  igms::Data data(model);
  const igms::VectorX q = igms::VectorX::Zero(model.nq), zero = igms::VectorX::Zero(model.nv);
  const igms::VectorX tau = igms::rnea(model, data, q, zero, zero);
  std::printf("rnea:");
  for (int i = 0; i < tau.size(); ++i) std::printf(" %.9g", tau[i]);
  std::printf("\n");

  igms::robot_state_t s{};
  s.seq = 42;
  s.nq = model.nq;
  s.nv = model.nv;
  s.q.assign(q.data(), q.data() + q.size());
  s.v.assign(model.nv, 0.0);
  s.qdd = s.v;
  s.tau.assign(tau.data(), tau.data() + tau.size());
  std::vector<uint8_t> bytes(static_cast<size_t>(s.getEncodedSize()));
  s.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  igms::robot_state_t back;
  if (!igms::safeDecode(bytes.data(), bytes.size(), &back) || back.seq != 42 ||
      back.tau != s.tau) {
    std::fprintf(stderr, "robot_state_t did not round-trip\n");
    return 1;
  }
  std::printf("robot_state_t: %d bytes, seq %lld, tau[1] %.9g\n", static_cast<int>(bytes.size()),
              static_cast<long long>(back.seq), back.tau[1]);
  return 0;
}
