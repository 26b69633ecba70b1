// The parts of the igms module, one function each (igms_module.cc calls them in order).
#pragma once

#include <nanobind/nanobind.h>

namespace igms::python {

void bindModel(nanobind::module_& m);       // Model: the kernels on numpy arrays
void bindSimulation(nanobind::module_& m);  // Scene, Simulation, the hands
void bindLog(nanobind::module_& m);         // Log, resimulate, run_scenario

}  // namespace igms::python
