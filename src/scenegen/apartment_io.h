// Writing a generated apartment and its ground truth (the file types, and reading them back for `semvox eval`,
// are in dataset/ground_truth.h).
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
#include "dataset/ground_truth.h"
#include "scenegen/apartment.h"
#include "scenegen/scan_artefacts.h"

namespace semvox {

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


}  // namespace semvox
