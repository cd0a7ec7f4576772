// Writing a generated apartment, and reading its ground truth back (for `semvox eval` and the tests).
//
// A generated apartment directory holds:
//   mesh.ply         the scanned-looking mesh (scan artefacts applied), binary, per-face label/instance/room
//   gt_mesh.ply      the clean labelled mesh (ground truth for voxel labels)
//   gt.json          rooms (polygon, type id and name, open-plan neighbours), doors, windows, objects (class
//                    and oriented box), floor and ceiling heights, the grids of the two images below
//   rooms_gt.png     16-bit room ids (0 = no room) on a 0.05 m grid, row 0 = largest y
//   topview_gt.png   16-bit NYU40 label seen from above in the height band (0 = empty), same grid
//   preview.png      the two images above in colour, for people
//   cloud.ply        (optional) the simulated fused point cloud with per-point label/instance/room
#pragma once

#include <string>
#include <vector>

#include "core/image.h"
#include "core/status.h"
#include "scenegen/apartment.h"
#include "scenegen/scan_artefacts.h"

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

struct GroundTruthOptions {
  double resolution_m = 0.05;        // Grid of rooms_gt.png and topview_gt.png, metres. > 0.
  double margin_m = 0.5;             // Margin around the apartment's bounds, metres. >= 0.
  double band_min_above_floor_m = 0.1;  // Height band of the top view (as the occupancy map's), metres.
  double band_max_above_floor_m = 1.8;
  bool Check(std::string* error) const;
};

FloorGrid MakeFloorGrid(const Apartment& apartment, const GroundTruthOptions& options);
// Room ids at pixel centres inside each room's clear interior.
ImageU16 RasterizeRooms(const Apartment& apartment, const FloorGrid& grid);
// Value of topview_gt.png pixels covered by a solid whose inside no scanner can see within the height
// band (the core of a wall, the body of a wardrobe whose top is above the band): not scored.
inline constexpr uint16_t kTopViewHidden = 65535;
// NYU40 label of the highest solid in the height band above each pixel centre (0 = empty), or
// kTopViewHidden where no surface of the clean mesh passes through the pixel's column within the band.
ImageU16 RasterizeTopView(const Apartment& apartment, const FloorGrid& grid, const GroundTruthOptions& options);

// A colour picture of the ground truth for people: rooms tinted by type, the top view in NYU40 colours,
// scaled up `scale` times.
ImageRgb8 RenderPreview(const Apartment& apartment, const ImageU16& rooms, const ImageU16& topview, int scale);

// gt.json text (deterministic).
std::string GroundTruthJson(const Apartment& apartment, const FloorGrid& grid, const GroundTruthOptions& gt_options,
                            const ApartmentOptions& options, const ScanArtefactOptions& artefacts, bool with_cloud);

// Writes mesh.ply (with artefacts), gt_mesh.ply, gt.json, rooms_gt.png and topview_gt.png into `dir`.
Status WriteApartment(const std::string& dir, const Apartment& apartment, const ApartmentOptions& options,
                      const ScanArtefactOptions& artefacts, const GroundTruthOptions& gt_options, bool with_cloud);

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
