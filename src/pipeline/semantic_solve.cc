#include "pipeline/semantic_solve.h"

#include <algorithm>
#include <chrono>

#include "core/labels.h"
#include "core/log.h"

namespace semvox {

Status SolveSemantic(const VoxelMap& map, const SemanticEvidence& evidence, const VoxelCrfModel& model,
                     const VoxelCrfOptions& options, SemanticLabels* labels) {
  const auto t0 = std::chrono::steady_clock::now();
  SemanticLabels& s = *labels;
  SEMVOX_RETURN_IF_ERROR(SolveVoxelCrf(map.grid, evidence.nodes, evidence.voxels, map.floor_z, map.ceiling_z, model, options, &s.crf));
  s.map = MakeSemanticMap(map.grid, evidence.nodes, evidence.voxels, s.crf, model);
  s.refined = s.map.RefinedGrid(map.grid, evidence.nodes);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  SEMVOX_INFO("voxel CRF: " << s.map.occupied.size() << " occupied voxels labelled (" << s.map.completed_count()
                            << " completed), " << s.crf.num_planes << " planes, " << s.crf.num_object_cliques
                            << " object cliques, " << s.crf.iterations.size() << " iterations, " << s.seconds << " s");
  return Status::Ok();
}

void ApplyWallOpenings(const VoxelMap& map, const WallOpeningOptions& options, SemanticLabels* labels) {
  const auto t0 = std::chrono::steady_clock::now();
  const VoxelGrid& grid = map.grid;
  // Up to the ceiling's underside, or the scan's top.
  const int top_cell = grid.TopOccupiedLayer();
  const double top_z = map.ceiling_found ? map.ceiling_z - 0.1 : top_cell >= 0 ? grid.CellCenter(0, 0, top_cell).z() : map.floor_z;
  labels->openings = FindWallOpenings(grid, map.floor_z, top_z, options);
  labels->opening_voxels = 0;
  std::vector<SemanticVoxelRecord>& occupied = labels->map.occupied;  // Ascending voxel index.
  for (const WallOpening& o : labels->openings) {
    // A pane or closed leaf is part of the wall's surface: only voxels the CRF took for wall (or the other
    // opening class) change. An open leaf stands free, so it changes whatever it was taken for.
    for (uint32_t v : o.voxels) {
      const auto it = std::lower_bound(occupied.begin(), occupied.end(), v,
                                       [](const SemanticVoxelRecord& r, uint32_t x) { return r.voxel < x; });
      if (it == occupied.end() || it->voxel != v || it->label == o.nyu40) continue;
      const bool structural = it->label == nyu40::kWall || it->label == nyu40::kDoor || it->label == nyu40::kWindow;
      if (!structural && !(o.open_leaf && it->label != nyu40::kFloor && it->label != nyu40::kCeiling)) continue;
      it->label = uint16_t(o.nyu40);
      ++labels->opening_voxels;
    }
  }
  labels->seconds_openings = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  int doors = 0;
  for (const WallOpening& o : labels->openings) doors += o.nyu40 == nyu40::kDoor;
  SEMVOX_INFO("wall openings: " << doors << " doors, " << labels->openings.size() - size_t(doors) << " windows, "
                                << labels->opening_voxels << " voxels relabelled, " << labels->seconds_openings << " s");
}

}  // namespace semvox
