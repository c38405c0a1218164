// Reads a frame through the installed mereo library and prints what it holds.
#include <cmath>
#include <cstdio>

#include <mereo/extension/projection.hpp>
#include <mereo/io/io.hpp>

int main(int argc, char** argv) {
  const char* input = argc > 1 ? argv[1] : "synthetic:0";
  const mereo::Frame frame = mereo::io::read(input);
  const mereo::Cloud cloud = mereo::extension::back_project(frame);
  std::size_t valid = 0;
  for (std::size_t i = 0; i < cloud.pixels(); ++i) valid += std::isfinite(cloud.data()[3 * i + 2]);
  std::printf("%s: %dx%d, %zu valid points\n", input, frame.cols(), frame.rows(), valid);
  return valid > 0 ? 0 : 1;
}
