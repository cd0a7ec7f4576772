#include "voxelcrf/voxel_crf_learning.h"

#include <chrono>
#include <cmath>
#include <numeric>
#include <random>

#include "core/log.h"

namespace semvox {

bool VoxelCrfLearningOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (epochs < 1) return fail("epochs = " + std::to_string(epochs) + ". Violated constraint: epochs >= 1");
  if (!(learning_rate > 0)) return fail("learning_rate = " + std::to_string(learning_rate) + ". Violated constraint: > 0");
  if (!(regularization >= 0)) return fail("regularization = " + std::to_string(regularization) + ". Violated constraint: >= 0");
  return solver.Check(error);
}

double HammingLoss(const std::vector<int>& labels, const std::vector<int>& gt) {
  size_t wrong = 0;
  for (size_t i = 0; i < gt.size(); ++i) wrong += labels[i] != gt[i];
  return gt.empty() ? 0.0 : double(wrong) / double(gt.size());
}

Result<std::array<double, kNumVoxelCrfWeights>> LearnVoxelCrfWeights(const std::vector<VoxelCrfTrainingExample>& examples,
                                                                     const std::array<double, kNumVoxelCrfWeights>& initial,
                                                                     const VoxelCrfLearningOptions& options,
                                                                     VoxelCrfLearningSummary* summary) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("voxel CRF learning: " + error);
  if (examples.empty()) return Status::InvalidInput("voxel CRF learning: no training example");
  const auto t0 = std::chrono::steady_clock::now();
  *summary = VoxelCrfLearningSummary{};
  std::array<double, kNumVoxelCrfWeights> w = initial;
  std::mt19937_64 rng(options.seed);
  std::vector<size_t> order(examples.size());
  std::iota(order.begin(), order.end(), 0);
  int t = 0;
  for (int epoch = 0; epoch < options.epochs; ++epoch) {
    std::shuffle(order.begin(), order.end(), rng);
    double loss_sum = 0, hinge_sum = 0;
    for (size_t k : order) {
      const VoxelCrfTrainingExample& ex = examples[k];
      const CrfEnergy energy = ex.problem.Energy(w, &ex.gt);
      std::vector<CrfLabel> labels;
      CrfSolverSummary s;
      SEMVOX_RETURN_IF_ERROR(MinimizeWithAlphaExpansion(energy, options.solver, &labels, &s));
      const std::vector<int> hat(labels.begin(), labels.end());
      const auto f_hat = ex.problem.Features(hat);
      const auto f_gt = ex.problem.Features(ex.gt);
      const double n = double(std::max(1, ex.problem.num_nodes));
      const double loss = HammingLoss(hat, ex.gt);
      double margin = 0;
      for (int i = 0; i < kNumVoxelCrfWeights; ++i) margin += w[size_t(i)] * (f_gt[size_t(i)] - f_hat[size_t(i)]);
      loss_sum += loss;
      hinge_sum += std::max(0.0, loss + margin / n);
      const double eta = options.learning_rate / std::sqrt(1.0 + t);
      for (int i = 0; i < kNumVoxelCrfWeights; ++i) {
        if (options.frozen[size_t(i)]) continue;
        const double g = options.regularization * w[size_t(i)] + (f_gt[size_t(i)] - f_hat[size_t(i)]) / n;
        w[size_t(i)] -= eta * g;
        if (i != kWOccupiedBias) w[size_t(i)] = std::max(0.0, w[size_t(i)]);
      }
      ++t;
    }
    summary->loss_per_epoch.push_back(loss_sum / double(examples.size()));
    summary->hinge_per_epoch.push_back(hinge_sum / double(examples.size()));
    SEMVOX_INFO("voxel CRF learning: epoch " << epoch + 1 << ": loss-augmented Hamming " << summary->loss_per_epoch.back()
                                             << ", hinge " << summary->hinge_per_epoch.back());
  }
  summary->steps = t;
  summary->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return w;
}

}  // namespace semvox
