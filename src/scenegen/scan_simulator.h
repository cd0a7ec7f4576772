// A simulated fused point cloud: a virtual scanner carried through the apartment.
//
//   Apartment --SimulateScan--> PointCloud (per-point label, instance, room; colours; normals)
//
// Scanner stations are laid on a grid over every room's free floor (away from furniture), visited room by
// room along the door graph. From each station the scanner casts rays over the sphere (Embree, through
// render/raycaster.h) against the clean mesh, so surfaces behind and under furniture are never seen. Each
// range gets Gaussian noise growing with distance, sigma(r) = noise_sigma_m + noise_quadratic * r^2 (the
// axial model of Nguyen, Izadi and Lovell 2012 for structured-light sensors), and the points of all
// stations are fused on a voxel grid (first point per voxel kept), as a SLAM system's map would be.
#pragma once

#include <cstdint>
#include <string>

#include "core/geometry.h"
#include "core/status.h"
#include "scenegen/apartment.h"

namespace semvox {

struct ScanSimulationOptions {
  uint64_t seed = 0;                 // Ray jitter and range noise are drawn from this.
  double station_spacing_m = 1.6;    // Grid spacing of scanner stations, metres. > 0.
  double station_clearance_m = 0.35; // A station keeps this far from furniture and walls, metres. >= 0.
  double scanner_height_m = 1.4;     // Above the floor, metres. > 0, below the ceiling.
  int azimuth_steps = 540;           // Rays per full turn. >= 8.
  int elevation_steps = 240;         // Rows from straight down to straight up (equal-area spacing). >= 4.
  double min_range_m = 0.3;          // Returns closer than this are dropped, metres. >= 0.
  double max_range_m = 8.0;          // Returns farther than this are dropped, metres. > min_range_m.
  double noise_sigma_m = 0.0012;     // Range noise at zero distance, metres. >= 0.
  double noise_quadratic = 0.0019;   // Growth of the range noise with distance, metres per m². >= 0.
  double fuse_voxel_m = 0.03;        // Fusion grid: one point per voxel of this size, metres. > 0.

  bool Check(std::string* error) const;
};

// Scanner stations (world positions at scanner height), in visiting order.
std::vector<Eigen::Vector3d> ScanStations(const Apartment& apartment, const ScanSimulationOptions& options);

Result<PointCloud> SimulateScan(const Apartment& apartment, const ScanSimulationOptions& options);

}  // namespace semvox
