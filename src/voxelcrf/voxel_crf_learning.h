// Structural-SVM learning of the Voxel-CRF weights (Kim et al. 2013, Sec. 5.2).
//
//   min_w  lambda/2 |w|^2 + 1/N sum_n max_L ( Delta(L; L^n) + E(L^n | w) - E(L | w) )
//
// with Delta the number of voxels whose label differs from the ground truth (normalised by the number of
// nodes of the example), solved by stochastic subgradient descent: per example the most violating labelling
// comes from loss-augmented inference (alpha-expansion on E - Delta, which stays a valid CRF energy because
// the loss decomposes over voxels), and w moves along -(lambda w + (Psi(L^n) - Psi(L_hat)) / N_nodes).
// Every weight but the occupied bias is projected onto w >= 0 after each step (graph-cut inference needs
// non-negative pairwise and clique weights; the log terms are costs).
#pragma once
#include <array>
#include <cstdint>
#include <vector>
#include "core/status.h"
#include "crf/solvers.h"
#include "voxelcrf/voxel_crf.h"

namespace semvox {

struct VoxelCrfTrainingExample {
  VoxelCrfProblem problem;  // Built with the visibility of the ground truth.
  std::vector<int> gt;      // Per node: 0 empty, k >= 1 class k - 1.
};

struct VoxelCrfLearningOptions {
  int epochs = 12;                // Passes over the examples. >= 1.
  double learning_rate = 0.5;     // eta_0; step t uses eta_0 / sqrt(1 + t). > 0.
  double regularization = 1e-3;   // lambda. >= 0.
  uint64_t seed = 0;              // Order of the examples in each epoch.
  std::array<bool, kNumVoxelCrfWeights> frozen{};  // Weights held at their initial value (not learned).
  AlphaExpansionOptions solver;
  bool Check(std::string* error) const;
};

struct VoxelCrfLearningSummary {
  std::vector<double> loss_per_epoch;      // Mean normalised Hamming loss of the loss-augmented labelling.
  std::vector<double> hinge_per_epoch;     // Mean normalised structured hinge loss.
  int steps = 0;
  double seconds = 0;
};

// Normalised Hamming loss of `labels` against `gt`.
double HammingLoss(const std::vector<int>& labels, const std::vector<int>& gt);

Result<std::array<double, kNumVoxelCrfWeights>> LearnVoxelCrfWeights(const std::vector<VoxelCrfTrainingExample>& examples,
                                                                     const std::array<double, kNumVoxelCrfWeights>& initial,
                                                                     const VoxelCrfLearningOptions& options,
                                                                     VoxelCrfLearningSummary* summary);

}  // namespace semvox
