// Linear stability read off the integrators themselves: a body of mass m on a
// spring k with damper b (damping ratio zeta) is linear, so one step of any
// scheme is a 2 x 2 matrix on (x, xdot). igms's own integrateStep is run from
// the two unit states to build it; its spectral radius is the amplitude
// factor per step (stable: <= 1), exact rather than judged from a run.
#pragma once

#include <vector>

namespace igms::accuracy {

// Method 0 semi-implicit Euler, 1 RK4, 2 linearly implicit; ratio = k h^2 / m.
double stepSpectralRadius(int method, double ratio, double zeta, double mass = 0.1, double h = 1e-3);

// The largest stable k h^2 / m (spectral radius <= 1 + 1e-12), by bisection
// on [0.01, 1e4]; infinity when every ratio there is stable.
double spectralStabilityLimit(int method, double zeta, double mass = 0.1, double h = 1e-3);

// The linearly-implicit scheme's amplitude factor per step on an undamped
// spring, in theory: 1 / sqrt(1 + k h^2 / m) (det of its step matrix).
double linearlyImplicitTheory(double ratio);

}  // namespace igms::accuracy
