// Canonical frame of a scan: up = +Z, floor at z = 0, walls along the x / y axes.
//
//   Scene --EstimateSceneFrame--> SceneFrame (canonical_from_input, up, tilt, yaw, floor, warnings)
//   TransformScene(frame.canonical_from_input, &scene)   // vertices, points and normals
//
// Every later stage (voxelisation, viewpoints, planes, floor plan, per-view features, top views) assumes
// this frame: the floor near z = 0 and walls along the axes. Real scans are levelled only roughly and turned
// arbitrarily about the vertical, so `semvox run` estimates the frame right after loading and works in it;
// coordinate outputs are mapped back to the input frame (docs/outputs.md, "Frames").
//
//   canonical_from_input = T(-shift_x, -shift_y, -floor_z) * Rz(-yaw) * R_level
//
// R_level: the smallest rotation taking the estimated up (the normal of the dominant horizontal planes,
// floor and ceiling) to +Z, applied for tilts up to `max_level_deg`; yaw: the dominant direction of wall
// normals modulo 90 degrees; floor_z: the lowest dominant horizontal plane after levelling, by the
// voxeliser's own rule (DetectFloorCeiling); shift_x, shift_y: the walls' phase within the voxel grid (the
// area-weighted circular mean of the wall surfaces' x (resp. y) modulo the voxel size), so that walls lie on
// voxel boundaries as the floor at z = 0 does. With the phase fixed, one apartment in any pose cuts into the
// same voxels (up to whole voxels), and its walls voxelise as the generated training apartments' do (their
// walls lie on the grid). Tiny corrections snap to exactly zero, so axis-aligned inputs
// with the floor at z = 0 get exactly the identity. Pure functions; deterministic (parallel loops write
// per-element slots only; histograms are summed in element order).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/geometry.h"

namespace semvox {

struct SceneFrameOptions {
  double max_level_deg = 35.0;        // Tilts up to this are levelled; beyond, the input up is kept (warning). (0, 80].
  double warn_tilt_deg = 3.0;         // A tilt above this is reported as a warning naming --up. >= 0, degrees.
  double plane_normal_deg = 5.0;      // Normals within this angle of the up estimate belong to its planes. (0, 20].
  double min_plane_fraction = 0.10;   // Those planes must carry this fraction of the surface area. (0, 1).
  double horizontal_normal_deg = 10;  // Horizontal surfaces for the floor rule (as the voxeliser). (0, 90).
  double wall_normal_deg = 10;        // Normals within this angle of horizontal are wall samples for the yaw. (0, 45).
  double min_wall_fraction = 0.05;    // No yaw unless wall samples carry this fraction of the surface area. [0, 1].
  double min_yaw_concentration = 0.25;  // ... and this fraction of the wall area lies within 5 degrees of the yaw. [0, 1].
  double bin_m = 0.05;                // Height bins of the floor rule (the voxel size), metres. > 0.
  double min_floor_to_ceiling_m = 1.8;  // As VoxelizeOptions, metres.
  int cloud_normal_neighbors = 12;    // k for PCA normals of clouds without normals. >= 3.
  size_t max_cloud_points = 200000;   // Clouds above this are subsampled (every k-th point) for the estimate.
  double snap_tilt_deg = 0.05;        // Smaller tilts are not corrected (exact identity), degrees.
  double snap_yaw_deg = 0.05;         // Smaller yaws are not corrected, degrees.
  double snap_floor_m = 0.001;        // Smaller floor offsets are not corrected, metres.
  bool wall_phase = true;             // Shift x, y so that the walls lie on voxel boundaries (period bin_m).
  // ... only when the frame turns the scan (levels it or turns it about z): a scan already level and
  // axis-aligned keeps its own grid, so its maps lie on the input's multiples of the voxel size (as map_server
  // users and the ground truth of generated apartments and plans expect; shifting them by a centimetre moved
  // every fifth wall surface into the next cell of the top view: coverage 0.94-0.97 instead of 0.98-0.99 on
  // the 11 of 100 R2V validation plans whose walls' phases agreed). A turned scan's grid is new anyway.
  bool phase_only_when_turned = true;
  double min_phase_concentration = 0.2;  // No shift on an axis unless the walls' phases agree this much
                                         // (resultant length of the area-weighted circular mean). [0, 1].
  double snap_shift_m = 0.0025;       // Smaller shifts are not applied, metres.

  bool Check(std::string* error) const;
};

struct SceneFrame {
  // The rigid transform into the canonical frame (metres); input_from_canonical is its inverse.
  Eigen::Isometry3d canonical_from_input = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d input_from_canonical() const { return canonical_from_input.inverse(); }
  bool identity() const { return canonical_from_input.matrix() == Eigen::Matrix4d::Identity(); }

  bool up_found = false;        // A dominant horizontal plane family was found within max_level_deg (+5) of +Z.
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // Estimated up, input frame, unit; +Z when not found.
  double tilt_deg = 0.0;        // Angle between the estimated up and +Z, degrees, [0, 180].
  bool levelled = false;        // R_level is not the identity.
  bool upside_down = false;     // The floor lies above the furniture (estimated up close to -Z).
  bool yaw_found = false;
  double yaw_deg = 0.0;         // Wall direction modulo 90 degrees, (-45, 45]; 0 when not found or snapped.
  double yaw_measured_deg = 0.0;  // Before snapping, degrees.
  bool floor_found = false;
  double floor_z = 0.0;         // Floor height after levelling (along the applied up, from the input origin),
                                // metres; 0 when not found or snapped. Equals the input z of the floor for a
                                // level scan.
  double floor_measured_z = 0.0;  // Before snapping, metres.
  // Wall phase shift along the canonical x and y (after levelling and turning), metres, in [-bin_m / 2,
  // bin_m / 2); 0 on an axis whose walls' phases do not agree or whose shift snapped.
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();
  Eigen::Vector2d phase_concentration = Eigen::Vector2d::Zero();  // Resultant lengths per axis, [0, 1].
  std::vector<std::string> warnings;  // Sentences for the log and summary.json; tilt warnings name --up.
  double seconds = 0.0;
};

// Estimates the canonical frame of a mesh (face normals and areas; winding is used for the floor rule only) or a
// cloud (its normals, else PCA normals of k nearest neighbours; point weight = local spacing squared). The
// floor side (upside down or not) comes from the furniture: horizontal surfaces between the lowest and
// highest planes lie mostly in the lower half.
SceneFrame EstimateSceneFrame(const Scene& scene, const SceneFrameOptions& options = {});

// Applies a rigid transform to the scene's vertices / points and rotates point normals. In parallel.
void TransformScene(const Eigen::Isometry3d& transform, Scene* scene);

}  // namespace semvox
