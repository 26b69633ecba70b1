#include "core/model/configuration.h"

#include <Eigen/Geometry>
#include <cmath>

namespace igms {

VectorX neutralConfiguration(const Model& model) {
  VectorX q = VectorX::Zero(model.nq);
  for (int i = 0; i < model.nb; ++i)
    if (model.joint_type[i] == JointType::Floating) q[model.q_index[i] + 3] = 1.0;
  return q;
}

VectorX randomVector(int n, std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  VectorX x(n);
  for (int i = 0; i < n; ++i) x[i] = u(rng);
  return x;
}

VectorX randomConfiguration(const Model& model, std::mt19937& rng) {
  VectorX q(model.nq);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < model.nb; ++i) {
    const int iq = model.q_index[i];
    if (model.joint_type[i] == JointType::Floating) {
      for (int k = 0; k < 3; ++k) q[iq + k] = 2.0 * unit(rng) - 1.0;
      // A normalised Gaussian 4-vector is uniform on SO(3) (Eigen's UnitRandom uses std::rand).
      std::normal_distribution<double> g;
      Eigen::Vector4d w(g(rng), g(rng), g(rng), g(rng));
      w.normalize();
      q.segment<4>(iq + 3) = w;
      continue;
    }
    const int iv = model.v_index[i];
    double lo = model.lower[static_cast<size_t>(iv)], hi = model.upper[static_cast<size_t>(iv)];
    const double span = model.joint_type[i] == JointType::Prismatic ? 0.5 : M_PI;
    if (!std::isfinite(lo) || !std::isfinite(hi) || hi <= lo) {
      lo = -span;
      hi = span;
    }
    q[iq] = lo + (hi - lo) * unit(rng);
  }
  return q;
}

RandomStates randomStates(const Model& model, int count, std::mt19937& rng, double tau_scale) {
  RandomStates s;
  for (int k = 0; k < count; ++k) {
    s.q.push_back(randomConfiguration(model, rng));
    s.v.push_back(randomVector(model.nv, rng));
    s.a.push_back(randomVector(model.nv, rng));
    s.tau.push_back(randomVector(model.nv, rng, tau_scale));
  }
  return s;
}

void integrateConfiguration(const Model& model, const VectorX& q, const VectorX& v, double dt, VectorX& q_out) {
  if (&q_out != &q) q_out = q;
  for (int i = 0; i < model.nb; ++i) {
    const int iq = model.q_index[i];
    const int iv = model.v_index[i];
    if (model.joint_type[i] != JointType::Floating) {
      q_out[iq] = q[iq] + v[iv] * dt;
      continue;
    }
    Eigen::Quaterniond quat(q[iq + 3], q[iq + 4], q[iq + 5], q[iq + 6]);
    quat.normalize();
    const Matrix3 R = quat.toRotationMatrix();
    const Vector3 lin = v.segment<3>(iv) * dt;
    const Vector3 phi = v.segment<3>(iv + 3) * dt;
    const double th = phi.norm();
    const Matrix3 W = skew(phi);
    // exp of the body twist: R_inc = exp([phi]), p_inc = V lin.
    double A, B;
    if (th < 1e-6) {
      A = 0.5 - th * th / 24.0;
      B = 1.0 / 6.0 - th * th / 120.0;
    } else {
      A = (1.0 - std::cos(th)) / (th * th);
      B = (th - std::sin(th)) / (th * th * th);
    }
    const Matrix3 V = Matrix3::Identity() + A * W + B * W * W;
    const Eigen::Quaterniond dq(Eigen::AngleAxisd(th, th > 0.0 ? Vector3(phi / th) : Vector3::UnitX()));
    const Vector3 p = Vector3(q[iq], q[iq + 1], q[iq + 2]) + R * (V * lin);
    Eigen::Quaterniond next = (quat * dq).normalized();
    q_out.segment<3>(iq) = p;
    q_out[iq + 3] = next.w();
    q_out[iq + 4] = next.x();
    q_out[iq + 5] = next.y();
    q_out[iq + 6] = next.z();
  }
}

void worldVelocityStep(const Model& model, const VectorX& v0, double h, VectorX& v) {
  for (int i = 0; i < model.nb; ++i) {
    if (model.joint_type[i] != JointType::Floating) continue;
    const int iv = model.v_index[i];
    v.segment<3>(iv) += h * v0.segment<3>(iv + 3).cross(v0.segment<3>(iv));
  }
}

void integrateContactStep(const Model& model, const VectorX& q, VectorX& v, const VectorX& v_position, double h,
                          VectorX& q_out) {
  if (&q_out != &q) q_out = q;
  for (int i = 0; i < model.nb; ++i) {
    const int iq = model.q_index[i];
    const int iv = model.v_index[i];
    if (model.joint_type[i] != JointType::Floating) {
      q_out[iq] = q[iq] + v_position[iv] * h;
      continue;
    }
    Eigen::Quaterniond quat(q[iq + 3], q[iq + 4], q[iq + 5], q[iq + 6]);
    quat.normalize();
    const Vector3 phi = v_position.segment<3>(iv + 3) * h;
    const double th = phi.norm();
    const Eigen::Quaterniond dq(Eigen::AngleAxisd(th, th > 0.0 ? Vector3(phi / th) : Vector3::UnitX()));
    const Eigen::Quaterniond next = (quat * dq).normalized();
    q_out.segment<3>(iq) = Vector3(q[iq], q[iq + 1], q[iq + 2]) + h * (quat * Vector3(v_position.segment<3>(iv)));
    q_out[iq + 3] = next.w();
    q_out[iq + 4] = next.x();
    q_out[iq + 5] = next.y();
    q_out[iq + 6] = next.z();
    v.segment<3>(iv) = dq.conjugate() * Vector3(v.segment<3>(iv));  // the same world velocity, in the turned frame
  }
}

namespace {
// [a, b] in se(3), twists ordered (linear; angular).
Vector6 bracket(const Vector6& a, const Vector6& b) {
  Vector6 out;
  out.head<3>() = a.tail<3>().cross(b.head<3>()) + a.head<3>().cross(b.tail<3>());
  out.tail<3>() = a.tail<3>().cross(b.tail<3>());
  return out;
}
}  // namespace

void configurationRate(const Model& model, const VectorX& u, const VectorX& v, VectorX& out) {
  out = v;
  for (int i = 0; i < model.nb; ++i) {
    if (model.joint_type[i] != JointType::Floating) continue;
    const int iv = model.v_index[i];
    const Vector6 ui = u.segment<6>(iv);
    const Vector6 uv = bracket(ui, v.segment<6>(iv));
    out.segment<6>(iv) += 0.5 * uv + bracket(ui, uv) / 12.0;
  }
}

void normalizeConfiguration(const Model& model, VectorX& q) {
  for (int i = 0; i < model.nb; ++i)
    if (model.joint_type[i] == JointType::Floating) {
      const int iq = model.q_index[i];
      q.segment<4>(iq + 3).normalize();
    }
}

}  // namespace igms
