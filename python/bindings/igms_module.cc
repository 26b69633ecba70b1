// The native part of the igms Python package (igms._igms); python/package/__init__.py
// adds what is easier said in Python (the hands, contacts as a structured array)
// and the message types.
#include <nanobind/nanobind.h>

#include "core/model/robot_description.h"
#include "core/scene/scene.h"
#include "python/bindings/bindings.h"
#include "python/bindings/diverged_error.h"
#include "tools/eventlog/event_log.h"

NB_MODULE(_igms, m) {
  namespace nb = nanobind;
  m.doc() = "igms: interactive dynamics of articulated bodies (Son, Kim, Jang, Choi 2003)";
  nb::exception<igms::SceneError>(m, "SceneError", PyExc_ValueError);
  nb::exception<igms::ModelError>(m, "ModelError", PyExc_ValueError);
  nb::exception<igms::log::LogError>(m, "LogError", PyExc_OSError);
  nb::exception<igms::python::DivergedError>(m, "SimulationDiverged", PyExc_RuntimeError);
  igms::python::bindModel(m);
  igms::python::bindSimulation(m);
  igms::python::bindLog(m);
}
