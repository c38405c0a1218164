// mereo's error types as Python exceptions whose message survives any bytes: a message that quotes
// a file's raw text (another encoding, a binary file) is decoded with \xNN escapes instead of
// failing with a UnicodeDecodeError traceback.
#pragma once

#include <cstring>
#include <string>

#include <pybind11/pybind11.h>

namespace mereo::py_util {

namespace py = pybind11;

/// Text from C++ as a Python str: UTF-8, any other byte as \xNN (a message may quote raw file text).
inline py::str text_to_python(const std::string& s) {
  return py::reinterpret_steal<py::str>(PyUnicode_DecodeUTF8(s.data(), Py_ssize_t(s.size()), "backslashreplace"));
}

/// Registers C++ exception type E as Python exception `name` (a subclass of `base`) in `m`.
template <class E>
void register_error(py::module_& m, const char* name, PyObject* base) {
  static py::handle type = py::exception<E>(m, name, base).release();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const E& e) {
      PyObject* text = PyUnicode_DecodeUTF8(e.what(), Py_ssize_t(std::strlen(e.what())), "backslashreplace");
      PyErr_SetObject(type.ptr(), text);
      Py_XDECREF(text);
    }
  });
}

}  // namespace mereo::py_util
