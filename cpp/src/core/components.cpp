// The 4-connected components of a binary image on its runs (union-find over overlapping runs of
// adjacent rows).
#include "core/components.hpp"

#include <algorithm>
#include <cstring>

#include "mereo/core/error.hpp"

namespace mereo {
namespace {

/// The root of run i; every link points to a run of a lower index, so roots come first.
int find(std::vector<int>& parent, int i) {
  while (parent[std::size_t(i)] != i) {
    parent[std::size_t(i)] = parent[std::size_t(parent[std::size_t(i)])];  // path halving
    i = parent[std::size_t(i)];
  }
  return i;
}

void unite(std::vector<int>& parent, int a, int b) {
  a = find(parent, a), b = find(parent, b);
  if (a < b) parent[std::size_t(b)] = a;
  else if (b < a) parent[std::size_t(a)] = b;
}

/// The first pixel from u on (or n) that is zero (set = true) or nonzero (set = false), eight
/// bytes at a time through long stretches.
int skip(const std::uint8_t* m, int u, int n, bool set) {
  constexpr std::uint64_t kOnes = 0x0101010101010101ull, kHigh = 0x8080808080808080ull;
  while (u + 8 <= n) {
    std::uint64_t w;
    std::memcpy(&w, m + u, 8);
    const bool has_zero = ((w - kOnes) & ~w & kHigh) != 0;
    if (set ? has_zero : w != 0) break;
    u += 8;
  }
  while (u < n && (m[u] != 0) == set) ++u;
  return u;
}

}  // namespace

Components connected_components(const cv::Mat& mask) {
  if (mask.type() != CV_8UC1) throw InputError("connected_components: the mask must be CV_8U with one channel");
  Components c;
  c.rows = mask.rows, c.cols = mask.cols;
  std::vector<int> first_run(std::size_t(mask.rows) + 1, 0);  // runs of row v: [first_run[v], first_run[v + 1])
  for (int v = 0; v < mask.rows; ++v) {
    first_run[std::size_t(v)] = int(c.row.size());
    const std::uint8_t* m = mask.ptr<std::uint8_t>(v);
    int u = 0;
    while (u < mask.cols) {
      u = skip(m, u, mask.cols, false);
      if (u == mask.cols) break;
      const int b = u;
      u = skip(m, u, mask.cols, true);
      c.row.push_back(v), c.begin.push_back(b), c.end.push_back(u);
    }
  }
  first_run[std::size_t(mask.rows)] = int(c.row.size());

  // runs of adjacent rows that share a column are one component
  std::vector<int> parent(c.row.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = int(i);
  for (int v = 1; v < mask.rows; ++v) {
    int i = first_run[std::size_t(v - 1)], j = first_run[std::size_t(v)];
    const int i_end = first_run[std::size_t(v)], j_end = first_run[std::size_t(v + 1)];
    while (i < i_end && j < j_end) {
      const std::size_t a = std::size_t(i), b = std::size_t(j);
      if (c.begin[a] < c.end[b] && c.begin[b] < c.end[a]) unite(parent, i, j);
      if (c.end[a] < c.end[b]) ++i;
      else if (c.end[b] < c.end[a]) ++j;
      else ++i, ++j;
    }
  }
  // labels in order of each component's first run; a root precedes its runs
  c.label.resize(c.row.size());
  for (std::size_t i = 0; i < c.row.size(); ++i) {
    const int r = find(parent, int(i));
    if (r == int(i)) {
      c.label[i] = c.count();
      c.area.push_back(0);
    } else {
      c.label[i] = c.label[std::size_t(r)];
    }
    c.area[std::size_t(c.label[i])] += std::size_t(c.end[i] - c.begin[i]);
  }
  return c;
}

cv::Mat draw_components(const Components& c, const std::vector<std::uint8_t>& keep) {
  cv::Mat out(c.rows, c.cols, CV_8U, cv::Scalar(0));
  for (std::size_t i = 0; i < c.row.size(); ++i)
    if (keep[std::size_t(c.label[i])])
      std::memset(out.ptr<std::uint8_t>(c.row[i]) + c.begin[i], 255, std::size_t(c.end[i] - c.begin[i]));
  return out;
}

std::vector<std::uint8_t> components_touching(const Components& c, const cv::Mat& other) {
  if (other.type() != CV_8UC1 || other.rows != c.rows || other.cols != c.cols)
    throw InputError("components_touching: the other mask must be CV_8U of the components' size");
  std::vector<std::uint8_t> touching(std::size_t(c.count()), 0);
  for (std::size_t i = 0; i < c.row.size(); ++i) {
    std::uint8_t& t = touching[std::size_t(c.label[i])];
    if (t) continue;
    const std::uint8_t* m = other.ptr<std::uint8_t>(c.row[i]);
    t = std::any_of(m + c.begin[i], m + c.end[i], [](std::uint8_t x) { return x != 0; });
  }
  return touching;
}

}  // namespace mereo
