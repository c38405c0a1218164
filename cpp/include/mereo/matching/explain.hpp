// mereo/matching/explain.hpp: an accepted object must explain the surface it stands for. A
// cylinder fitted to a band of a squeeze bottle, or a sphere to the corner of a box, is a good
// primitive of a small part of a free-form object; the object is then not a container but
// `unknown`. The check: the object's region (the pixels above the table connected to its parts'
// pixels without a depth jump, over its footprint on the table, not what it stands on) must be
// mostly its parts' pixels (an object of free-form regions takes no pixels from the others'
// regions). Two objects do not fill one place: the weaker of two there goes.
// What no accepted object explains and lies in no accepted object's place is reported as unknown
// objects with their region and size: the free-form regions that models of free-form objects are
// matched to (features/regions.hpp, the find_regions node).
#pragma once

#include <vector>

#include "mereo/core/image.hpp"
#include "mereo/core/segment.hpp"
#include "mereo/extension/support_plane.hpp"
#include "mereo/matching/interpret.hpp"

namespace mereo::matching {

/// Rejects the accepted objects of `objects` (in their order: the strongest first) that take the
/// place of an earlier one or do not explain their region (accepted = false, `rejected` says why,
/// `coverage` set on every accepted one), then appends the unexplained
/// regions of `plane.roi` as objects of model "unknown" (not accepted, with their `region`).
/// The thresholds are InterpretOptions' min_coverage (min_surface_coverage, with the pixels near a
/// part: surface_tolerance, surface_residual_factor, surface_normal_deg), depth_jump, reach and
/// min_unknown_pixels; with `normals`, the silhouettes (max_grazing_deg) separate unknown regions
/// that touch.
/// `cloud` is the frame's organized cloud; pixel indices are row-major. Deterministic.
void explain_regions(std::vector<RecognizedObject>& objects, const std::vector<Segment>& segments,
                     const Cloud& cloud, const extension::SupportPlane& plane, const InterpretOptions& options = {},
                     const NormalMap* normals = nullptr);

}  // namespace mereo::matching
