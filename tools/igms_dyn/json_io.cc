#include "tools/igms_dyn/json_io.h"

#include <cmath>
#include <cstdio>

namespace igms::dyn {

std::string quote(const std::string& s) { return nlohmann::json(s).dump(); }

void JsonWriter::separate() {
  if (need_comma_) out_ += ',';
  need_comma_ = true;
}
JsonWriter& JsonWriter::key(const std::string& k) {
  separate();
  out_ += quote(k);
  out_ += ':';
  need_comma_ = false;
  return *this;
}
JsonWriter& JsonWriter::number(double x) {
  separate();
  if (!std::isfinite(x)) {  // never emit NaN: JSON has none
    out_ += "null";
    return *this;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  out_ += buf;
  return *this;
}
JsonWriter& JsonWriter::integer(long long x) {
  separate();
  out_ += std::to_string(x);
  return *this;
}
JsonWriter& JsonWriter::string(const std::string& s) {
  separate();
  out_ += quote(s);
  return *this;
}
JsonWriter& JsonWriter::raw(const std::string& text) {
  separate();
  out_ += text;
  return *this;
}
JsonWriter& JsonWriter::beginObject() {
  separate();
  out_ += '{';
  need_comma_ = false;
  return *this;
}
JsonWriter& JsonWriter::endObject() {
  out_ += '}';
  need_comma_ = true;
  return *this;
}
JsonWriter& JsonWriter::beginArray() {
  separate();
  out_ += '[';
  need_comma_ = false;
  return *this;
}
JsonWriter& JsonWriter::endArray() {
  out_ += ']';
  need_comma_ = true;
  return *this;
}
JsonWriter& JsonWriter::vector(const double* x, int n) {
  beginArray();
  for (int i = 0; i < n; ++i) number(x[i]);
  return endArray();
}
JsonWriter& JsonWriter::vector(const VectorX& x) { return vector(x.data(), static_cast<int>(x.size())); }
JsonWriter& JsonWriter::matrix(const MatrixX& M) {
  beginArray();
  for (int r = 0; r < M.rows(); ++r) {
    const VectorX row = M.row(r).transpose();
    vector(row);
  }
  return endArray();
}

namespace {
double finiteNumber(const nlohmann::json& x, const std::string& where) {
  if (!x.is_number()) throw InputError(where + " is not a number");
  const double d = x.get<double>();
  if (!std::isfinite(d)) throw InputError(where + " is not finite");
  return d;
}
}  // namespace

VectorX readVector(const nlohmann::json& line, const char* name, int n) {
  const auto it = line.find(name);
  if (it == line.end()) throw InputError(std::string("missing \"") + name + "\"");
  if (!it->is_array()) throw InputError(std::string("\"") + name + "\" must be an array");
  if (static_cast<int>(it->size()) != n)
    throw InputError(std::string("\"") + name + "\" has " + std::to_string(it->size()) + " entries, expected " +
                     std::to_string(n));
  VectorX out(n);
  for (int i = 0; i < n; ++i)
    out[i] = finiteNumber((*it)[static_cast<size_t>(i)], std::string("\"") + name + "\"[" + std::to_string(i) + "]");
  return out;
}

Vector3 readVector3(const nlohmann::json& obj, const char* name, const std::string& where) {
  const auto it = obj.find(name);
  if (it == obj.end() || !it->is_array() || it->size() != 3)
    throw InputError(where + ": \"" + name + "\" must be an array of 3 numbers");
  Vector3 out;
  for (int i = 0; i < 3; ++i)
    out[i] = finiteNumber((*it)[static_cast<size_t>(i)], where + ": \"" + name + "\"[" + std::to_string(i) + "]");
  return out;
}

}  // namespace igms::dyn
