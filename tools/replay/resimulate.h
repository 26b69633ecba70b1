// Re-simulation of a recorded session: the scene from the log's session info,
// the recorded haptic inputs fed into the server's step function offline (no
// network, no clock) with the step -> input association the states recorded,
// and the result compared with the recorded states.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/simulation/simulation.h"
#include "tools/eventlog/event_log.h"

namespace igms {

struct FieldDeviation {
  std::string field;   // "q", "v", "qdd", "tau", "interaction_force", "link_poses"
  double max_abs = 0.0;
  int64_t at_seq = -1;  // state seq where the maximum occurred
};

struct ResimResult {
  bool ok = false;            // ran (the log had what a replay needs)
  std::string error;          // why not, or the damage warning
  int64_t steps = 0;          // states compared
  std::vector<FieldDeviation> deviations;
  bool identical = false;     // every compared double bit-identical
  double max_deviation = 0.0;
  std::string scene_path, model_hash_logged, model_hash_now, build_logged;
  bool model_from_log = false;                // the log carried the (first robot's) model file (else read from the disk)
  int robots = 0, models_from_log = 0;        // the scene's robots, and how many of their models came from the log
  std::vector<std::string> mesh_differences;  // meshes here that differ from the recording's
  std::vector<double> final_q;  // the re-simulated final configuration
};

// base_dir resolves the scene's relative model path (the server's working
// directory at record time; by default the current one). each_step, when given, sees the simulation
// after every re-simulated step (igms-replay export's contacts and bodies).
ResimResult resimulate(const std::vector<log::Event>& events, const std::string& base_dir = ".",
                       const std::function<void(const Simulation&)>& each_step = nullptr);

}  // namespace igms
