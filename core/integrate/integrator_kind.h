// The integration schemes a scene can choose, by name.
#pragma once

#include <string>

namespace igms {

enum class IntegratorKind { SemiImplicitEuler, Rk4, LinearlyImplicit };

inline const char* integratorName(IntegratorKind k) {
  switch (k) {
    case IntegratorKind::SemiImplicitEuler: return "semi_implicit_euler";
    case IntegratorKind::Rk4: return "rk4";
    case IntegratorKind::LinearlyImplicit: return "linearly_implicit";
  }
  return "?";
}

// \return false when `name` is none of the names integratorName gives.
inline bool parseIntegrator(const std::string& name, IntegratorKind* out) {
  for (IntegratorKind k : {IntegratorKind::SemiImplicitEuler, IntegratorKind::Rk4, IntegratorKind::LinearlyImplicit})
    if (name == integratorName(k)) {
      *out = k;
      return true;
    }
  return false;
}

}  // namespace igms
