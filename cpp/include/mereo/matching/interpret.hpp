// mereo/matching/interpret.hpp: from the lattice of hypotheses to the objects a frame is taken to
// hold (the judgement step), and the frame's result as one JSON line (the contract of DESIGN.md).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "mereo/core/frame.hpp"
#include "mereo/core/options.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/knowledge/model.hpp"
#include "mereo/matching/match.hpp"

namespace mereo::matching {

/// One object hypothesis of the result: a concept with the segments of its present parts.
struct RecognizedObject {
  int id = 0;                      ///< index in the result's list
  std::string model;               ///< the concept's name ("mug")
  std::vector<std::string> is_a;   ///< the concepts it specializes, nearest first ({"container"})
  std::string modality;            ///< its part set, for a concept with alternatives ("conical"); else ""
  double score = 0.0;              ///< the hypothesis's score (eq. 5.5)
  double posterior = 0.0;          ///< P(concept | evidence)
  std::vector<std::pair<std::string, int>> parts;  ///< role -> segment index, present parts only
  bool accepted = false;           ///< part of the frame's interpretation
  std::vector<int> excludes;       ///< ids of the listed objects that share a segment with it
  int hypothesis = -1;             ///< index into Lattice::hypotheses
  double coverage = -1;            ///< its parts' share of its region (explain_regions; -1: not checked)
  std::string rejected;            ///< why a hypothesis that won its segments is not accepted
  /// An object of model "unknown" (explain_regions): a region above the table that no accepted
  /// object explains.
  struct Region {
    std::array<int, 4> box{};      ///< u0, v0, u1, v1 (inclusive)
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  ///< camera frame, metres
    Eigen::Vector3d size = Eigen::Vector3d::Zero();      ///< extent along the table's x, y and up
    std::vector<int> indices;      ///< its pixels, v * width + u, sorted (the JSON gives their number)
  };
  std::optional<Region> region;
};

struct InterpretOptions {
  double min_score = 0.5;          ///< hypotheses below are not accepted
  double min_posterior = 0.5;      ///< nor below this posterior
  double list_score = 0.3;         ///< alternatives at or above this are listed (not accepted)
  // explain_regions (explain.hpp), when the node has the frame's cloud and support plane:
  double min_coverage = 0.5;       ///< an accepted object's parts' least share of its region
  /// ... or, counting the pixels near its parts' surfaces (surface_tolerance, surface_normal_deg)
  /// with theirs, this share (wavy stereo depth leaves a body's inliers sparse). Rendered stereo
  /// seeds 6000-6099: most true objects explain 0.74-1.0 so, cylinders on free-form distractors
  /// 0.28-0.77; real Kinect frames (mOSD) 0.41-0.8 with inliers covering over half.
  double min_surface_coverage = 0.7;
  /// ... of an object made of free-form regions only (they are whole regions: true bottles
  /// explain 0.97-1.0 of theirs on rendered and real frames, a drill's grip cut off at a
  /// silhouette 0.54)
  double min_free_form_coverage = 0.9;
  double depth_jump = 0.02;        ///< neighbours further apart in depth (times it) are not connected
  double reach = 0.02;             ///< a region reaches this far (metres) beyond its object's extent
  /// A region's pixel within this of the surface of one of the object's axial (within its
  /// extent), spherical or toroidal parts is near it (min_surface_coverage). Metres at 1 m,
  /// growing with depth squared up to twice that.
  double surface_tolerance = 0.006;
  /// ... or this times the part's own fit residual (its inliers' RMS), where that is larger: the
  /// noise the part was fitted in (stereo depth beyond a metre is noisier than the tolerance)
  double surface_residual_factor = 3.0;
  /// ... and, where the frame has normals, its normal within this of the part's (degrees): the
  /// flat face of a rounded box beside a cylinder fitted to its rounded edge is none.
  double surface_normal_deg = 45;
  /// A region's pixel seen through the opening of an upright outer cylinder among the object's
  /// parts (below its rim, within its radius; explain.cpp: inside_opening) counts as explained:
  /// a mug's inside is its own where no inner wall was fitted to it.
  bool open_tops = true;
  int min_unknown_pixels = 800;    ///< unexplained regions this big are unknown objects (0: none)
  /// With normals: pixels seen at more than this angle to their ray (an object's silhouette,
  /// where it meets what lies behind it without a depth jump) join no unknown region.
  double max_grazing_deg = 75;
  /// Two hypotheses of one concept at the same place (Lattice::same_place: a chair whose seat and
  /// back were each found in two pieces) are one object: only the first is accepted. Off for
  /// small objects that stand close (two mugs touching), on in the room graph.
  bool one_per_place = false;

