// mereo._mereo._testing: what mereo's own Python tests need from C++ and users do not: the
// test-only node kinds of tests/support/test_nodes.hpp (identity, checksum, fail_on_frame).
#include <pybind11/pybind11.h>

#include "mereo/core/frame.hpp"
#include "support/test_nodes.hpp"

namespace py = pybind11;

void bind_testing(py::module_& m) {
  m.def("register_test_nodes", [] { mereo::test_nodes::register_test_nodes<mereo::Frame>(); },
        "Registers the test-only node kinds identity, checksum and fail_on_frame (idempotent); they "
        "are added by kind name (Graph.add('checksum', ...)), not listed in mereo.nodes.");
}
