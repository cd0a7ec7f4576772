#include "pipeline/voxel_crf_examples.h"

#include "core/labels.h"
#include "voxelcrf/planes.h"

namespace semvox {

std::vector<int> GroundTruthNodeLabels(const VoxelGrid& grid, const SemanticEvidence& evidence, const LabelLevel& level,
                                       const std::unordered_map<uint64_t, int>& nyu40_of_key) {
  const VoxelCrfNodes& nodes = evidence.nodes;
  std::vector<int> gt(nodes.size(), 0);
  for (size_t i = 0; i < gt.size(); ++i) {
    const auto c = grid.Cell(nodes.voxel[i]);
    const auto it = nyu40_of_key.find(grid.KeyOf(c[0], c[1], c[2]).Pack());
    if (it == nyu40_of_key.end() || it->second <= 0 || it->second >= kNumNyu40) continue;
    const int cls = level.class_of_nyu40[size_t(it->second)];
    if (cls >= 0) gt[i] = cls + 1;
  }
  return gt;
}

void AddLayoutCounts(const VoxelMap& map, const SemanticEvidence& evidence, int num_classes, const std::vector<int>& gt,
                     std::vector<double>* counts) {
  const int K = num_classes;
  counts->resize(size_t(LayoutPrior::kHeightBins) * LayoutPrior::kNormalBins * size_t(K), 0.0);
  for (size_t i = 0; i < gt.size(); ++i) {
    if (gt[i] <= 0) continue;
    const auto c = map.grid.Cell(evidence.nodes.voxel[i]);
    const int hb = LayoutPrior::HeightBin(map.grid.CellCenter(c[0], c[1], c[2]).z(), map.floor_z, map.ceiling_z);
    const int nb = LayoutPrior::NormalBin(evidence.voxels.normal[i]);
    (*counts)[(size_t(hb) * LayoutPrior::kNormalBins + size_t(nb)) * size_t(K) + size_t(gt[i] - 1)] += 1.0;
  }
}

VoxelCrfTrainingExample TrainingExample(const VoxelMap& map, const SemanticEvidence& evidence, const VoxelCrfOptions& options,
                                        std::vector<int> gt, const VoxelCrfModel& model) {
  VoxelCrfTrainingExample ex;
  const std::vector<DetectedPlane> planes = DetectPlanes(map.grid, evidence.nodes, evidence.voxels, options.planes);
  const std::vector<int32_t> vis = ComputeVisibility(map.grid, evidence.nodes, evidence.voxels, gt);
  ex.problem = BuildVoxelCrfProblem(map.grid, evidence.nodes, evidence.voxels, map.floor_z, map.ceiling_z, model, planes, options, vis);
  ex.gt = std::move(gt);
  return ex;
}

}  // namespace semvox
