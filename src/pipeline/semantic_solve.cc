#include "pipeline/semantic_solve.h"

#include <chrono>

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

}  // namespace semvox
