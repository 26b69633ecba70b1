// igms-scenario's CSV, as a user reads it: every number parses back to the bits the simulation had
// (round-trip digits, not a stream's default 6), and the contact count per step is the solver's. Run
// on a mesh scene (scenes/ball_on_mesh.yaml), where a ball used to sink: the CSV then said 0 contacts
// at every step while the JSON said max_contacts 1. The contact solve's sweeps and residual per step
// are the solver's too.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/simulation/simulation.h"
#include "tests/support/child_process.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  for (std::string cell; std::getline(s, cell, ',');) out.push_back(cell);
  return out;
}

TEST(ScenarioCsv, EveryNumberRoundTripsAndTheContactsAreTheSolvers) {
  const std::string scene = test::sourceDir() + "/scenes/ball_on_mesh.yaml";
  const std::string csv = ::testing::TempDir() + "/ball_on_mesh.csv";
  const double seconds = 1.5;
  {
    test::ChildProcess run({std::string(std::getenv("IGMS_TOOLS_DIR")) + "/igms-scenario", "--scene", scene,
                            "--seconds", "1.5", "--csv", csv});
    ASSERT_EQ(run.wait(std::chrono::milliseconds(60000)), 0);
  }
  std::ifstream in(csv);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  const std::vector<std::string> header = split(line);
  auto column = [&](const std::string& name) {
    for (size_t k = 0; k < header.size(); ++k)
      if (header[k] == name) return static_cast<int>(k);
    ADD_FAILURE() << "no column " << name;
    return 0;
  };
  const int contacts = column("contacts"), first_q = column("ball.x");
  const int sweeps = column("solver_sweeps"), residual = column("solver_residual");
  Simulation sim(loadScene(scene));
  const int steps = static_cast<int>(seconds / sim.scene().dt + 0.5);
  int rows = 0, touching = 0;
  for (int k = 0; k < steps && std::getline(in, line); ++k, ++rows) {
    ASSERT_TRUE(sim.step(nullptr));
    const std::vector<std::string> cells = split(line);
    ASSERT_EQ(std::stoi(cells[static_cast<size_t>(contacts)]), sim.contacts().n) << "step " << k;
    // The contact solve's own sweeps and residual, each step it ran.
    const bool solved = sim.contacts().n > 0;
    ASSERT_EQ(std::stoi(cells[static_cast<size_t>(sweeps)]), solved ? sim.contactStats().iterations : 0) << "step " << k;
    ASSERT_EQ(std::strtod(cells[static_cast<size_t>(residual)].c_str(), nullptr), solved ? sim.contactStats().residual : 0.0)
        << "step " << k;
    if (solved) ASSERT_GE(sim.contactStats().iterations, 1) << "step " << k;
    touching += sim.contacts().n > 0;
    for (int i = 0; i < sim.model().nq; ++i)
      ASSERT_EQ(std::strtod(cells[static_cast<size_t>(first_q + i)].c_str(), nullptr), sim.q()[i])
          << "step " << k << ", coordinate " << i << ": the CSV's digits do not round-trip";
  }
  std::printf("%d rows, every q bit for bit; contacts in %d of them, as the solver had\n", rows, touching);
  EXPECT_EQ(rows, steps);
  EXPECT_GT(touching, steps / 2) << "the balls rest on the meshes";
}

}  // namespace
}  // namespace igms
