// Training and validation of the generic object proposer (MST-CRF paper, Sec. 4) on generated apartments,
// for `semvox train` and the benchmark.
//
// Ground truth boxes: the visible pixels of every clutter object (support_truth.h: props standing on a
// support) whose box has at least min_gt_pixels pixels and both metric sides in [5, 50] cm (from the median
// depth of its pixels). Positives: the features of those boxes. Negatives: candidate windows (no sampling)
// overlapping no ground-truth box by IoU 0.3 or more, evenly thinned to max_negatives_per_view per view.
// NYU-4 probabilities per pixel come from the per-view classifier (tree CRF marginals).
//
// Validation (the paper's Sec. 5.2): a proposal is a detection when its IoU with a not yet matched
// ground-truth box is >= 0.5 (greedy by score over the view); detection rate against false positives
// per image, with and without sampling by p(furniture) + p(props), and the time spent on features and SVM.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

#include "core/status.h"
#include "objects/proposals.h"
#include "objects/support_truth.h"
#include "perception/training_data.h"
#include "perception/view_classifier.h"

namespace semvox {

struct ProposalTrainingOptions {
  std::vector<uint64_t> train_seeds;
  std::vector<uint64_t> val_seeds;
  TrainingViewsOptions views;
  SupportTruthOptions truth;
  SuperpixelOptions superpixels = [] {
    SuperpixelOptions o;
    o.region_size_px = 12;
    return o;
  }();
  ProposalOptions proposals;
  SvmOptions svm;
  int min_gt_pixels = 30;           // Smaller visible objects are not ground truth. >= 1.
  int max_negatives_per_view = 6;   // >= 1.
  int max_positives = 700;          // Rows kept (even stride): the kernel matrix is n^2. >= 2.
  int max_negatives = 1400;         // >= 2.
};

struct DetectionCurve {
  int views = 0, ground_truth = 0;
  double candidates = 0;             // Mean candidates scored per view.
  double ms_features = 0, ms_svm = 0, ms_candidates = 0;  // Mean per view.
  std::vector<std::pair<double, int>> scored;  // (score, 1 if detection) of every proposal.
  // Detection rate at `fppi` false positives per image (best threshold with at most that many).
  double DetectionRateAt(double fppi) const;
};

struct ProposalTrainingSummary {
  int train_views = 0, positives = 0, negatives = 0, support_vectors = 0;
  DetectionCurve sampled, all;  // With and without sampling by p(furniture) + p(props).
  nlohmann::json ToJson() const;
};

// Ground-truth boxes of a view.
std::vector<Box2i> GroundTruthBoxes(const SupportView& view, const ProposalTrainingOptions& options);
// NYU-4 probabilities per pixel (w x h x 4) from the per-view classifier's tree marginals.
Result<std::vector<float>> Nyu4PixelProbabilities(const ViewClassifier& nyu4, const RenderedView& view);

Result<ObjectProposer> TrainObjectProposer(const ProposalTrainingOptions& options, const ViewClassifier& nyu4, ProposalTrainingSummary* summary);

}  // namespace semvox
