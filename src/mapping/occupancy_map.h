// Top-view occupancy in ROS map_server format, on the voxel grid's x/y cells, in the input's frame.
#pragma once

#include <string>

#include "core/image.h"
#include "core/option_table.h"
#include "core/status.h"
#include "core/voxel_grid.h"

namespace semvox {

struct OccupancyOptions {
  double band_min_above_floor_m = 0.1;
  double band_max_above_floor_m = 1.8;  // > band_min_above_floor_m.
  double occupied_thresh = 0.65;        // Written to the YAML (map_server semantics).
  double free_thresh = 0.196;           // Written to the YAML (map_server semantics).

  // The fields users set (section `occupancy`): meaning, unit and range.
  static const OptionTable<OccupancyOptions>& Options() {
    using O = OccupancyOptions;
    static const OptionTable<O> table = {
        OptionNumber(&O::band_min_above_floor_m, "band_min_above_floor_m", -10, 10, "metres",
                     "height band bottom above the floor"),
        OptionNumber(&O::band_max_above_floor_m, "band_max_above_floor_m", -10, 10, "metres",
                     "height band top above the floor"),
    };
    return table;
  }
  bool Check(std::string* error) const;
};

// map_server pixel values for trinary maps with negate = 0.
inline constexpr uint8_t kPgmOccupied = 0, kPgmFree = 254, kPgmUnknown = 205;

struct OccupancyMap {
  ImageRgb8 image;        // 1 channel; row 0 = largest y (top of the map).
  double resolution = 0;  // Metres per pixel (the voxel size).
  double origin_x = 0;    // World position of the lower-left pixel's lower-left corner.
  double origin_y = 0;
  double origin_yaw = 0;  // Radians: the map's turn about +Z in the frame of origin_x / origin_y (map_server's
                          // third origin value); non-zero when the map is on a canonical grid turned against
                          // the input frame (mapping/scene_frame.h).
};

// A column is occupied when any voxel in the band is occupied, free when any is free, unknown otherwise.
OccupancyMap ComputeOccupancy(const VoxelGrid& grid, double floor_z, const OccupancyOptions& options);

// Writes `<stem>.pgm` and `<stem>.yaml` into `dir` atomically.
Status WriteOccupancyMap(const OccupancyMap& map, const std::string& dir, const std::string& stem);

// Reads a map_server map back (for tests and `semvox eval`).
Result<OccupancyMap> ReadOccupancyMap(const std::string& yaml_path);

}  // namespace semvox
