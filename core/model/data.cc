#include "core/model/data.h"

namespace igms {

Data::Data(const Model& m)
    : liMi(m.nb),
      oMi(m.nb),
      oMf(m.frames.size()),
      v(m.nb),
      a(m.nb),
      f(m.nb),
      fext(m.nb),
      tau(VectorX::Zero(m.nv)),
      bias(VectorX::Zero(m.nv)),
      Ic(m.nb),
      S_world(Matrix6X::Zero(6, m.nv)),
      H(m),
      Hfact(m),
      qdd(VectorX::Zero(m.nv)),
      rhs(VectorX::Zero(m.nv)),
      diag(VectorX::Zero(m.nv)),
      IA(m.nb),
      pA(m.nb),
      c(m.nb),
      U(Matrix6X::Zero(6, m.nv)),
      Dinv(VectorX::Zero(m.nv)),
      u(VectorX::Zero(m.nv)),
      J(Matrix6X::Zero(6, m.nv)),
      support(m.nb),
      a_cmd(m.nb),
      f_cmd(m.nb) {}

}  // namespace igms
