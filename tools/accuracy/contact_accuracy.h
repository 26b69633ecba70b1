// Error against run time for contact: the cases with an analytic answer (a box
// sliding to a stop, a box held on a slope, a sphere rolling down one, a ball
// bouncing with e = 0.5, a free top spinning for 10 s in a scene with contact, a
// ball resting on a mesh), each simulated by igms and by ODE's dWorldStep at
// h = 0.25 .. 4 ms, each run's error against the analytic answer beside its
// wall time per simulated second. The same case scenes are written for
// scripts/bench/contact_peers.py --accuracy, which puts MuJoCo's mj_step on the
// same axes; scripts/reports/accuracy_report.py draws the three together.
#pragma once

#include <string>
#include <vector>

namespace igms::accuracy {

struct ContactCase {
  std::string name;     // also the scene's file name in the cases folder: NAME.yaml
  std::string yaml;     // the scene
  std::string measure;  // what "error" means for it, in words
  std::string unit;     // the error's unit
  double seconds = 1.0;
  double goal_at_1ms;   // igms's bound at h = 1 ms (the goal for it)
};

// source_dir: where models/meshes is (the mesh case's file).
std::vector<ContactCase> contactCases(const std::string& source_dir);

struct ContactAccuracyOptions {
  bool quick = false;      // 0.5 .. 2 ms, one timing run
  int repeats = 3;         // timing runs per row (median)
  std::string csv;         // the rows, here
  std::string write_cases; // the scenes, into this folder, and return
  std::string source_dir;  // the repository (the meshes)
};

// Prints the table; 0 when igms meets every case's goal at 1 ms, 1 otherwise.
int contactAccuracy(const ContactAccuracyOptions& options);

}  // namespace igms::accuracy
