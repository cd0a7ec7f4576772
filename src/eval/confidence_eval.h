// How far a run's per-voxel `confidence` can be trusted (docs/metrics.md, "Confidence scores"): given the
// confidence of each scored prediction and whether it was right, the reliability table (10 equal-width bins over
// [0, 1]), the expected calibration error and the AUROC of confidence for telling right from wrong.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "eval/score.h"

namespace semvox {

inline constexpr int kReliabilityBins = 10;

struct ReliabilityBin {
  size_t count = 0;
  double mean_confidence = 0;  // Mean confidence of the bin's predictions (0 when empty).
  double accuracy = 0;         // Share of them right (0 when empty).
};

struct ConfidenceScores {
  size_t scored = 0;       // Predictions with a confidence.
  Score mean_confidence;
  Score accuracy;          // Share right among them.
  // Expected calibration error: sum over bins of (bin count / scored) |accuracy - mean confidence|.
  Score ece;
  // Probability that a right prediction has a higher confidence than a wrong one (ties count half): 0.5 is
  // chance; absent when all are right or all wrong.
  Score auroc;
  std::array<ReliabilityBin, kReliabilityBins> bins{};  // Bin b holds confidences in [b/10, (b+1)/10) (1.0 in the last).
  // Share of predictions with confidence >= 0.5 and >= 0.8, and the accuracy among them.
  Score share_above_05, accuracy_above_05, share_above_08, accuracy_above_08;
};

// `confidence[i]` in [0, 1] (values outside are clamped; NaN skipped) and `right[i]` for each prediction.
ConfidenceScores ScoreConfidence(const std::vector<float>& confidence, const std::vector<uint8_t>& right);

// The scores and the reliability table as lines of the eval tables (each starting with two spaces).
std::string ConfidenceTable(const ConfidenceScores& s);

}  // namespace semvox
