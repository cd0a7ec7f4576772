// Voxelisation of a scanned scene into free / occupied / unknown space (the mapping stage).
//
//   Scene --Voxelize--> VoxelMap
//
// Occupied voxels are those the surface passes through (exact triangle-box overlap for meshes, points
// splatted as small discs for clouds). Free voxels are those a scanner standing at virtual scan positions
// inside the scanned space would see through: rays are cast from each position towards every occupied
// voxel within range and stop at the first occupied voxel. Everything else stays unknown (inside walls,
// behind and under furniture, outside the apartment). Floor and ceiling are the dominant lowest / highest
// horizontal surfaces.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry.h"
#include "core/option_table.h"
#include "core/progress.h"
#include "core/status.h"
#include "core/voxel_grid.h"

namespace semvox {

struct VoxelizeOptions {
  double voxel_size_m = 0.05;  // The OctoMap resolution.
  double scan_spacing_m = 1.0;
  double scan_height_m = 1.5;  // Clamped below the ceiling.
  double scan_clearance_m = 0.3;
  double max_range_m = 10.0;
  int enclosure_directions = 16;
  double min_enclosed_fraction = 0.75;
  double horizontal_normal_deg = 10.0;
  double min_floor_to_ceiling_m = 1.8;
  size_t max_voxels = 400'000'000;  // A memory guard.
  int cloud_normal_neighbors = 12;  // For clouds without normals (PCA normals).
  bool free_space = true;           // false: surfaces, floor and ceiling only (no scan positions, no free voxels).
  // Pockets: after the grid positions have cast their rays, every region at scanner height that is clear of
  // surfaces by scan_clearance_m (a person 2 x scan_clearance_m wide fits), still unseen, and next to seen
  // free space - a closet, a WC or a hall the 1 m grid missed, glimpsed through its door - gets a position at
  // its most open cell (if it has a floor below and passes the enclosure test), and casts its rays; repeated
  // up to pocket_rounds times. The sealed inside of a closed furniture mesh borders no free space and gets
  // none.
  int pocket_rounds = 3;
  int max_pocket_positions = 64;
  // Sealed rooms: a pocket that borders no seen free space (no door of the model leads into it) still gets a
  // position when it holds at least min_sealed_room_m2 of clear cells and the first surfaces straight above and
  // below its most open cell lie within sealed_room_tolerance_m of the detected ceiling and floor (a room, not
  // the inside of a closed cabinet, whose lid is lower). Needs a found floor and ceiling; tolerance 0 = off.
  double min_sealed_room_m2 = 0.5;
  double sealed_room_tolerance_m = 0.2;

