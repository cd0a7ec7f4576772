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
//    peak), and both basins are room-sized (peak >= min_room_radius_m). Otherwise they merge. A door
//    opening (door cells, under a lintel seen in 3D, and cells within 0.15 m of them) is flooded last and
//    always a border: rooms meeting there stay apart when the smaller has an inscribed radius of at least
//    door_min_room_radius_m (closets and WCs 0.6 m wide), whatever a wall-gap line through the door says.
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
#include "core/option_table.h"
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
  double max_opening_width_m = 2.0;  // Doors and the wide openings floor plans still draw a room border across.
  double saddle_ratio = 0.7;
  double saddle_ratio_larger = 0.5;  // A door from a narrow corridor into a big room.
  double wall_gap_max_m = 2.5;
  double wall_gap_ratio = 1.0;
  double min_room_radius_m = 0.3;    // Alcoves, niches and gaps between furniture never stay apart.
  double door_min_room_radius_m = 0.15;  // Behind a door opening (door cells: under a lintel) narrower rooms stay
                                         // apart: closets and WCs 0.6 m wide. >= 0; above min_room_radius_m: no effect.
  double min_room_area_m2 = 0.5;     // A closet is 0.5 m².
  double min_seed_area_m2 = 1.0;
  double max_speck_distance_m = 0.5;
  // JoinEnclosedUnknown's limit (0 = off); `semvox run` applies it after the room types.
  double max_enclosed_unknown_m2 = 2.0;
  bool fill_clutter = true;          // Treat clutter cells as room space while segmenting (they never get
                                     // an id in room_ids, only in room_extent_ids).

  // The fields users set (section `rooms`): meaning, unit and range.
  static const OptionTable<RoomSegmentationOptions>& Options() {
    using O = RoomSegmentationOptions;
    static const OptionTable<O> table = {
        OptionChoice(&O::method, "method", RoomSegmentationMethodNames(), ParseRoomSegmentationMethod,
                     "room segmentation method (distance: doorway-aware distance watershed; morphological: erosion + growth)"),
        OptionNumber(&O::max_opening_width_m, "max_opening_width_m", 0.1, 20, "metres",
                     "widest opening that separates rooms"),
        OptionNumber(&O::saddle_ratio, "saddle_ratio", 0.01, 1, "",
                     "distance: a pass separates rooms below this fraction of the smaller room's inscribed radius"),
        OptionNumber(&O::saddle_ratio_larger, "saddle_ratio_larger", 0.01, 1, "",
                     "distance: ... or of the larger room's inscribed radius"),
        OptionNumber(&O::min_room_radius_m, "min_room_radius_m", 0, 10, "metres",
                     "distance: rooms need at least this inscribed radius"),
        OptionNumber(&O::door_min_room_radius_m, "door_min_room_radius_m", 0, 10, "metres",
                     "distance: rooms that meet their neighbour only across a door opening need at least this "
                     "inscribed radius"),
        OptionNumber(&O::wall_gap_max_m, "wall_gap_max_m", 0, 20, "metres",
                     "distance: gaps from a thin wall's end straight on to an obstacle up to this long are candidate "
                     "room borders (0 = off)"),
        OptionNumber(&O::wall_gap_ratio, "wall_gap_ratio", 0.01, 100, "",
                     "distance: such a border separates rooms below this ratio of its half length to the smaller "
                     "room's inscribed radius"),
        OptionNumber(&O::min_room_area_m2, "min_room_area_m2", 0, 1000, "m2", "smaller rooms merge into a neighbour"),
        OptionNumber(&O::min_seed_area_m2, "min_seed_area_m2", 0.01, 1000, "m2",
                     "morphological: pieces split by the erosion stay rooms when both cover this"),
        OptionNumber(&O::max_speck_distance_m, "max_speck_distance_m", 0, 10, "metres",
                     "unreached free cells join the nearest room within this"),
        OptionNumber(&O::max_enclosed_unknown_m2, "max_enclosed_unknown_m2", 0, 1000, "m2",
                     "unseen pockets enclosed by one room and walls up to this join the room's extent (0 = off)"),
    };
    return table;
  }
  bool Check(std::string* error) const;
};

struct RoomSegmentation {
  ImageU16 room_ids;         // Room id per floor cell (free or door), 0 elsewhere; ids 1..num_rooms.
  ImageU16 room_extent_ids;  // Same, plus the clutter cells inside each room (for polygons and areas) and, after
                             // JoinEnclosedUnknown, the unseen pockets it encloses.
  int num_rooms = 0;
  double seconds = 0;        // Wall time of SegmentRooms.
};

RoomSegmentation SegmentRooms(const FloorPlan& plan, const RoomSegmentationOptions& options);

// Unseen pockets join the room around them: every 4-connected group of unknown cells of at most `max_area_m2`
// whose 4-neighbours are walls and the extent of one room (the floor behind a sofa or a wardrobe, a corner no
// view reached) gets that room's id in `extent_ids` and, when `pixel_types` (same size) is given, the type of
// the room's cell beside it. A pocket touching the grid's border, a free, door or clutter cell of no room, or a
// second room stays outside, and so does a larger one (an unseen alcove that may be a room of its own, a
// courtyard seen through a window) and one with no cell whose four neighbours are all in it (a wall's unseen
// inside, reached through a window or a gap in its face, one or two cells wide). Returns the cells joined; 0
// when max_area_m2 <= 0. `semvox run` calls it after the room types: a pocket holds no evidence, and its cells
// would change the room's shape features.
size_t JoinEnclosedUnknown(const FloorPlan& plan, double max_area_m2, ImageU16* extent_ids, ImageU16* pixel_types = nullptr);

}  // namespace semvox
