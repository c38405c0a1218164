// mereo/cognitive/relations.hpp: scene relations between a frame's objects (the accepted ones and
// the unknown regions that no model explains) and the surface that carries them, the method's top
// layer: which object stands on what (`on`: the support surface, or another object, a cup on a
// plate), which stand side by side on the same thing (`next_to`) and which stands between the
// camera and another (`in_front_of`).
//
// Each object is placed by its parts' shapes: its lowest and highest points above the support
// (a shape's half extent along the support's normal about its origin) and its footprint (the
// body's axis or centre dropped onto the support, and its half extent across). A is on B when
// A's lowest point lies within on_gap of B's top and A's footprint centre within B's footprint;
// else on the support when its lowest point lies within on_gap of the surface. The result's
// JSON lists them as {"relation": "on", "subject": 3, "object": 0}, the support surface named
// "support_plane" (the result's key for it).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mereo/core/segment.hpp"

namespace mereo::cognitive {

struct RelationOptions {
  /// A resting object's lowest point lies within this of what carries it, metres (the fitted
  /// extent of a body seen from above stops short of its foot by a few millimetres; stereo noise).
  double on_gap = 0.03;
  /// Two objects on the same thing whose footprints are at most this far apart are next to each
  /// other, metres.
  double next_to_gap = 0.10;
};

/// An accepted object as the relations see it: its id in the result and its parts' segments
/// (camera frame), or, for an object without shaped parts (an "unknown" region), its box: centre
/// and size along the support's x, y and up.
struct PlacedObject {
  int id = 0;
  std::vector<Segment> parts;  ///< the body first, when the object has one
  std::optional<Eigen::Vector3d> box_centre, box_size;
};

/// A relation between two accepted objects; object = kSupport: the support surface.
struct Relation {
  static constexpr int kSupport = -1;
  std::string relation;  ///< "on", "next_to", "in_front_of"
  int subject = 0, object = 0;
  bool operator==(const Relation& o) const {
    return relation == o.relation && subject == o.subject && object == o.object;
  }
};

/// The frame's scene relations, about the support plane normal.dot(x) + d = 0 (normal up,
/// towards the camera); the camera is at the origin. next_to is listed once per pair (subject <
/// object). Throws InputError for a normal that is not a unit vector.
std::vector<Relation> scene_relations(const std::vector<PlacedObject>& objects, const Eigen::Vector3d& normal,
                                      double d, const RelationOptions& o = {});

}  // namespace mereo::cognitive
