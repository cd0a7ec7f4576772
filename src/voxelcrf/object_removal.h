// Object removal with scene completion (Kim, Kohli & Savarese, "3D Scene Understanding by Voxel-CRF",
// ICCV 2013, Sec. 6.4 and Fig. 7): the chosen objects' voxels leave the map and the space they hid is
// completed by a Voxel-CRF over the remaining, labelled map.
//
//   std::vector<int32_t> instance = LabelInstances(grid, map, &instances);   // --instance ids, --list
//   std::vector<uint8_t> remove = SelectForRemoval(map, instance, selection);
//   ObjectRemovalResult out;
//   Status st = RemoveObjects(grid, map, remove, ObjectRemovalOptions{}, &out);
//   WriteVoxelsPly(out.map, ...); WriteVoxelMesh(out.grid, out.map, "mesh.ply", "mesh.obj");
//
// Instances. voxels.ply carries no instance ids; an instance is a connected component of occupied voxels of
// one NYU40 label under 26-connectivity. Ids count from 1 in grid-index order of each component's first
// voxel (z, then y, then x), so they are stable for one map.
//
// Completion energy. The removed voxels, and the unknown voxels within `completion_band_m` of them (the
// space the objects hid from the scanner), become the CRF's nodes; every other voxel keeps its state and
// label and enters the energy as fixed evidence (the remaining map is the "observed" part of Eq. 1). Each node
// takes a label l in {0 = empty} U {NYU40 labels of the planes and of the fixed voxels next to the nodes}:
//
//   unary (Eq. 3-4):   w_unseen [l != 0]                       occupying space nobody saw costs
//                      + sum over free 6-neighbours of V(l, 0)  (the scanner saw through them)
//                      + sum over fixed occupied 6-neighbours j of w_semantic [l != 0, l != l_j]
//                      + w_plane [l != plane label]            nodes on an extended plane (Sec. 4.3)
//   pairwise (Eq. 5):  V(l_i, l_j) over 6-adjacent nodes, V(a, b) = 0 if a = b, w_occupancy if exactly one
//                      is empty, w_semantic if both are occupied with different labels (a metric for
//                      w_semantic <= 2 w_occupancy, so alpha-expansion is exact per move).
//
// Planes (Sec. 4.3, "planes extended"): DetectPlanes on the remaining occupied voxels, with normals from
// the PCA of their occupied 5x5x5 neighbourhood oriented towards the free side; each plane piece's convex
// hull covers the hole its objects left. The paper's Robust P^n plane clique w_g min(Q, min_l N_l) is used in
// its linear regime (every hidden node costs w_plane for leaving the plane's label), which it is in while the
// hidden part of a plane is smaller than the truncation Q = 0.25 x clique size, as for objects in front of
// walls and floors. Minimised by alpha-expansion (crf/solvers.h).
//
// Completed voxels take the colour of the adjacent visible voxels of the same label (layer by layer: the mean
// colour of their already coloured 26-neighbours of that label), else the label's mean colour in the map.
// Removed voxels labelled empty become free (the object is gone); unknown nodes labelled empty stay unknown.
//
// RemoveObjects runs six named phases (object_removal.cc): ClearRemoved (the records leave the grid),
// CompletionNodes (the band BFS), PlaneLabelsOfNodes (normals, planes, hull labels), SolveCompletion (the
// energy above and alpha-expansion), ApplyCompletion (states, completed records, confidences) and
// ColourCompleted.
#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>
#include "core/status.h"
#include "core/voxel_grid.h"
#include "crf/solvers.h"
#include "voxelcrf/planes.h"
#include "voxelcrf/semantic_map.h"

namespace semvox {

struct ObjectInstance {
  int id = 0;            // From 1.
  uint16_t label = 0;    // NYU40 id.
  size_t voxels = 0;
  Eigen::Vector3f min = Eigen::Vector3f::Zero(), max = Eigen::Vector3f::Zero();  // Voxel-centre bounds, metres.
};

// Per SemanticMap::occupied record its instance id (26-connected components of one label).
std::vector<int32_t> LabelInstances(const VoxelGrid& grid, const SemanticMap& map, std::vector<ObjectInstance>* instances);

struct RemovalSelection {
  std::vector<int> classes;     // NYU40 ids to remove.
  std::vector<int> instances;   // Instance ids (LabelInstances) to remove.
  bool all_furniture = false;   // Every voxel of an NYU-4 "furniture" or "props" class.
};

// Per record: 1 = remove.
std::vector<uint8_t> SelectForRemoval(const SemanticMap& map, const std::vector<int32_t>& instance_of_record,
                                      const RemovalSelection& selection);

struct ObjectRemovalOptions {
  double completion_band_m = 0.25;   // Unknown voxels this close to a removed voxel become nodes, metres. >= 0.
  double w_unseen = 0.3;             // Cost of occupying a node (unseen space). >= 0.
  double w_occupancy = 0.5;          // Pairwise cost, one side empty and one occupied. > 0.
  double w_semantic = 1.0;           // Pairwise cost, two different occupied labels. (0, 2 w_occupancy].
  double w_plane = 2.0;              // Cost per hull node of leaving its plane's label. >= 0.
  double planar_ratio = 0.1;         // Normals only where the smallest PCA eigenvalue < this x the middle one. (0, 1].
  PlaneDetectionOptions planes;
  AlphaExpansionOptions solver;
  bool Check(std::string* error) const;
};

struct ObjectRemovalResult {
  VoxelGrid grid;                    // States after removal and completion.
  SemanticMap map;                   // Remaining records (unchanged) + completed ones (completed = 1).
  size_t removed_voxels = 0;
  size_t nodes = 0, unknown_nodes = 0;
  size_t completed_voxels = 0;       // Nodes labelled occupied.
  size_t planes = 0, planes_used = 0;  // Detected; with a hull node.
  std::vector<std::pair<int, size_t>> completed_labels;  // NYU40 id -> completed voxels.
  double energy_initial = 0, energy_final = 0;
  double seconds = 0;
};

Status RemoveObjects(const VoxelGrid& grid, const SemanticMap& map, const std::vector<uint8_t>& remove,
                     const ObjectRemovalOptions& options, ObjectRemovalResult* result);

// Mesh of the occupied voxels' boundary faces (faces between an occupied voxel and a non-occupied one),
// in the input frame, metres. PLY: binary, shared corner vertices, triangles with per-face red, green,
// blue (the voxel's colour) and label (ushort, NYU40). OBJ: the same vertices, quads grouped by label with
// one material per label (mesh.mtl beside it; Kd = the label's mean colour, name = NYU40 name). Atomic.
struct VoxelMeshStats {
  size_t vertices = 0, quads = 0;
};
// Vertices are mapped by `input_from_world` (the canonical frame of the run back to its input frame).
Status WriteVoxelMesh(const VoxelGrid& grid, const SemanticMap& map, const std::string& ply_path,
                      const std::string& obj_path, VoxelMeshStats* stats = nullptr,
                      const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity());

}  // namespace semvox
