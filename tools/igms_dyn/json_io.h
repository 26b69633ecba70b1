// Small JSON helpers for igms-dyn: doubles printed with %.17g (round-trip
// exact), and checked reading of number arrays from parsed input lines.
#pragma once

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "core/model/data.h"

namespace igms::dyn {

// Thrown for a malformed input line; the message becomes {"error": ...}.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A JSON object written field by field, numbers at full precision.
class JsonWriter {
 public:
  JsonWriter& key(const std::string& k);
  JsonWriter& number(double x);
  JsonWriter& string(const std::string& s);
  JsonWriter& integer(long long x);
  JsonWriter& vector(const VectorX& x);
  JsonWriter& vector(const double* x, int n);
  JsonWriter& matrix(const MatrixX& M);
  JsonWriter& beginObject();
  JsonWriter& endObject();
  JsonWriter& beginArray();
  JsonWriter& endArray();
  JsonWriter& raw(const std::string& text);
  const std::string& str() const { return out_; }

 private:
  void separate();
  std::string out_;
  bool need_comma_ = false;
};

std::string quote(const std::string& s);

// The array at key `name` as exactly n finite numbers.
VectorX readVector(const nlohmann::json& line, const char* name, int n);
Vector3 readVector3(const nlohmann::json& obj, const char* name, const std::string& where);

}  // namespace igms::dyn
