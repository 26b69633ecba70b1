// The contact solve's figures over a run as a dict: what Simulation.summary() and run_scenario() report
// under "contact_solve", igms-scenario's JSON fields.
#pragma once

#include <nanobind/nanobind.h>

#include "tools/scenario/scenario_run.h"

namespace igms::python {

inline nanobind::dict solveFigures(const ScenarioSolveStats& s) {
  nanobind::dict d;
  d["solves"] = s.solves;
  d["unconverged"] = s.unconverged;
  d["max_sweeps"] = s.max_sweeps;
  d["polish_rounds"] = s.polish_rounds;
  d["max_residual"] = s.max_residual;
  d["warm_dropped"] = s.warm_dropped;
  d["restitution_scaled"] = s.restitution_scaled;
  d["energy_capped"] = s.energy_capped;
  d["position_unconverged"] = s.position_unconverged;
  d["slips_unturned"] = s.slips_unturned;
  d["polish_cycles"] = s.polish_cycles;
  d["large_solves"] = s.large_solves;
  d["large_iterations"] = s.large_iterations;
  d["max_slip_angle"] = s.max_slip_angle;
  d["linearised_exact"] = s.linearised_exact;
  d["linearised"] = s.linearised;
  d["linearised_failed"] = s.linearised_failed;
  d["max_linearised_angle"] = s.max_linearised_angle;
  return d;
}

}  // namespace igms::python