  /// The options of the report node.
  static const Fields<InterpretOptions>& fields();
};

inline const Fields<InterpretOptions>& InterpretOptions::fields() {
  using O = InterpretOptions;
  static const Fields<O> f = {
      field("min_score", &O::min_score, 0, 1, "hypotheses below this score are not accepted"),
      field("min_posterior", &O::min_posterior, 0, 1, "nor below this posterior"),
      field("list_score", &O::list_score, 0, 1, "alternatives at or above this are listed"),
      field("min_coverage", &O::min_coverage, 0, 1, "an object's parts' least share of its region"),
      field("min_surface_coverage", &O::min_surface_coverage, 0, 1,
            "... or with the pixels near its parts' surfaces, this share"),
      field("min_free_form_coverage", &O::min_free_form_coverage, 0, 1,
            "the least share of an object made of free-form regions"),
      field("depth_jump", &O::depth_jump, 0.001, 1, "a depth step (times the depth) that separates regions"),
      field("reach", &O::reach, 0, 1, "a region's reach beyond its object's extent, metres"),
      field("surface_tolerance", &O::surface_tolerance, 0, 1,
            "a region's pixels this near an object's part (metres at 1 m) are explained by it"),
      field("surface_residual_factor", &O::surface_residual_factor, 0, 100,
            "... or this times the part's fit residual, where that is larger"),
      field("surface_normal_deg", &O::surface_normal_deg, 0, 90,
            "... with normals within this of the part's (degrees)"),
      field("open_tops", &O::open_tops,
            "a region's pixels seen through the opening of an upright cylinder among the parts are explained by it"),
      field("min_unknown_pixels", &O::min_unknown_pixels, 0, 1e7, "least pixels of an unknown object (0: none)"),
      field("max_grazing_deg", &O::max_grazing_deg, 0, 90, "with normals: pixels seen more obliquely join no unknown region"),
      field("one_per_place", &O::one_per_place, "hypotheses of one concept at the same place are one object"),
  };
  return f;
}

/// The interpretation of a frame: hypotheses are accepted greedily, one per set of segments,
/// preferring those that explain more segments (a mug, body and handle, over a cup on the same
/// body), then the higher score, then the more specific concept (narrower attribute ranges: a
/// can over a jar), then the lattice's order; a hypothesis that shares a segment
/// with an accepted one is an alternative. Accepted objects come first (best first), then the
/// alternatives above options.list_score. Deterministic.
std::vector<RecognizedObject> interpret(const knowledge::KnowledgeBase& kb, const Lattice& lattice,
                                        const InterpretOptions& options = {});

/// The result of one frame as one JSON object (no newline), as in DESIGN.md's contract:
/// {"frame", "source", "objects": [{"id", "model", "score", "posterior", "accepted", "parts":
/// {role: {...}}, "excludes"}], "primitives": [...], "support_plane": {...} (when given),
/// "timing_ms": {...} (when given)}.
std::string result_json(const Frame& frame, const std::vector<Segment>& segments,
                        const std::vector<RecognizedObject>& objects,
                        const extension::SupportPlane* plane = nullptr,
                        const std::vector<std::pair<std::string, double>>& timing_ms = {});

/// One segment's parameters as a JSON object (class-specific fields, see DESIGN.md).
std::string segment_json(const Segment& s);

}  // namespace mereo::matching
