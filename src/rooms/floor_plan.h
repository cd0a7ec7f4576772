// Floor plan: the occupancy grid's cells classified for room segmentation.
//
//   VoxelGrid + OccupancyMap --FloorPlanFromVoxels--> FloorPlan     (semvox run: 3D cues available)
//   grey 2D map image        --FloorPlanFromImage---> FloorPlan     (semvox rooms: a plain 2D map)
//
// A cell is free floor, a door opening, clutter (furniture: an obstacle that does not reach the ceiling,
// or in a 2D map a small obstacle island), a wall, or unknown. Door openings are the 3D cue a 2D map
// lacks: a free cell in a narrow gap (at most door_max_width_m across) with a lintel above it, i.e.
// occupied voxels between door_min_height_m and just below the ceiling while the slab below is free.
// A ceiling step between two large ceiling zones (an open kitchen under a lowered ceiling) is a room
// border too, the other 3D cue. The grid is the occupancy grid: pixel (x, y) with row 0 at the largest world y, origin = world
// position of the lower-left corner of the lower-left pixel (map_server convention).
#pragma once

#include <cstdint>
#include <string>

#include "core/image.h"
#include "core/option_table.h"
#include "core/status.h"
#include "core/voxel_grid.h"
#include "mapping/occupancy_map.h"

namespace semvox {

enum class FloorCell : uint8_t {
  kUnknown = 0,  // Never observed (outside the apartment, inside walls, under furniture).
  kFree = 1,     // Free floor in the mid-height slab.
  kDoor = 2,     // Free floor on a room border: a door opening (under a lintel, between walls) or a
                 // ceiling step between two ceiling zones.
  kClutter = 3,  // Furniture: occupied in the slab but not a wall; belongs to the room around it.
  kWall = 4,     // Occupied from the slab up to the ceiling (or any obstacle of a 2D map).
};

struct FloorPlan {
  Image<uint8_t> cells;       // One FloorCell per occupancy pixel (1 channel).
  ImageF32 ceiling_height_m;  // Ceiling height above the floor per cell, metres; 0 where unknown.
  double resolution_m = 0.05; // Cell edge, metres.
  double origin_x = 0;        // World position of the lower-left pixel's lower-left corner, metres.
  double origin_y = 0;
  double floor_z = 0;         // Metres, input frame (0 for 2D maps).
  size_t ceiling_step_cells = 0;  // Door cells that mark a ceiling step rather than a lintel.

  int width() const { return cells.width; }
  int height() const { return cells.height; }
  FloorCell at(int x, int y) const { return FloorCell(cells.at(x, y)); }
  // Free floor or door: the cells that get a room id in rooms.png.
  bool IsFloor(int x, int y) const {
    const FloorCell c = at(x, y);
    return c == FloorCell::kFree || c == FloorCell::kDoor;
  }
  size_t Count(FloorCell kind) const;
};

struct FloorPlanOptions {
  double door_min_width_m = 0.55;
  // >= door_min_width_m. 2.6 since 2026-12-04 (was 1.3): sliding doors of real flats (R2V plans: 31 % of the
  // doors wider than 1.3 m, balcony doors mostly 1.4-1.9 m, up to 2.5) are door openings with a lintel too;
  // chosen on R2V training plans 250-269 (docs/rooms.md). Lintel detection only: 2D maps are not affected.
  double door_max_width_m = 2.6;
  double door_min_height_m = 1.85;
  double lintel_ceiling_gap_m = 0.15;
  double wall_min_height_m = 2.2;         // Taller than wardrobes and doors.
  double ceiling_step_m = 0.25;
  double ceiling_zone_min_area_m2 = 2.0;  // Not a lamp or a lintel.
  double clutter_max_area_m2 = 1.0;
  double clutter_max_length_m = 1.0;      // Furniture, not wall fragments.
  int free_threshold = 250;               // As the ipa benchmark.

  // The fields users set (section `rooms`): meaning, unit and range.
  static const OptionTable<FloorPlanOptions>& Options() {
    using O = FloorPlanOptions;
    static const OptionTable<O> table = {
        OptionNumber(&O::door_min_width_m, "door_min_width_m", 0.1, 10, "metres", "narrowest door opening"),
        OptionNumber(&O::door_max_width_m, "door_max_width_m", 0.1, 10, "metres",
                     "widest door opening (lintel detection)"),
        OptionNumber(&O::door_min_height_m, "door_min_height_m", 0.5, 10, "metres",
                     "lowest lintel underside above the floor"),
        OptionNumber(&O::lintel_ceiling_gap_m, "lintel_ceiling_gap_m", 0, 5, "metres",
                     "a lintel ends at least this far below the ceiling"),
        OptionNumber(&O::wall_min_height_m, "wall_min_height_m", 0.5, 10, "metres",
                     "obstacles reaching this high are walls, not furniture"),
        OptionNumber(&O::ceiling_step_m, "ceiling_step_m", 0, 5, "metres",
                     "a ceiling height change this large between two ceiling zones is a room border (0 = off)"),
        OptionNumber(&O::ceiling_zone_min_area_m2, "ceiling_zone_min_area_m2", 0, 1000, "m2",
                     "... when both zones cover this area"),
        OptionNumber(&O::clutter_max_area_m2, "clutter_max_area_m2", 0, 100, "m2",
                     "2D maps: obstacle islands up to this area are furniture"),
        OptionNumber(&O::clutter_max_length_m, "clutter_max_length_m", 0, 100, "metres",
                     "2D maps: ... and up to this bounding-box diagonal"),
        OptionNumber(&O::free_threshold, "free_threshold", 0, 254, "", "2D maps: grey values above this are free"),
    };
    return table;
  }
  bool Check(std::string* error) const;
};

// From a voxel map and its top-view occupancy (same x/y grid): free cells of the slab, walls and
// clutter by their height, door openings by their lintels, and the ceiling height per cell.
FloorPlan FloorPlanFromVoxels(const VoxelGrid& grid, double floor_z, double ceiling_z, const OccupancyMap& occupancy,
                              const FloorPlanOptions& options);

// From a grey 2D map (values > free_threshold free, the rest obstacles) at `resolution_m` per pixel.
// Obstacle islands not touching the map's border, no larger than clutter_max_area_m2 and no longer than
// clutter_max_length_m become clutter: chairs and tables, not the pieces of a broken wall.
FloorPlan FloorPlanFromImage(const Image<uint8_t>& grey, double resolution_m, const FloorPlanOptions& options);

// Reads a map image (PNG, PGM, ...; colour and alpha are converted to grey) for FloorPlanFromImage.
Result<Image<uint8_t>> ReadGreyMap(const std::string& path);

}  // namespace semvox
