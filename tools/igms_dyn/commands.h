// The three igms-dyn commands. Each returns the process exit code.
#pragma once

#include <iosfwd>

#include "core/model/model.h"

namespace igms::dyn {

int info(const Model& model, std::ostream& out);
int eval(const Model& model, std::istream& in, std::ostream& out, std::ostream& err);
int bench(const Model& model, bool json, std::ostream& out);

}  // namespace igms::dyn
