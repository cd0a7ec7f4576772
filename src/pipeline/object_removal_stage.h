// Object removal on a finished run (`semvox remove`): the run's outputs read back (summary.json, map.ot,
// voxels.ply), the chosen objects removed and the space behind them completed (voxelcrf/object_removal.h,
// Voxel-CRF paper Sec. 6.4), the edited run written like `semvox run` writes its own.
//
//   ObjectRemovalRequest request;
//   request.outdir = "out/run"; request.output = "out/edited"; request.classes = {"television"};
//   Status st = RemoveObjectsFromRun(request);   // OUT2/voxels.ply, map.ot, mesh.{ply,obj,mtl}, occupancy.*, ...
//
//   Result<std::vector<RunInstance>> list = ListRunInstances("out/run");   // `semvox remove OUTDIR --list`
#pragma once
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/status.h"
#include "core/voxel_grid.h"
#include "mapping/occupancy_map.h"
#include "voxelcrf/object_removal.h"
#include "voxelcrf/planes.h"
#include "voxelcrf/semantic_map.h"

namespace semvox {

// A run's outputs as read back: the refined grid (map.ot's known voxels), the labelled voxels (voxels.ply,
// moved back into the grid's canonical frame), floor and ceiling heights (canonical frame) and the frame.
struct RunOutputs {
  VoxelGrid grid;
  SemanticMap map;
  double floor_z = 0, ceiling_z = 0;  // Canonical frame of the run (the grid's frame), metres.
  // The run's canonical frame back to its input frame (summary.json `frame`, identity when absent): voxels.ply
  // holds input-frame coordinates, the grid and map.ot canonical keys.
  Eigen::Isometry3d input_from_world = Eigen::Isometry3d::Identity();
};

// Reads OUTDIR of `semvox run` (with the semantic stage); a missing or malformed file is kInvalidInput naming it.
Status ReadRunOutputs(const std::string& outdir, RunOutputs* run);

struct ObjectRemovalRequest {
  std::string outdir;                // OUTDIR of a `semvox run` (voxels.ply, map.ot, summary.json).
  std::string output;                // OUT2: where the edited run goes (must differ from OUTDIR).
  std::vector<std::string> classes;  // NYU40 names (aliases accepted) or ids to remove.
  std::vector<int> instances;        // Instance ids (ListRunInstances).
  bool all_furniture = false;        // Every NYU-4 furniture and props voxel.
  // The run's own options (its config_used.yaml, which the CLI reads): the occupancy image's band and the
  // planes of the completion.
  OccupancyOptions occupancy;
  PlaneDetectionOptions planes;
};

// Removes the request's objects and writes OUT2/voxels.ply, map.ot, mesh.ply, mesh.obj, mesh.mtl,
// occupancy.pgm, occupancy.yaml, semantic_topview.png, semantic_topview_labels.png and summary.json. Bad
// classes or instances, a selection that matches nothing or OUT2 = OUTDIR are kInvalidInput before anything
// is written.
Status RemoveObjectsFromRun(const ObjectRemovalRequest& request);

// One object of a run: an instance (voxelcrf/object_removal.h) with its box in the run's input frame.
struct RunInstance {
  ObjectInstance instance;
  std::string name;                  // NYU40 name of its label.
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();  // Input frame, metres.
};
Result<std::vector<RunInstance>> ListRunInstances(const std::string& outdir);

}  // namespace semvox
