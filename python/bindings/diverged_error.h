// The exception step() throws when the state diverges; igms.SimulationDiverged in Python.
#pragma once

#include <stdexcept>

namespace igms::python {

struct DivergedError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace igms::python
