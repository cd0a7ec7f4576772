// 3D planes in the voxel map, for the Voxel-CRF's surface cliques (Kim et al. 2013, Sec. 4.3, Fig. 4).
//
// Detection votes in a parameter space, as the paper's Hough-voting detector does: the observed occupied
// voxels' normals are grouped into dominant directions (greedy mode seeking on the sphere), each direction's
// voxels vote for the plane offset n . p in half-voxel bins, and the peaks become planes; each plane splits
// into connected pieces in its own 2D coordinates. Each piece is then extended to its convex hull ("the 3D
// plane with smallest perimeter containing all the points associated with a detected surface"): the hull is
// rasterised on the plane and every CRF node there that the map does not know to be free joins the
// clique, so that occluded parts of walls and floors take the plane's label.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>
#include "core/option_table.h"
#include "core/voxel_grid.h"
#include "voxelcrf/voxel_evidence.h"

namespace semvox {

struct PlaneDetectionOptions {
  double normal_angle_deg = 12.0;      // Voxels whose normal is within this of a direction vote for it.
  double offset_tolerance_voxels = 0.75;  // Inliers lie within this of the plane, in voxel sizes. > 0.
  int min_voxels = 60;
  int max_planes = 400;                // Most plane pieces kept (largest first). >= 0.
  int gap_cells = 1;                   // Pieces join across gaps up to this many cells in the plane. >= 0.

  // The fields users set (section `semantic`): meaning, unit and range.
  static const OptionTable<PlaneDetectionOptions>& Options() {
    using O = PlaneDetectionOptions;
    static const OptionTable<O> table = {
        OptionNumber(&O::min_voxels, "min_voxels", 3, 1000000, "voxels", "smallest plane piece"),
        OptionNumber(&O::normal_angle_deg, "normal_angle_deg", 0.1, 45, "degrees", "plane detection: normal tolerance"),
    };
    return table;
  }
  bool Check(std::string* error) const;
};

struct DetectedPlane {
  Eigen::Vector3f normal = Eigen::Vector3f::UnitZ();  // Unit, towards the observing side.
  float offset = 0;                    // normal . p for points p on the plane, metres.
  std::vector<int> members;            // Nodes that voted for it (observed, occupied).
  std::vector<int> hull_nodes;         // Nodes in the convex hull, not known free (members included).
  double area_m2 = 0;                  // Of the hull.
  bool horizontal() const { return std::abs(normal.z()) > 0.9f; }
  bool vertical() const { return std::abs(normal.z()) < 0.2f; }
};

std::vector<DetectedPlane> DetectPlanes(const VoxelGrid& grid, const VoxelCrfNodes& nodes, const VoxelEvidence& evidence,
                                        const PlaneDetectionOptions& options);

// Convex hull of 2D points (Andrew's monotone chain), counter-clockwise, without collinear points.
std::vector<Eigen::Vector2d> ConvexHull2D(std::vector<Eigen::Vector2d> points);

}  // namespace semvox
