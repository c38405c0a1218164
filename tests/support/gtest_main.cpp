// The main of the library's GoogleTest binaries: registers the library's port types and node
// kinds, as a C++ program does before it builds a graph, then runs the tests.
#include <gtest/gtest.h>

#include "mereo/nodes/builtin.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  mereo::nodes::register_builtin();
  return RUN_ALL_TESTS();
}
