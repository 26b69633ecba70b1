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

// The same points' order around their centroid (by angle; n at most 4): the polygon's corners in turn.
void patchOrder(const double* u, const double* v, int n, int* order);

// Whether the points span an area (three or more not all in a row), as patchTorsionRadius decides:
// else they are a line, of the longest chord's ends *a and *b.
bool patchHasArea(const double* u, const double* v, int n, const int* order, int* a, int* b);

}  // namespace igms
