// Internal: tracked objects as JSON values (nlohmann), for the report node; the public
// interface (tracking.hpp) gives them as text.
#pragma once

#include "matching/json.hpp"
#include "mereo/cognitive/tracking.hpp"

namespace mereo::cognitive::detail {

/// The tracks a frame's result reports (probability at least `report`), in their order: the
/// result's object ids are their indices here.
std::vector<const Track*> reported_tracks(const std::vector<Track>& tracks, double report);

/// The "objects" array of a frame's result from its tracks (see objects_json).
matching::detail::Json tracks_to_json(const std::vector<Track>& tracks, const Pose& camera_to_world, double report);

}  // namespace mereo::cognitive::detail
