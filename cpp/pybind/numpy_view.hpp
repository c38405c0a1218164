// Zero-copy views of mereo images as NumPy arrays (shared by the bind_*.cpp files).
#pragma once

#include <memory>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "mereo/core/image.hpp"

namespace mereo::py_util {

namespace py = pybind11;

/// An (H, W) or (H, W, C) NumPy array over the image's buffer. The array holds a reference
/// to the buffer (a capsule around a shared_ptr copy), so it stays valid on its own.
template <typename T, int C>
py::object to_numpy(const Image<T, C>& image) {
  if (image.empty()) return py::none();
  auto* keep = new std::shared_ptr<T[]>(image.buffer());
  py::capsule owner(keep, [](void* p) { delete static_cast<std::shared_ptr<T[]>*>(p); });
  std::vector<py::ssize_t> shape{image.rows(), image.cols()};
  std::vector<py::ssize_t> strides{py::ssize_t(sizeof(T)) * image.cols() * C, py::ssize_t(sizeof(T)) * C};
  if (C > 1) {
    shape.push_back(C);
    strides.push_back(sizeof(T));
  }
  return py::array(py::dtype::of<T>(), shape, strides, image.buffer().get(), owner);
}

/// Copies an (H, W) or (H, W, C) array of any numeric dtype into a new image.
template <typename T, int C>
Image<T, C> from_numpy(const py::handle& obj, const char* what) {
  auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a) throw py::type_error(std::string(what) + ": expected a NumPy array");
  const bool ok = C == 1 ? (a.ndim() == 2 || (a.ndim() == 3 && a.shape(2) == 1))
                         : (a.ndim() == 3 && a.shape(2) == C);
  if (!ok)
    throw py::value_error(std::string(what) + ": expected shape (H, W" +
                          (C == 1 ? std::string(")") : ", " + std::to_string(C) + ")"));
  Image<T, C> image(int(a.shape(0)), int(a.shape(1)));
  std::copy(a.data(), a.data() + image.size(), image.data());
  return image;
}

}  // namespace mereo::py_util
