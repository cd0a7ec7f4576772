// The per-view classifier: superpixels -> observations -> k-NN unaries -> tree CRF and union-coverage CRF.
//
//   TrainingSet set;
//   AddTrainingView(view, pixel_classes, options, &set);           // for every training view
//   Result<ViewClassifier> clf = ViewClassifier::Train(set, num_classes, options);
//   Result<ViewClassification> out = clf->Classify(view);          // out->tree_labels, out->union_marginals ...
//
// Two k-NN models, as the heterogeneous-coverage paper's f1 and f2: image-only (8-D) trained on every
// labelled superpixel, image + 3D (15-D) trained on those with depth.
#pragma once

#include <string>
#include <vector>

#include "core/image.h"
#include "core/status.h"
#include "perception/belief_propagation.h"
#include "perception/crf_learning.h"
#include "perception/knn_unary.h"
#include "perception/observations.h"
#include "perception/superpixels.h"
#include "perception/view_crf.h"
#include "render/view_renderer.h"

namespace semvox {

struct ViewClassifierOptions {
  SuperpixelOptions superpixels;
  ObservationOptions observations;
  KnnOptions knn;
  ViewCrfOptions crf;        // Tree CRF (its distance_weight is unused: Eq. 6 is colour only).
  ViewCrfOptions union_crf;  // Union-coverage CRF.
  LoopyBpOptions loopy;
  // A training superpixel takes the majority class of its labelled pixels when that class covers at
  // least this fraction of them; otherwise it is not used. (0, 1].
  double min_label_purity = 0.5;

  bool Check(std::string* error) const;
};

// Rows of observations with their classes, for the two k-NN models.
struct TrainingSet {
  std::vector<float> image_features;  // kImageObservationDims per row.
  std::vector<int> image_labels;
  std::vector<float> full_features;   // kObservationDims per row (superpixels with depth only).
  std::vector<int> full_labels;
};

// Class of every superpixel: the majority class of its pixels (`pixel_classes`, -1 = ignore) when that
// class holds at least `min_label_purity` of them, else -1.
std::vector<int> SuperpixelClasses(const Superpixels& superpixels, const Image<int32_t>& pixel_classes,
                                   double min_label_purity);

// Adds the superpixels of an already segmented view: each takes the majority class of its pixels
// (`pixel_classes`, -1 = ignore) when that class holds at least `min_label_purity` of them.
void AddTrainingSuperpixels(const Superpixels& superpixels, const ViewObservations& observations,
                            const Image<int32_t>& pixel_classes, double min_label_purity, TrainingSet* set);

// Segments one view and adds its superpixels. `pixel_classes`: class per pixel in [0, num_classes), -1 = ignore.
Status AddTrainingView(const RenderedView& view, const Image<int32_t>& pixel_classes,
                       const ViewClassifierOptions& options, TrainingSet* set);

struct ViewClassification {
  Superpixels superpixels;
  ViewObservations observations;
  std::vector<std::vector<double>> knn;  // Per superpixel: f2's P_s with depth, f1's without.
  std::vector<int> knn_labels;           // Argmax of knn.
  // Per superpixel: how unlike every training superpixel it is, the mean distance to its k nearest training
  // observations of the k-NN that gave its unary over that k-NN's KnnClassifier::kFamiliarQuantile of the
  // training observations' own (KnnClassifier::TrainingNeighbourDistanceQuantile). Above 1: its class is a guess.
  std::vector<float> unfamiliarity;
  Marginals tree_marginals;              // Tree CRF (exact sum-product).
  std::vector<int> tree_labels;          // Tree CRF MAP (exact max-product).
  Marginals union_marginals;             // Union-coverage CRF (loopy BP).
  std::vector<int> union_labels;         // Argmax of union_marginals.
  LoopyBpSummary union_bp;
};

class ViewClassifier {
 public:
  static Result<ViewClassifier> Train(const TrainingSet& set, int num_classes, const ViewClassifierOptions& options);
  Result<ViewClassification> Classify(const RenderedView& view) const;
  // The same from an already segmented view (one segmentation shared by classifiers of two label levels).
  Result<ViewClassification> Classify(Superpixels superpixels, ViewObservations observations) const;

  // The tree and union CRF features of a segmented, labelled view under this classifier's k-NN unaries,
  // for LearnCrfWeights (crf_learning.h).
  Status CrfTrainingGraphs(const Superpixels& superpixels, const ViewObservations& observations,
                           const Image<int32_t>& pixel_classes, CrfTrainingGraph* tree, CrfTrainingGraph* union_graph) const;
  // Replaces the CRF weights (after learning).
  void SetCrfOptions(const ViewCrfOptions& tree, const ViewCrfOptions& union_crf) {
    options_.crf = tree;
    options_.union_crf = union_crf;
  }

  int num_classes() const { return image_knn_.num_classes(); }
  // The denominators of ViewClassification::unfamiliarity (image-only and full k-NN; the
  // KnnClassifier::kFamiliarQuantile of the training observations' own neighbour distances, over 2,000 of each).
  double image_familiar_distance() const { return image_familiar_; }
  double full_familiar_distance() const { return full_familiar_; }
  const ViewClassifierOptions& options() const { return options_; }
  // PREFIX.image_knn.bin, PREFIX.full_knn.bin and PREFIX.crf_weights.txt (tree w_u w_c; union w_u w_c
  // w_d). Load keeps `options`' weights when the weights file is absent.
  Status Save(const std::string& prefix) const;
  static Result<ViewClassifier> Load(const std::string& prefix, const ViewClassifierOptions& options);

 private:
  ViewClassifier(KnnClassifier image_knn, KnnClassifier full_knn, ViewClassifierOptions options);
  // The k-NN unaries of every superpixel: f2 from the image + 3D features where it has depth, else f2 = f1 from
  // the image features alone; f1 is left empty where there is depth (the CRFs read it only where there is none).
  // `unfamiliarity` (when given): ViewClassification::unfamiliarity.
  void KnnUnaries(const ViewObservations& observations, std::vector<std::vector<double>>* f1,
                  std::vector<std::vector<double>>* f2, std::vector<float>* unfamiliarity = nullptr) const;
  KnnClassifier image_knn_, full_knn_;
  ViewClassifierOptions options_;
  double image_familiar_ = 0, full_familiar_ = 0;
};

// Pixel-wise confusion counts: recall per class, average (mean recall) and global accuracy.
struct ConfusionMatrix {
  explicit ConfusionMatrix(int num_classes = 0) : m(num_classes), counts(size_t(num_classes) * size_t(num_classes), 0) {}
  int m;
  std::vector<int64_t> counts;  // [truth * m + predicted].
  void Add(int truth, int predicted) { ++counts[size_t(truth) * size_t(m) + size_t(predicted)]; }
  // Adds every pixel with truth >= 0.
  void AddImages(const Image<int32_t>& truth, const Image<int32_t>& predicted);
  void Merge(const ConfusionMatrix& other);
  int64_t Total() const;
  double Recall(int c) const;  // NaN when class c never occurs.
  double AverageRecall() const;  // Over the classes that occur.
  double GlobalAccuracy() const;
};

}  // namespace semvox
