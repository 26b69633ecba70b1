// Impacts passed along before the step's contact solve: pair by pair, as a sequence of two-body
// impacts (the sequential-impulse reading of Newton's law for simultaneous collisions), so that a
// blow travels down a chain as it does in Newton's cradle. Solved at once, the cradle's three balls
// share the blow (-1/3, 2/3, 2/3 of the speed, momentum and energy kept) where only the last should
// leave. Each round takes the pairs in order; a pair that approaches faster than the bounce speed,
// and meets within the step, takes its own impact with every other impulse held: its normal speed
// becomes e times its approach, with its friction (ContactSweep's block solve of that pair alone).
// Where a pair's impact would add kinetic energy (friction that sticks beside a bounce), its
// restitution is scaled down to the largest factor that adds none, so no pair's impact, and so no
// sequence of them, adds energy. Rounds continue until no pair approaches (or the limit: what is
// left is the solve's, as plastic contact).
// Runs only where impacts can pass along: a bouncing pair on a body that another pair touches. A
// lone impact is the solve's own, unchanged.
// Allocation-free.
#pragma once

#include "core/contact/contact_rows.h"
#include "core/contact/contact_set.h"

namespace igms {

struct ImpactPassing {
  int rounds = 0;    // rounds over the pairs
  int scaled = 0;    // pair impacts whose restitution was scaled down to add no energy
  bool settled = false;  // the last round had no pair approaching
};

// A bouncing pair in the solve with another pair, in the solve or waiting outside it, on one of its
// bodies: a chain an impact can pass along.
bool impactsCanPass(const ContactRows& rows);

// Called where impactsCanPass, over the groups in the solve (complete(): all of them, as a pair waiting
// outside the solve may be struck), their impacts into g.impact and the accumulator z
// (zero before; D^-1 sum X impact after, for ContactRows::apply).
ImpactPassing passImpacts(ContactRows& rows, const ContactSet& contacts, double h, double bounce_velocity,
                          int max_rounds, double tolerance, VectorX& z);

}  // namespace igms
