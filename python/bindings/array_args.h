// The arrays the module takes and gives. What comes in is checked before
// anything runs: its shape, and that every entry is finite (a clear ValueError
// otherwise); a float64 array is read through the buffer protocol, anything
// else (lists, ints, float32) through numpy.asarray first. What goes out is a
// new NumPy array, or a read-only view of the simulation's own storage that
// keeps the simulation alive. (The buffer protocol and numpy.empty cost about
// half of nanobind's ndarray import and export here: rnea on the UR5 is
// mostly the call.)
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cmath>
#include <cstring>
#include <initializer_list>
#include <string>

#include "core/model/tree_matrix.h"

namespace igms::python {

namespace nb = nanobind;

using VectorView = nb::ndarray<nb::numpy, const double, nb::ndim<1>>;

// numpy's functions, looked up once (never released: they live as long as the interpreter).
inline PyObject* numpyFunction(const char* name) {
  nb::object f = nb::module_::import_("numpy").attr(name);
  return f.release().ptr();
}

// Anything numpy.asarray reads as an array of real numbers (lists, tuples, ints, float32), as float64;
// complex, boolean, text and object arrays raise TypeError.
inline nb::object asFloat64(nb::handle h, const char* what) {
  static PyObject* asarray = numpyFunction("asarray");
  nb::object a = nb::borrow<nb::object>(asarray)(h);
  nb::object dtype = a.attr("dtype");
  const std::string kind = nb::cast<std::string>(dtype.attr("kind"));
  if (kind != "i" && kind != "u" && kind != "f")
    throw nb::type_error((std::string(what) + ": expected an array of real numbers, got dtype " +
                          nb::cast<std::string>(nb::str(dtype)))
                             .c_str());
  return a.attr("astype")("float64");
}

// A buffer of doubles held for one read (the buffer protocol: numpy arrays without nanobind's import).
struct DoubleBuffer {
  Py_buffer view{};
  bool held = false;
  explicit DoubleBuffer(nb::handle h) {
    if (PyObject_GetBuffer(h.ptr(), &view, PyBUF_STRIDES | PyBUF_FORMAT) != 0) {
      PyErr_Clear();
      return;
    }
    held = true;
  }
  ~DoubleBuffer() {
    if (held) PyBuffer_Release(&view);
  }
  bool isDouble() const {
    if (!held || view.itemsize != 8 || !view.format) return false;
    const char* f = view.format;
    if (*f == '<' || *f == '=' || *f == '@') ++f;
    return f[0] == 'd' && f[1] == 0;
  }
  std::string shapeText() const {
    std::string s = "(";
    for (int d = 0; d < view.ndim; ++d) s += (d ? ", " : "") + std::to_string(view.shape[d]);
    return s + (view.ndim == 1 ? ",)" : ")");
  }
};

// Copies a (n,) array into out (already n long: nothing allocates), after checking its shape and that every
// entry is finite. A float64 array is read in place; anything else goes through numpy.asarray first.
inline void readVector(nb::handle h, Eigen::Index n, const char* what, VectorX& out) {
  DoubleBuffer b(h);
  if (!b.isDouble()) {
    nb::object converted = asFloat64(h, what);
    DoubleBuffer c(converted);
    if (!c.isDouble()) throw nb::type_error((std::string(what) + ": not an array of numbers").c_str());
    return readVector(converted, n, what, out);
  }
  if (b.view.ndim != 1 || b.view.shape[0] != n)
    throw nb::value_error(
        (std::string(what) + ": expected shape (" + std::to_string(n) + ",), got " + b.shapeText()).c_str());
  const char* p = static_cast<const char*>(b.view.buf);
  const Py_ssize_t stride = b.view.strides ? b.view.strides[0] : 8;
  for (Eigen::Index i = 0; i < n; ++i) {
    double x;
    std::memcpy(&x, p + i * stride, sizeof x);
    if (!std::isfinite(x))
      throw nb::value_error((std::string(what) + "[" + std::to_string(i) + "] is not finite").c_str());
    out[i] = x;
  }
}

inline Vector3 readVector3(nb::handle h, const char* what) {
  VectorX v(3);
  readVector(h, 3, what, v);
  return v;
}

// A new float64 array of the given shape, numpy's own, filled from row-major data.
inline nb::object newArray(std::initializer_list<Py_ssize_t> shape, const double* row_major) {
  static PyObject* empty = numpyFunction("empty");
  nb::object a;
  if (shape.size() == 1) {
    a = nb::borrow<nb::object>(empty)(*shape.begin());
  } else {
    a = nb::borrow<nb::object>(empty)(nb::make_tuple(shape.begin()[0], shape.begin()[1]));
  }
  Py_buffer view;
  if (PyObject_GetBuffer(a.ptr(), &view, PyBUF_C_CONTIGUOUS | PyBUF_WRITABLE) != 0) throw nb::python_error();
  std::memcpy(view.buf, row_major, static_cast<size_t>(view.len));
  PyBuffer_Release(&view);
  return a;
}

inline nb::object newVector(const double* p, size_t n) { return newArray({static_cast<Py_ssize_t>(n)}, p); }

template <typename Matrix>
nb::object newMatrix(const Matrix& m) {
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = m;
  return newArray({static_cast<Py_ssize_t>(m.rows()), static_cast<Py_ssize_t>(m.cols())}, rows.data());
}

// A pose as the 4 x 4 homogeneous matrix (world <- frame).
template <typename Pose>
nb::object newPose(const Pose& X) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = X.R;
  T.topRightCorner<3, 1>() = X.p;
  return newMatrix(T);
}

}  // namespace igms::python
