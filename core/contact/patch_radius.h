// A contact patch's torsion radius: the mean distance from its centroid over the region its points
// span under uniform pressure, so that spinning the patch in place takes mu N times it (a box's face
// on the floor: its rectangle; a cylinder lying down: its line). The mean of the points' own distances
// (the corners') overstated it: 1.85 times for a square, twice for a line.
#pragma once

namespace igms {

// The points' in-plane coordinates (u[k], v[k]) from their centroid, n of them (at most 4, convex as
// the detection spreads them, in any order). Three or more not all in a row: the mean of |r| over
// their polygon; else a line, uniform along it: a quarter of its length; fewer than two: 0.
double patchTorsionRadius(const double* u, const double* v, int n);

}  // namespace igms
