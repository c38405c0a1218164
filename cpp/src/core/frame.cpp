#include "mereo/core/frame.hpp"

#include "mereo/core/error.hpp"

namespace mereo {

namespace {
std::string size_text(int rows, int cols) {
  return std::to_string(cols) + "x" + std::to_string(rows);
}
}  // namespace

void Frame::validate() const {
  const std::string where = !source.empty() ? source : !id.empty() ? "frame " + id : std::string("the frame");
  if (depth.empty()) throw InputError(where + ": the frame has no depth image");
  if (const std::string p = intrinsics.problem(depth.cols(), depth.rows()); !p.empty())
    throw InputError(where + ": intrinsics: " + p);
  if (!color.empty() && !color.same_size(depth))
    throw InputError(where + ": colour is " + size_text(color.rows(), color.cols()) +
                     " but depth is " + size_text(depth.rows(), depth.cols()));
  if (!cloud.empty() && !cloud.same_size(depth))
    throw InputError(where + ": cloud is " + size_text(cloud.rows(), cloud.cols()) +
                     " but depth is " + size_text(depth.rows(), depth.cols()));
  if (!labels.empty() && !labels.same_size(depth))
    throw InputError(where + ": labels are " + size_text(labels.rows(), labels.cols()) +
                     " but depth is " + size_text(depth.rows(), depth.cols()));
}

}  // namespace mereo
