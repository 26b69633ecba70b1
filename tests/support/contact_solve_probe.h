// The contact solve of one state taken alone, outside a step: the contacts at q, then ContactSolver
// with A = H (the inertia matrix's factor, from forward dynamics at (q, v0) with no torque), from the
// unconstrained velocity v_free (v0 + h qdd unless given). For tests that look inside one solve: the
// energy it leaves, its impulses' net effect, what it kept from the last one.
#pragma once

#include <gtest/gtest.h>

#include "core/contact/contact_detection.h"
#include "core/contact/contact_solver.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/simulation/simulation.h"

namespace igms::test {

struct ContactSolveProbe {
  explicit ContactSolveProbe(const Simulation& sim)
      : model(sim.model()),
        h(sim.scene().dt),
        data(model),
        geometry(sim.geometry()),
        placed(geometry),
        detection(*sim.contactModel()),
        solver(model, *sim.contactModel()),
        set(sim.contactModel()->capacity()),
        v_free(model.nv),
        v(model.nv),
        v_position(model.nv) {}

  // \return whether anything touched (then v_free, v = v+ and the set's impulses are the solve's).
  bool solve(const VectorX& q, const VectorX& v0) { return run(q, v0, nullptr); }
  bool solveFrom(const VectorX& q, const VectorX& v0, const VectorX& given_v_free) { return run(q, v0, &given_v_free); }

  const Model& model;
  double h;
  Data data;
  const GeometryModel& geometry;
  GeometryData placed;
  ContactDetection detection;
  ContactSolver solver;
  ContactSet set;
  VectorX v_free, v, v_position;

 private:
  bool run(const VectorX& q, const VectorX& v0, const VectorX* given) {
    EXPECT_TRUE(forwardDynamics(model, data, q, v0, VectorX::Zero(model.nv)));
    placed.place(geometry, model, data);
    detection.detect(placed, set);
    if (set.n == 0) return false;
    v_free = given ? *given : VectorX(v0 + h * data.qdd);
    v = v_free;
    solver.solve(data, data.Hfact, h, v0, set, v, v_position);
    return true;
  }
};

}  // namespace igms::test
