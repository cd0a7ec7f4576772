// Ground truth as data (library semvox_dataset): the file types that `semvox generate` writes and
// `semvox eval` reads, apart from the generator, so that scoring does not link it and real datasets can
// come in the same shapes.
//
//   Result<GroundTruth> gt = ReadGroundTruth("apt_dir");   // gt.json of a generated apartment
//   FloorGrid             the raster of rooms_gt.png / topview_gt.png (and of the occupancy images)
//
// The generated apartment's directory (written by scenegen/apartment_io.h):
//   gt.json          rooms (polygon, type id and name, open-plan neighbours), doors, windows, objects (class
//                    and oriented box), floor and ceiling heights, the grids of the two images below
//   rooms_gt.png     16-bit room ids (0 = no room) on a 0.05 m grid, row 0 = largest y
//   topview_gt.png   16-bit NYU40 label seen from above in the height band (0 = empty), same grid
//   gt_mesh.ply      the clean labelled mesh (ground truth for voxel labels)
// Real scans with furniture boxes: dataset/scan_boxes.h.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/status.h"

namespace semvox {

// An axis-aligned raster on the floor plane: pixel (c, r) covers x in [origin_x + c*res, +res) and
// y in [origin_y + (height-1-r)*res, +res) (row 0 = largest y, as map_server images).
struct FloorGrid {
  double resolution = 0.05;
  double origin_x = 0, origin_y = 0;  // World position of the lower-left corner of the lower-left pixel.
  int width = 0, height = 0;
  double CenterX(int c) const { return origin_x + (c + 0.5) * resolution; }
  double CenterY(int r) const { return origin_y + (height - r - 0.5) * resolution; }
  // Pixel containing (x, y); false when outside.
  bool PixelOf(double x, double y, int* c, int* r) const;
};

// Value of topview_gt.png pixels covered by a solid whose inside no scanner can see within the height
// band (the core of a wall, the body of a wardrobe whose top is above the band): not scored.
inline constexpr uint16_t kTopViewHidden = 65535;

// gt.json's "format" field: the generator writes it, ReadGroundTruth requires it.
inline constexpr const char* kGroundTruthFormat = "semvox-apartment-gt";

// What `semvox eval` needs from a ground-truth directory.
struct GroundTruth {
  std::string dir;
  double floor_z_m = 0, ceiling_z_m = 0;
  double band_min_above_floor_m = 0.1, band_max_above_floor_m = 1.8;
  struct Room {
    int id = 0, type_id = 0;
    std::string type;
    std::vector<int> open_to;  // Open-plan partners (no wall in between).
  };
  std::vector<Room> rooms;
  FloorGrid grid;
  std::string rooms_image, topview_image, gt_mesh;  // Paths.
};
Result<GroundTruth> ReadGroundTruth(const std::string& dir);

}  // namespace semvox
