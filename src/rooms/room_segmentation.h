// Geometric room segmentation of a floor plan: every floor cell of the apartment gets exactly one room.
//
//   FloorPlan --SegmentRooms--> RoomSegmentation (16-bit room ids on the occupancy grid, 0 = no room)
//
// Two methods:
//  - kDistanceWatershed ("distance", the default): the distance transform D of the room space (free,
//    door and clutter cells; door openings count as obstacles so that D drops to zero across them) is
//    flooded from its maxima downwards (a watershed by union-find, cf. Najman & Couprie 2006). Where two
//    basins meet at a pass of height d (the half-width of the opening), they stay separate rooms only when
//    the pass looks like a doorway: d <= max_opening_width_m / 2, d < saddle_ratio * (the smaller basin's
//    peak), and both basins are room-sized (peak >= min_room_radius_m). Otherwise they merge.
//  - kMorphological ("morphological"), after Bormann et al., ICRA 2016, Sec. III-A: the room space is
//    eroded step by step (a 3x3 square); where the erosion splits a part in two and both pieces still
//    cover min_seed_area_m2, they become separate room seeds; the seeds then grow back over the space
//    (watershed growth). Implemented as a flood of the chessboard distance, which replays all erosion
//    levels in one pass.
// Both then merge rooms below min_room_area_m2 into the neighbour they share the longest border with, and
// give free cells the segmentation could not reach (specks cut off by furniture) the nearest room within
// max_speck_distance_m; specks farther away are outside the apartment and stay 0.
#pragma once

#include <string>
#include <vector>

#include "core/image.h"
#include "core/status.h"
#include "rooms/floor_plan.h"

namespace semvox {

enum class RoomSegmentationMethod { kDistanceWatershed, kMorphological };

// "distance", "morphological".
const char* RoomSegmentationMethodName(RoomSegmentationMethod method);
// All method names, for CLI help and config choices.
std::vector<std::string> RoomSegmentationMethodNames();
// False when `name` is not a method name.
bool ParseRoomSegmentationMethod(const std::string& name, RoomSegmentationMethod* method);

struct RoomSegmentationOptions {
  RoomSegmentationMethod method = RoomSegmentationMethod::kDistanceWatershed;
  double max_opening_width_m = 2.0;   // Widest opening that can separate two rooms (doors and the wide
                                      // openings floor plans still draw a room border across), metres. > 0.
  double saddle_ratio = 0.7;          // distance: a pass separates rooms only when narrower than this
                                      // fraction of the smaller room's inscribed radius... (0, 1].
  double saddle_ratio_larger = 0.5;   // distance: ... or than this fraction of the larger room's (a door
                                      // from a narrow corridor into a big room). (0, 1].
  double wall_gap_max_m = 2.5;        // distance: the gap from the end of a thin wall straight on to the next
                                      // obstacle is a candidate room border when at most this long, metres;
                                      // 0 = off. >= 0.
  double wall_gap_ratio = 1.0;        // distance: a wall-gap line separates rooms when its half length is
                                      // below this fraction of the smaller room's inscribed radius. > 0.
  double min_room_radius_m = 0.3;     // distance: basins with a smaller inscribed radius never stay apart
                                      // (alcoves, niches, gaps between furniture), metres. >= 0.
  double min_room_area_m2 = 0.5;      // Smaller rooms merge into a neighbour, m² (a closet is 0.5 m²). >= 0.
  double min_seed_area_m2 = 1.0;      // morphological: pieces the erosion splits apart stay separate rooms
                                      // when both still cover this area, m². > 0.
  double max_speck_distance_m = 0.5;  // Unreached free cells join the nearest room within this, metres. >= 0.
  bool fill_clutter = true;           // Treat clutter cells as room space while segmenting (they never get
                                      // an id in room_ids, only in room_extent_ids).

  bool Check(std::string* error) const;
};

struct RoomSegmentation {
  ImageU16 room_ids;         // Room id per floor cell (free or door), 0 elsewhere; ids 1..num_rooms.
  ImageU16 room_extent_ids;  // Same, plus the clutter cells inside each room (for polygons and areas).
  int num_rooms = 0;
  double seconds = 0;        // Wall time of SegmentRooms.
};

RoomSegmentation SegmentRooms(const FloorPlan& plan, const RoomSegmentationOptions& options);

}  // namespace semvox
