#include "core/trajectory/cartesian_line.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <stdexcept>

#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/model/configuration.h"

namespace igms {

double solveIk(const Model& model, Data& data, int frame, const SE3& target, VectorX& q, int max_iterations) {
  const bool full = model.nv >= 6;
  const int rows = full ? 6 : 3;
  const double lambda = 1e-3;
  double err = 0.0;
  for (int it = 0; it <= max_iterations; ++it) {
    bodyKinematics(model, data, q);
    const SE3 X = framePose(model, data, frame);
    Vector6 e;
    e.head<3>() = target.p - X.p;
    const Eigen::AngleAxisd r(target.R * X.R.transpose());
    e.tail<3>() = r.axis() * r.angle();
    err = e.head(rows).norm();
    if (err < 1e-10 || it == max_iterations) break;
    pointJacobian(model, data, frame, Vector3::Zero(), data.J);
    const MatrixX J = data.J.topRows(rows);
    const MatrixX A = J * J.transpose() + lambda * lambda * MatrixX::Identity(rows, rows);
    const VectorX dq = J.transpose() * A.llt().solve(e.head(rows));
    integrateConfiguration(model, q, dq, 1.0, q);
  }
  return err;
}

PiecewisePolynomial cartesianLineTrajectory(const Model& model, const VectorX& q0, const CartesianLine& line) {
  if (line.frame < 0) throw std::runtime_error("cartesian line: unknown frame");
  if (!(line.duration > 0.0)) throw std::runtime_error("cartesian line: duration must be positive");
  Data data(model);
  forwardKinematics(model, data, q0);
  const SE3 start = data.oMf[static_cast<size_t>(line.frame)];
  const int samples = std::max(2, static_cast<int>(std::ceil(line.duration / line.sample_dt)) + 1);
  std::vector<double> times;
  std::vector<VectorX> points;
  VectorX q = q0;
  for (int k = 0; k < samples; ++k) {
    const double t = line.duration * k / (samples - 1);
    const double tau = t / line.duration;
    const double s = tau * tau * tau * (10 - 15 * tau + 6 * tau * tau);  // rest-to-rest quintic
    SE3 target = start;
    target.p = start.p + s * (line.target - start.p);
    const double err = solveIk(model, data, line.frame, target, q);
    if (err > 1e-6)
      throw std::runtime_error("cartesian line: inverse kinematics does not reach the line at t = " +
                               std::to_string(t) + " s (error " + std::to_string(err) + " m): target unreachable?");
    times.push_back(t);
    points.push_back(q);
  }
  return PiecewisePolynomial::clampedCubicSpline(times, points);
}

}  // namespace igms
