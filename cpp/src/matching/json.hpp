// Internal: the frame's result as JSON values (nlohmann), for the report node and the tracker;
// the public interface (interpret.hpp) gives them as text.
#pragma once

#include <nlohmann/json.hpp>

#include "mereo/matching/interpret.hpp"

namespace mereo::matching::detail {

using Json = nlohmann::ordered_json;  // fields in the contract's order

/// One segment's parameters (class-specific fields, see DESIGN.md).
Json segment_to_json(const Segment& s);

/// The result of one frame (see result_json).
Json result_to_json(const Frame& frame, const std::vector<Segment>& segments,
                    const std::vector<RecognizedObject>& objects, const extension::SupportPlane* plane,
                    const std::vector<std::pair<std::string, double>>& timing_ms);

}  // namespace mereo::matching::detail
