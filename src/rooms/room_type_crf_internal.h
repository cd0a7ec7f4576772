// Helpers shared by the room-type CRF's source files (room_type_model.cc, room_type_graph.cc,
// room_type_inference.cc, room_type_learning.cc, room_type_render.cc); not part of the public API.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <vector>

#include "rooms/room_type_crf.h"

namespace semvox::room_type_internal {

using Dist = std::array<double, kRoomTypeLabels>;

inline Dist Uniform() {
  Dist d;
  d.fill(1.0 / kRoomTypeLabels);
  return d;
}

inline int ArgMax(const Dist& d) { return int(std::max_element(d.begin(), d.end()) - d.begin()); }

inline double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Pixels (indices) covered by one view's cone: rays over the field of view, marched in half-pixel steps from
// the camera, stopped by walls, unknown cells and the plan's border (2D ray casting on the plan). `stamp`
// (one entry per plan pixel) marks the pixels already taken with `tag`.
void ConePixels(const FloorPlan& plan, const ViewRoomEvidence& v, std::vector<uint32_t>* stamp, uint32_t tag,
                std::vector<int>* out);

// The 4 events of Eq. 6: 0 same type & same segment, 1 different & same, 2 same & different segment, 3 both different.
inline int Event(bool same_type, bool same_segment) { return same_segment ? (same_type ? 0 : 1) : (same_type ? 2 : 3); }

// Per-neighbour difference between the same-type and different-type pair potential (the only part of the pair
// term a node's conditional depends on), times w_hom / normaliser.
std::vector<std::vector<float>> PairDeltas(const RoomTypeEnergy& e);

}  // namespace semvox::room_type_internal
