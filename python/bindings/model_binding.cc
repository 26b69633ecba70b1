// igms.Model: a robot model from URDF (or a DH table) with its own Data, and
// the dynamics kernels on numpy arrays. Each call reads its arrays into
// preallocated vectors (checked: shape, finite) and returns a new array.
// A Model's Data is its own: one thread at a time per Model.
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>
#include <nanobind/stl/variant.h>

#include <memory>
#include <variant>

#include "core/dynamics/aba.h"
#include "core/dynamics/crba.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/rnea.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/model/configuration.h"
#include "core/model_io/model_loader.h"
#include "python/bindings/array_args.h"
#include "python/bindings/bindings.h"

namespace igms::python {

namespace {

class PyModel {
 public:
  explicit PyModel(Model model)
      : model_(std::make_shared<const Model>(std::move(model))),
        data_(*model_),
        q_(model_->nq),
        v_(model_->nv),
        a_(model_->nv),
        J_(6, model_->nv) {}

  const Model& model() const { return *model_; }

  nb::object rnea(nb::handle q, nb::handle v, nb::handle a) {
    read(q, v);
    readVector(a, model_->nv, "a", a_);
    return newVector(igms::rnea(*model_, data_, q_, v_, a_).data(), static_cast<size_t>(model_->nv));
  }
  nb::object crba(nb::handle q) {
    readVector(q, model_->nq, "q", q_);
    return newMatrix(igms::crba(*model_, data_, q_).dense());
  }
  nb::object aba(nb::handle q, nb::handle v, nb::handle tau) {
    read(q, v);
    readVector(tau, model_->nv, "tau", a_);
    if (!igms::aba(*model_, data_, q_, v_, a_)) singular();
    return newVector(data_.qdd.data(), static_cast<size_t>(model_->nv));
  }
  nb::object forwardDynamics(nb::handle q, nb::handle v, nb::handle tau) {
    read(q, v);
    readVector(tau, model_->nv, "tau", a_);
    if (!igms::forwardDynamics(*model_, data_, q_, v_, a_)) singular();
    return newVector(data_.qdd.data(), static_cast<size_t>(model_->nv));
  }
  nb::object framePlacement(nb::handle q, const std::variant<int, std::string>& frame) {
    const int f = frameOf(frame);
    readVector(q, model_->nq, "q", q_);
    forwardKinematics(*model_, data_, q_);
    return newPose(framePose(*model_, data_, f));
  }
  nb::object frameJacobian(nb::handle q, const std::variant<int, std::string>& frame) {
    const int f = frameOf(frame);
    readVector(q, model_->nq, "q", q_);
    igms::frameJacobian(*model_, data_, q_, f, J_);
    return newMatrix(J_);
  }

  int frameOf(const std::variant<int, std::string>& frame) const {
    if (const int* i = std::get_if<int>(&frame)) {
      if (*i < 0 || *i >= static_cast<int>(model_->frames.size()))
        throw nb::index_error(("frame " + std::to_string(*i) + " out of range: the model has " +
                               std::to_string(model_->frames.size()) + " frames").c_str());
      return *i;
    }
    const std::string& name = std::get<std::string>(frame);
    const int f = model_->frameIndex(name);
    if (f < 0) throw nb::key_error(("no frame '" + name + "' in " + model_->name).c_str());
    return f;
  }

 private:
  void read(nb::handle q, nb::handle v) {
    readVector(q, model_->nq, "q", q_);
    readVector(v, model_->nv, "v", v_);
  }
  [[noreturn]] void singular() const {
    throw std::runtime_error("the inertia matrix is singular at this q (dof " +
                             dofName(*model_, data_.singular_dof) + " moves no mass)");
  }

  std::shared_ptr<const Model> model_;
  Data data_;
  VectorX q_, v_, a_;
  Matrix6X J_;
};

}  // namespace

void bindModel(nb::module_& m) {
  nb::class_<PyModel>(m, "Model", "A robot model and its kernels (one thread at a time per Model).")
      .def_static(
          "from_urdf",
          [](const std::string& path, bool floating_base) {
            BuildOptions options;
            options.floating_base = floating_base;
            return new PyModel(loadModel(path, options));
          },
          nb::arg("path"), nb::arg("floating_base") = false,
          "Loads a URDF file (or a DH table, .yaml); floating_base adds a free joint at the root.")
      .def_prop_ro("name", [](const PyModel& p) { return p.model().name; })
      .def_prop_ro("nq", [](const PyModel& p) { return p.model().nq; })
      .def_prop_ro("nv", [](const PyModel& p) { return p.model().nv; })
      .def_prop_ro("joint_names", [](const PyModel& p) { return p.model().joint_name; })
      .def_prop_ro("frame_names",
                   [](const PyModel& p) {
                     std::vector<std::string> names;
                     for (const Frame& f : p.model().frames) names.push_back(f.name);
                     return names;
                   })
      .def("neutral", [](const PyModel& p) {
        const VectorX q = neutralConfiguration(p.model());
        return newVector(q.data(), static_cast<size_t>(q.size()));
      }, "The neutral configuration (zero joints; identity quaternion).")
      .def("rnea", &PyModel::rnea, nb::arg("q"), nb::arg("v"), nb::arg("a"),
           "Inverse dynamics, recursive Newton-Euler: tau = H(q) a + C(q, v) v + G(q).")
      .def("crba", &PyModel::crba, nb::arg("q"), "The joint-space inertia matrix H(q), nv x nv.")
      .def("aba", &PyModel::aba, nb::arg("q"), nb::arg("v"), nb::arg("tau"),
           "Forward dynamics by the articulated-body algorithm: qdd.")
      .def("forward_dynamics", &PyModel::forwardDynamics, nb::arg("q"), nb::arg("v"), nb::arg("tau"),
           "Forward dynamics, eq. (2) of the paper: qdd = H^-1 (tau - C v - G), by a sparse L^T D L.")
      .def("frame_placement", &PyModel::framePlacement, nb::arg("q"), nb::arg("frame"),
           "A frame's pose in the world at q, 4 x 4 homogeneous (frame: name or index).")
      .def("frame_jacobian", &PyModel::frameJacobian, nb::arg("q"), nb::arg("frame"),
           "J (6 x nv) of a frame's origin, world axes: rows [linear velocity; angular velocity].");
}

}  // namespace igms::python
