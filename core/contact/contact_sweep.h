// Projected block Gauss-Seidel on the contact rows (contact_rows.h): pair by pair, its velocity
// u = b + X^T z from the accumulator, the pair's block solved or projected (a point: sticking first,
// the whole 3x3 block at once, else the normal and the friction onto the cone; a patch: its normals
// one by one, then its friction inside its limit surface), and z updated by the change.
// At the edge of the cone the friction steps isotropically (1 / the largest eigenvalue of its
// block), whose fixed point has the friction opposite the slip (maximal dissipation).
#pragma once

#include "core/contact/contact_rows.h"

namespace igms {

struct SweepResult {
  bool converged = false;
  int sweeps = 0;        // taken
  double residual = 0.0;  // m/s: the largest velocity change of the last sweep
};

// Up to `sweeps` sweeps over every group's impulses, stopping once none changes a contact velocity
// by more than `tolerance`. z holds D^-1 sum X lambda before and after.
SweepResult sweepImpulses(ContactRows& rows, VectorX& z, int sweeps, double tolerance);

// Group g's own problem with every other impulse held (u: its velocity without its own impulse, its
// targets in g.target): block solves from g.lambda until one changes its velocity by no more than
// `tolerance`, at most `sweeps`. \return converged.
bool solveGroupAlone(ContactGroup& g, const ContactRowVector& u, int sweeps, double tolerance);

// The position correction's pseudo-impulses sigma (normal rows only, targets in g.target): each >= 0
// but where a bounce sets the end gap (free sign). zs: their accumulator, zero before.
SweepResult sweepPseudo(ContactRows& rows, VectorX& zs, int sweeps, double tolerance);

}  // namespace igms
