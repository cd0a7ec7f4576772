// Doors and windows found in the walls by their geometry (library semvox_objects).
//
//   std::vector<WallOpening> openings = FindWallOpenings(map.grid, floor_z, top_z, WallOpeningOptions{});
//   for (const WallOpening& o : openings) ... o.nyu40 (door 8, window 9), o.voxels (grid indices)
//
// A door or window lies in a wall: the per-view classifiers can tell it only by colour, and the object
// segments never see it (its voxels are wall columns), so on a scan whose colours the classifiers never
// learnt (a real scan) it comes out wall. Its shape says more. Seen from the room, an opening is a
// rectangle of the wall where the surface lies behind the wall's face (a window pane or a closed door in
// the middle of the wall's thickness, the reveal around it) or is missing (the view goes through an open
// door into the next room, or through glass the scanner did not record), framed by the wall's face on both
// sides and above. A door reaches the floor and ends 1.6-2.5 m up; a window starts above the floor.
//
// Walls are found along the grid's axes: run it on the canonical frame (mapping/scene_frame.h: walls along
// x and y), where the scan's dominant wall directions are the axes. For each of the four directions a
// wall can face, rows of voxels whose room-side neighbour is free (wall faces) are counted and the rows with
// at least `min_face_m2` of face are wall lines. Each wall line gets an elevation image (along the wall x
// height): per cell, whether the first surface behind the line is at the face, recessed by 1 cell or more
// (up to `max_recess_m`), missing (free space past the face: a hole), or hidden by something standing in
// front (up to `front_m` before the face). Connected recessed-or-missing regions that are rectangular
// (`min_fill` of their box, cells hidden by furniture not counted), framed by the face on both sides and
// above (`min_frame_share` of the cells the scan saw there, when it saw `min_frame_seen_share` of them: a
// sparse scan often misses the wall above a window), flat (`min_flat_share`) and sized like a door or a
// window become openings. The opening's voxels are
// the first surface of each recessed cell (the pane or the closed leaf) and, for a door whose opening is a
// hole, an open leaf: a thin panel standing free in front of the wall at one jamb, about as long as the
// opening is wide and as high.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/voxel_grid.h"

namespace semvox {

struct WallOpeningOptions {
  double min_face_m2 = 1.0;         // A wall line needs this much face (cells whose room side is free). > 0.
  double max_recess_m = 0.25;       // An opening's surface lies at most this far behind the wall face. > 0.
  double hole_depth_m = 0.6;        // A hole is free (or unseen) past the face and has nothing occupied up to this far behind. > max_recess_m.
  double front_m = 0.2;             // Something occupied up to this far in front of the face hides the cell. > 0.
  double pane_tolerance_m = 0.05;   // A pane's voxels lie at the opening's commonest depth, or this much in front (scan noise). >= 0.
  double pane_behind_m = 0.1;       // ... and up to this far behind a cell's first surface (a fused cloud spreads a pane over
                                    // two or three cells). >= 0.
  double min_flat_share = 0.8;      // Recessed cells within a cell of the commonest depth / all recessed cells (a flat pane). [0, 1].
  double min_fill = 0.7;            // Opening cells / cells of their box not hidden by furniture. (0, 1].
  double min_frame_share = 0.5;     // Share of the seen cells just beside and above an opening that are face (or hidden). (0, 1].
  double min_frame_seen_share = 0.25;  // ... when at least this share of those cells was seen (else not framed). [0, 1].
  double door_min_width_m = 0.5;    // Doors: width range, metres.
  double door_max_width_m = 1.5;
  double door_max_bottom_m = 0.2;   // ... bottom at most this far above the floor,
  double door_min_top_m = 1.6;      // ... top in this range above the floor.
  double door_max_top_m = 2.5;
  double window_min_width_m = 0.5;  // Windows: width range,
  double window_max_width_m = 3.5;
  double window_min_bottom_m = 0.25;  // ... bottom at least this far above the floor,
  double window_min_height_m = 0.3;   // ... at least this tall.
  bool Check(std::string* error) const;
};

struct WallOpening {
  int nyu40 = 0;         // 8 door, 9 window.
  int axis = 0;          // 0: the wall runs along x (faces +y or -y); 1: along y (faces +x or -x).
  int facing = 1;        // +1 or -1: the room lies on this side of the wall, along the other axis.
  int line = 0;          // Grid row (axis 0: y index) or column (axis 1: x index) of the wall's face.
  int along0 = 0, along1 = 0;  // Cell range along the wall (inclusive).
  int z0 = 0, z1 = 0;          // Cell range in z (inclusive).
  bool open_leaf = false;      // A door whose leaf stands open in front of the wall.
  std::vector<uint32_t> voxels;  // Occupied grid indices of the pane / leaf, ascending.
  double width_m(double res) const { return (along1 - along0 + 1) * res; }
};

// Openings of the occupied / free / unknown grid, floor at floor_z; cells above top_z (the ceiling's
// underside, or the scan's top) are not looked at. Deterministic, in the order of direction, line, then
// position along the wall.
std::vector<WallOpening> FindWallOpenings(const VoxelGrid& grid, double floor_z, double top_z, const WallOpeningOptions& options = {});

}  // namespace semvox