  // The fields users set (section `mapping`): meaning, unit and range.
  static const OptionTable<VoxelizeOptions>& Options() {
    using O = VoxelizeOptions;
    static const OptionTable<O> table = {
        OptionNumber(&O::voxel_size_m, "voxel_size_m", 0.005, 1.0, "metres", "voxel edge"),
        OptionNumber(&O::scan_spacing_m, "scan_spacing_m", 0.05, 100, "metres", "spacing of virtual scan positions"),
        OptionNumber(&O::scan_height_m, "scan_height_m", 0.1, 10, "metres", "scanner height above the floor"),
        OptionNumber(&O::scan_clearance_m, "scan_clearance_m", 0, 5, "metres", "free radius around a scan position"),
        OptionNumber(&O::max_range_m, "max_range_m", 0.1, 1000, "metres", "scanner range"),
        OptionNumber(&O::enclosure_directions, "enclosure_directions", 4, 360, "",
                     "horizontal rays testing that a position is indoors"),
        OptionNumber(&O::min_enclosed_fraction, "min_enclosed_fraction", 0, 1, "",
                     "fraction of those rays that must hit a surface"),
        OptionNumber(&O::horizontal_normal_deg, "horizontal_normal_deg", 0.1, 89, "degrees",
                     "max tilt of floor/ceiling surfaces"),
        OptionNumber(&O::min_floor_to_ceiling_m, "min_floor_to_ceiling_m", 0.5, 20, "metres",
                     "min ceiling height above the floor"),
        OptionNumber(&O::max_voxels, "max_voxels", 1, 1e12, "", "refuse voxel grids larger than this"),
        OptionNumber(&O::cloud_normal_neighbors, "cloud_normal_neighbors", 3, 100, "", "k for point-cloud normals"),
        OptionNumber(&O::pocket_rounds, "pocket_rounds", 0, 10, "",
                     "rounds of extra scan positions in unseen clear pockets (closets, WCs) the grid missed; 0 = off"),
        OptionNumber(&O::max_pocket_positions, "max_pocket_positions", 1, 100000, "",
                     "extra positions per round at most, largest pockets first"),
        OptionNumber(&O::min_sealed_room_m2, "min_sealed_room_m2", 0, 1000, "m2",
                     "an unseen pocket no door leads into gets a position from this clear area on, ..."),
        OptionNumber(&O::sealed_room_tolerance_m, "sealed_room_tolerance_m", 0, 2, "metres",
                     "... when the surfaces straight above and below it are the ceiling and the floor within this; 0 = off"),
    };
    return table;
  }
  bool Check(std::string* error) const;
};

struct VoxelMap {
  VoxelGrid grid;
  bool floor_found = false;
  double floor_z = 0.0;     // Metres, input frame.
  bool ceiling_found = false;
  double ceiling_z = 0.0;
  // Clouds: the grid indices of the voxels that hold at least one input point, ascending (the disc splats
  // of VoxelizeCloudSurface occupy more). Empty for meshes, whose occupied voxels are all exact surface.
  std::vector<uint32_t> point_voxels;
  // True for a mesh: every occupied voxel is one the input surface passes through (the Voxel-CRF keeps them
  // occupied, as it keeps a cloud's point voxels; VoxelCrfOptions::keep_scan_points).
  bool exact_surface = false;
  std::vector<Eigen::Vector3d> scan_positions;  // The grid's, then the pockets'.
  int pocket_positions = 0;  // Of scan_positions, how many were added for pockets (the last ones).
  bool enclosed = true;     // False when no candidate passed the enclosure test (degraded input).
  size_t rays_cast = 0;
  double seconds_surface = 0, seconds_floor = 0, seconds_free_space = 0;
};

// Floor and ceiling heights from (z, weight) samples of near-horizontal surface elements (weight = area,
// m²). Floor: the lowest `bin_m` bin of upward-facing area holding at least 30% of the largest such bin;
// ceiling: the highest bin of downward-facing area with at least 10% of the floor's area and at least
// `min_floor_to_ceiling_m` above it. Heights are refined to the area-weighted mean over the bin and its
// neighbours. Unoriented surfaces (clouds) pass the same samples as `up` and `down`. Also used by the scene
// frame estimate (mapping/scene_frame.h), so both agree on where the floor is.
struct FloorCeiling {
  bool floor_found = false, ceiling_found = false;
  double floor_z = 0, ceiling_z = 0;  // Metres.
};
FloorCeiling DetectFloorCeiling(const std::vector<std::pair<double, double>>& up,
                                const std::vector<std::pair<double, double>>& down, double bin_m,
                                double min_floor_to_ceiling_m);

// Returns the grid bounds (keys) covering `box` with one voxel of margin, or an error when it exceeds
// options.max_voxels or the OctoMap key range.
Status PlanVoxelGrid(const Aabb& box, const VoxelizeOptions& options, VoxelGrid* grid);

// `progress` (optional) is called as free-space rays are cast, once per scan position.
Result<VoxelMap> Voxelize(const Scene& scene, const VoxelizeOptions& options, const ProgressCallback& progress = {});

// Building blocks, exposed for tests and benchmarks.
// Marks the voxels each triangle passes through as occupied (exact triangle/box overlap, half-open cells).
void VoxelizeMeshSurface(const Mesh& mesh, VoxelGrid* grid);
// Marks point voxels as occupied; where the local spacing exceeds half a voxel a point becomes a disc
// of that radius in its tangent plane. `normals` may be empty.
void VoxelizeCloudSurface(const PointCloud& cloud, const std::vector<Eigen::Vector3f>& normals,
                          const std::vector<float>& spacing, VoxelGrid* grid);
// The grid indices of the voxels holding at least one of `points`, ascending, without repeats.
std::vector<uint32_t> PointVoxels(const std::vector<Eigen::Vector3f>& points, const VoxelGrid& grid);
// Marks free voxels seen from `positions`. Returns the number of rays cast.
size_t CastFreeSpace(const std::vector<Eigen::Vector3d>& positions, double max_range_m, VoxelGrid* grid,
                     const ProgressCallback& progress = {});

}  // namespace semvox
