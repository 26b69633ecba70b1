// A contact patch's limit surface (Goyal, Ruina and Papadopoulos): the set of friction wrenches
// (f_t, tau) a patch under uniform pressure can give, and the one it gives as it slides and spins.
// The patch is sampled as a grid of points, each a Coulomb contact with its share of the load (an
// area weight), so that a box sent off sliding and spinning turns as a grid of point contacts under
// it predicts; Howe and Cutkosky's ellipsoid, which igms took before, is right only at pure sliding
// and pure spinning (a 0.2 m box sent off at 1 m/s, 5 rad/s: 18 % short of the grid's turn).
//
// Everything is in the friction's scaled coordinates (contact_solver.h): a wrench s = (f_t, tau / r)
// and a slip w = (u_t, r omega), r the patch's torsion radius (patch_radius.h), the samples' positions
// divided by their mean distance (so that pure spinning takes mu N r, as the radius says, and pure
// sliding mu N). Per unit load, the slip's dissipation is the support function
//   h(w) = sum_k weight_k |w_t + w_z z x r_k|,
// a norm (each sample's length smoothed, below); the surface is {s : s . w <= h(w) for every w}, the friction against a slip w is
// -mu N grad h(w) (maximal dissipation), and s's size (1 on the surface) is h's dual norm. With no
// samples (a point, a patch without a radius) h is the Euclidean norm: the ball (the ellipsoid in
// unscaled coordinates), and every function here gives the ball's answer to the bit.
// Allocation-free; the order of every sum is fixed.
#pragma once

#include "core/model/spatial.h"

namespace igms {

constexpr int kLimitGrid = 4;                             // samples a side of a quadrilateral; a line's
constexpr int kLimitSamples = kLimitGrid * kLimitGrid;
// Each sample's slip length is smoothed, sqrt(|slip|^2 + eps^2 |w|^2): the sampled surface has flat
// faces (a sample's disc, where the patch turns about it) that stall Newton's method; smoothed, it is
// strictly convex like uniform pressure's own. With 0.1, the box above turns within 0.8 % of uniform
// pressure (0.3-1.1 % unsmoothed).
constexpr double kLimitSmoothing = 0.1;

struct LimitSurface {
  int samples = 0;                  // 0: the ball
  double x[kLimitSamples] = {}, y[kLimitSamples] = {}, weight[kLimitSamples] = {};
  // Bounds on h over unit vectors, so on the surface's distance from the origin: the ball of radius
  // inner lies inside it, the surface inside the ball of radius outer (most sizes need no solve).
  double inner = 1.0, outer = 1.0;
};

// The surface of the patch whose carrying points are (u[k], v[k]) in its plane from their centroid,
// n of them (at most 4): a 4 x 4 grid over their polygon by its bilinear map, area-weighted, or 4
// points along a line (as patchTorsionRadius tells the two apart); fewer than two points: the ball.
void sampleLimitSurface(const double* u, const double* v, int n, LimitSurface& out);

// h(w): the dissipation per unit load of slip w.
double limitSupport(const LimitSurface& s, const Vector3& w);
// grad h(w): the point of the surface whose outward normal is w (w not 0): the friction per unit
// load, reversed, of a patch slipping at w.
Vector3 limitGradient(const LimitSurface& s, const Vector3& w);
// h(w) and its gradient and Hessian at w (w not 0).
double limitDerivatives(const LimitSurface& s, const Vector3& w, Vector3& grad, Eigen::Matrix3d& hess);
// The size of wrench f: the least t with f inside t times the surface (|f| for the ball). hint: as
// limitInside's.
double limitSize(const LimitSurface& s, const Vector3& f, Vector3* hint = nullptr);
// Whether f is inside cap times the surface (its size at most cap), from the bounds where they tell.
// hint (optional): the surface normal the last solve on this patch found, in and out: Newton's method
// starts from it (a patch's solves within one step are near each other: each then takes a step or
// two), and the answer does not depend on it beyond round-off. Zero: no hint.
bool limitInside(const LimitSurface& s, const Vector3& f, double cap, Vector3* hint = nullptr);
// The point of cap times the surface nearest to f (f itself where it is inside). hint: as limitInside's
// (out: the answer's normal where f is outside).
Vector3 limitProject(const LimitSurface& s, const Vector3& f, double cap, Vector3* hint = nullptr);

}  // namespace igms
