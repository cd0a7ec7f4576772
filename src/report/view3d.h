// The interactive 3D view of report.html: the occupied voxels of voxels.ply on the canonical grid,
// packed compactly for the page and drawn there by three.js (inlined, no URL fetched).
//
//   Result<View3dVoxels> v = View3dVoxelsFromPly(ply, "OUTDIR/voxels.ply", frame);  // cells + attributes
//   View3dVoxels shown = MergeToFit(v.value(), 1000000);                          // 2x2x2 blocks until it fits
//   std::string html = View3dHtml(shown, rooms, three_js_text);                   // the page's section
//
// The view works in the canonical frame (summary.json `frame.input_from_canonical` undone, floor at z = 0, walls
// along x and y), where the voxels are the grid's axis-aligned cubes. In the page each shown voxel is a cube;
// only faces between a shown voxel and an empty or hidden cell are drawn. Colours: NYU40 display colours
// (core/labels.h), room colours as the room table's (RoomDisplayColour), confidence on a viridis ramp.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "core/ply.h"
#include "core/status.h"

namespace semvox {

// Limits of what the page can hold and draw; MergeToFit merges until all hold.
inline constexpr int kView3dMaxCellsPerAxis = 32767;             // Face corners are uint16 half-cells in the page.
inline constexpr int64_t kView3dMaxGridCells = int64_t(1) << 24;  // The page's dense occupancy grid (bytes).

struct View3dCell {
  std::array<int32_t, 3> ijk{0, 0, 0};  // Cell on the view's grid (0 .. dims - 1).
  uint16_t label = 0;                   // NYU40 id.
  float confidence = 1;                 // [0, 1].
  int32_t room = 0;                     // Room id (rooms.png), 0 = outside every room.
  uint8_t completed = 0;                // 1: never seen and inferred occupied (voxels.ply `completed`).
};

struct View3dVoxels {
  double voxel_size_m = 0;              // Edge of one cell of the view, metres (the map's voxel times `merge`).
  int merge = 1;                        // Map voxels per cell edge (1, 2, 4, ... after MergeToFit).
  size_t source_voxels = 0;             // Occupied voxels in voxels.ply.
  Eigen::Vector3d origin{0, 0, 0};      // Canonical-frame centre of cell (0, 0, 0), metres.
  std::array<int32_t, 3> dims{0, 0, 0}; // Cells along x, y, z.
  std::vector<View3dCell> cells;        // Sorted by (z, y, x), one per occupied cell.
  bool has_confidence = false, has_room = false, has_completed = false;  // Properties voxels.ply carried.
};

// Reads the vertices of a voxels.ply (x, y, z and label required; confidence, room, completed optional) into
// cells of size `voxel_size_m` (<= 0: the smallest spacing of the centres along an axis) after mapping the
// centres by `canonical_from_input`. Two centres in one cell keep the first. Errors name `name` (the file).
Result<View3dVoxels> View3dVoxelsFromPly(const PlyData& ply, const std::string& name,
                                         const Eigen::Isometry3d& canonical_from_input = Eigen::Isometry3d::Identity(),
                                         double voxel_size_m = 0);

// One level coarser: 2x2x2 blocks become one cell with the majority label and room (ties: the smaller id), the
// mean confidence and `completed` when most of the block is.
View3dVoxels MergeBlocks(const View3dVoxels& voxels);

// MergeBlocks until at most `max_cells` cells remain and the grid is within the page's limits above.
View3dVoxels MergeToFit(View3dVoxels voxels, size_t max_cells);

// The room each cell switches with (show / hide a room): its own room (voxels.ply `room`), else the room of the
// nearest column (x, y) within `reach_m` holding voxels of a room (8-connected, in whole cells; ties: the smaller
// id), else 0. voxels.ply gives walls and the furniture standing on a room's floor no room (rooms.png excludes
// occupied cells); this way they switch with the room around them.
std::vector<int32_t> RoomGroups(const View3dVoxels& voxels, double reach_m);

// A room of the room table, for the 3D view's room switches.
struct View3dRoom {
  int id = 0;
  std::string type;  // Room type name ("bedroom"); empty when unknown.
};

// The 3D view section: switches, canvas, the packed voxels as JSON and the scripts (three.js, then the view's
// own). `three_js` is the library's text (inlined as is; "</script" in it is an error at the caller).
std::string View3dHtml(const View3dVoxels& voxels, const std::vector<View3dRoom>& rooms, const std::string& three_js);

// The section when there is no view: one line saying why.
std::string View3dAbsentHtml(const std::string& reason);

// Style rules of the view (for the page's <style>).
const char* View3dCss();

// Background of the 3D canvas (rgb(233, 236, 241)); tests look for it in screenshots.
inline constexpr Rgb8 kView3dBackground{233, 236, 241};
// "Colour by seen / completed": voxels never seen and inferred occupied, and the others.
inline constexpr Rgb8 kView3dCompletedColour{226, 61, 200};
inline constexpr Rgb8 kView3dSeenColour{178, 184, 192};
// "Colour by room": voxels outside every room.
inline constexpr Rgb8 kView3dNoRoomColour{190, 190, 190};

}  // namespace semvox
