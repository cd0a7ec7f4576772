#include "perception/view_classifier.h"

#include "core/file_util.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <cmath>
#include <limits>

namespace semvox {

bool ViewClassifierOptions::Check(std::string* error) const {
  if (!superpixels.Check(error) || !observations.Check(error) || !knn.Check(error) || !crf.Check(error) ||
      !union_crf.Check(error) || !loopy.Check(error))
    return false;
  if (!(min_label_purity > 0 && min_label_purity <= 1)) {
    if (error) *error = "min_label_purity = " + std::to_string(min_label_purity) + ". Violated constraint: 0 < min_label_purity <= 1";
    return false;
  }
  return true;
}

std::vector<int> SuperpixelClasses(const Superpixels& superpixels, const Image<int32_t>& pixel_classes,
                                   double min_label_purity) {
  std::vector<int> out(static_cast<size_t>(superpixels.count), -1);
  int num_classes = 0;
  for (int32_t c : pixel_classes.data) num_classes = std::max(num_classes, c + 1);
  if (num_classes == 0) return out;
  std::vector<int> votes(size_t(superpixels.count) * size_t(num_classes), 0);
  for (size_t k = 0; k < pixel_classes.data.size(); ++k)
    if (pixel_classes.data[k] >= 0) ++votes[size_t(superpixels.label.data[k]) * size_t(num_classes) + size_t(pixel_classes.data[k])];
  for (int s = 0; s < superpixels.count; ++s) {
    const int* row = &votes[size_t(s) * size_t(num_classes)];
    int total = 0;
    for (int c = 0; c < num_classes; ++c) total += row[c];
    const int best = int(std::max_element(row, row + num_classes) - row);
    if (total > 0 && row[best] >= min_label_purity * total) out[size_t(s)] = best;
  }
  return out;
}

void AddTrainingSuperpixels(const Superpixels& superpixels, const ViewObservations& observations,
                            const Image<int32_t>& pixel_classes, double min_label_purity, TrainingSet* set) {
  const std::vector<int> classes = SuperpixelClasses(superpixels, pixel_classes, min_label_purity);
  for (int s = 0; s < superpixels.count; ++s) {
    const int best = classes[size_t(s)];
    if (best < 0) continue;
    const SuperpixelObservation& o = observations.superpixels[size_t(s)];
    set->image_features.insert(set->image_features.end(), o.z.begin(), o.z.begin() + kImageObservationDims);
    set->image_labels.push_back(best);
    if (o.has_depth) {
      set->full_features.insert(set->full_features.end(), o.z.begin(), o.z.end());
      set->full_labels.push_back(best);
    }
  }
}

Status AddTrainingView(const RenderedView& view, const Image<int32_t>& pixel_classes,
                       const ViewClassifierOptions& options, TrainingSet* set) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("training view: " + error);
  if (pixel_classes.width != view.rgb.width || pixel_classes.height != view.rgb.height)
    return Status::InvalidInput("training view: class image size differs from the view's");
  Result<Superpixels> sp = ComputeSuperpixels(view.rgb, options.superpixels);
  if (!sp.ok()) return sp.status();
  Result<ViewObservations> obs = ComputeObservations(view, *sp, options.observations);
  if (!obs.ok()) return obs.status();
  AddTrainingSuperpixels(*sp, *obs, pixel_classes, options.min_label_purity, set);
  return Status::Ok();
}

Result<ViewClassifier> ViewClassifier::Train(const TrainingSet& set, int num_classes, const ViewClassifierOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("view classifier: " + error);
  Result<KnnClassifier> image = KnnClassifier::Train(set.image_features, kImageObservationDims, set.image_labels, num_classes, options.knn);
  if (!image.ok()) return Status::InvalidInput("image-only k-NN: " + image.status().message());
  Result<KnnClassifier> full = KnnClassifier::Train(set.full_features, kObservationDims, set.full_labels, num_classes, options.knn);
  if (!full.ok()) return Status::InvalidInput("image+3D k-NN: " + full.status().message());
  return ViewClassifier(std::move(image).value(), std::move(full).value(), options);
}

namespace {
constexpr size_t kFamiliarRows = 2000;  // Training observations the familiar distance is measured over.
}  // namespace

ViewClassifier::ViewClassifier(KnnClassifier image_knn, KnnClassifier full_knn, ViewClassifierOptions options)
    : image_knn_(std::move(image_knn)), full_knn_(std::move(full_knn)), options_(std::move(options)) {
  image_familiar_ = image_knn_.TrainingNeighbourDistanceQuantile(KnnClassifier::kFamiliarQuantile, kFamiliarRows);
  full_familiar_ = full_knn_.TrainingNeighbourDistanceQuantile(KnnClassifier::kFamiliarQuantile, kFamiliarRows);
}

void ViewClassifier::KnnUnaries(const ViewObservations& observations, std::vector<std::vector<double>>* f1,
                                std::vector<std::vector<double>>* f2, std::vector<float>* unfamiliarity) const {
  const size_t n = observations.superpixels.size();
  f1->assign(n, {});
  f2->assign(n, {});
  if (unfamiliarity) unfamiliarity->assign(n, 0.f);
  for (size_t s = 0; s < n; ++s) {
    const SuperpixelObservation& o = observations.superpixels[s];
    double distance = 0;
    double familiar = 0;
    if (o.has_depth) {
      (*f2)[s] = full_knn_.Probabilities({o.z.data(), size_t(kObservationDims)}, &distance);
      familiar = full_familiar_;
    } else {
      (*f1)[s] = (*f2)[s] = image_knn_.Probabilities({o.z.data(), size_t(kImageObservationDims)}, &distance);
      familiar = image_familiar_;
    }
    if (unfamiliarity) (*unfamiliarity)[s] = familiar > 0 ? float(distance / familiar) : std::numeric_limits<float>::quiet_NaN();
  }
}

Result<ViewClassification> ViewClassifier::Classify(const RenderedView& view) const {
  Result<Superpixels> sp = ComputeSuperpixels(view.rgb, options_.superpixels);
  if (!sp.ok()) return sp.status();
  Result<ViewObservations> obs = ComputeObservations(view, *sp, options_.observations);
  if (!obs.ok()) return obs.status();
  return Classify(std::move(sp).value(), std::move(obs).value());
}

Result<ViewClassification> ViewClassifier::Classify(Superpixels superpixels, ViewObservations observations) const {
  if (int(observations.superpixels.size()) != superpixels.count)
    return Status::InvalidInput("classify: observations do not match the superpixels");
  ViewClassification out;
  out.superpixels = std::move(superpixels);
  out.observations = std::move(observations);
  const size_t n = out.observations.superpixels.size();
  std::vector<std::vector<double>> f1, f2;
  KnnUnaries(out.observations, &f1, &f2, &out.unfamiliarity);
  out.knn = f2;  // f2 with depth, f1 without.
  out.knn_labels.resize(n);
  for (size_t s = 0; s < n; ++s)
    out.knn_labels[s] = int(std::max_element(out.knn[s].begin(), out.knn[s].end()) - out.knn[s].begin());
  // Tree CRF: f on every node (f2 with depth, f1 without), Eq. 6 colour pairwise on the 3D MST.
  Result<PairwiseModel> tree = BuildViewCrf(out.observations, BuildTreeGraph(out.observations), out.knn, {}, false, options_.crf);
  if (!tree.ok()) return tree.status();
  SEMVOX_RETURN_IF_ERROR(TreeSumProduct(*tree, &out.tree_marginals));
  SEMVOX_RETURN_IF_ERROR(TreeMaxProduct(*tree, &out.tree_labels));
  // Union-coverage CRF: f2 with depth, f1 without; g1 everywhere, g2 on 3D edges; loopy BP.
  Result<PairwiseModel> uni = BuildViewCrf(out.observations, BuildUnionCoverageGraph(out.observations), f2, f1, true, options_.union_crf);
  if (!uni.ok()) return uni.status();
  SEMVOX_RETURN_IF_ERROR(LoopyBeliefPropagation(*uni, options_.loopy, &out.union_marginals, &out.union_bp));
  out.union_labels = DecodeMaxMarginals(out.union_marginals);
  return out;
}

Status ViewClassifier::Save(const std::string& prefix) const {
  SEMVOX_RETURN_IF_ERROR(image_knn_.Save(prefix + ".image_knn.bin"));
  SEMVOX_RETURN_IF_ERROR(full_knn_.Save(prefix + ".full_knn.bin"));
  char text[256];
  std::snprintf(text, sizeof(text), "tree %.17g %.17g\nunion %.17g %.17g %.17g\n", options_.crf.unary_weight,
                options_.crf.colour_weight, options_.union_crf.unary_weight, options_.union_crf.colour_weight,
                options_.union_crf.distance_weight);
  return WriteFileAtomic(prefix + ".crf_weights.txt", text);
}

Result<ViewClassifier> ViewClassifier::Load(const std::string& prefix, const ViewClassifierOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("view classifier: " + error);
  Result<KnnClassifier> image = KnnClassifier::Load(prefix + ".image_knn.bin");
  if (!image.ok()) return image.status();
  Result<KnnClassifier> full = KnnClassifier::Load(prefix + ".full_knn.bin");
  if (!full.ok()) return full.status();
  if (image->dims() != kImageObservationDims || full->dims() != kObservationDims || image->num_classes() != full->num_classes())
    return Status::InvalidInput(FileError(prefix, "k-NN models do not match (dimensions or classes)", "re-run `semvox train`"));
  ViewClassifierOptions effective = options;
  std::ifstream weights(prefix + ".crf_weights.txt");
  if (weights) {
    std::string tree_tag, union_tag;
    ViewCrfOptions tree = options.crf, uni = options.union_crf;
    if (!(weights >> tree_tag >> tree.unary_weight >> tree.colour_weight >> union_tag >> uni.unary_weight >>
          uni.colour_weight >> uni.distance_weight) || tree_tag != "tree" || union_tag != "union" ||
        !tree.Check(nullptr) || !uni.Check(nullptr))
      return Status::InvalidInput(FileError(prefix + ".crf_weights.txt", "expected 'tree W_U W_C' and 'union W_U W_C W_D' with weights >= 0",
                                            "re-run `semvox train`"));
    effective.crf = tree;
    effective.union_crf = uni;
  }
  return ViewClassifier(std::move(image).value(), std::move(full).value(), effective);
}

Status ViewClassifier::CrfTrainingGraphs(const Superpixels& superpixels, const ViewObservations& observations,
                                         const Image<int32_t>& pixel_classes, CrfTrainingGraph* tree,
                                         CrfTrainingGraph* union_graph) const {
  const size_t n = observations.superpixels.size();
  if (int(n) != superpixels.count) return Status::InvalidInput("CRF training graphs: observations do not match the superpixels");
  std::vector<std::vector<double>> f1, f2;
  KnnUnaries(observations, &f1, &f2);
  const std::vector<int> labels = SuperpixelClasses(superpixels, pixel_classes, options_.min_label_purity);
  *tree = MakeCrfTrainingGraph(observations, BuildTreeGraph(observations), f2, {}, false, options_.crf, labels);
  *union_graph = MakeCrfTrainingGraph(observations, BuildUnionCoverageGraph(observations), f2, f1, true, options_.union_crf, labels);
  return Status::Ok();
}

void ConfusionMatrix::AddImages(const Image<int32_t>& truth, const Image<int32_t>& predicted) {
  for (size_t k = 0; k < truth.data.size(); ++k)
    if (truth.data[k] >= 0 && truth.data[k] < m && predicted.data[k] >= 0 && predicted.data[k] < m) Add(truth.data[k], predicted.data[k]);
}

void ConfusionMatrix::Merge(const ConfusionMatrix& other) {
  for (size_t k = 0; k < counts.size(); ++k) counts[k] += other.counts[k];
}

int64_t ConfusionMatrix::Total() const {
  int64_t t = 0;
  for (int64_t c : counts) t += c;
  return t;
}

double ConfusionMatrix::Recall(int c) const {
  int64_t row = 0;
  for (int p = 0; p < m; ++p) row += counts[size_t(c) * size_t(m) + size_t(p)];
  return row > 0 ? double(counts[size_t(c) * size_t(m) + size_t(c)]) / double(row) : std::numeric_limits<double>::quiet_NaN();
}

double ConfusionMatrix::AverageRecall() const {
  double s = 0;
  int k = 0;
  for (int c = 0; c < m; ++c) {
    const double r = Recall(c);
    if (!std::isnan(r)) {
      s += r;
      ++k;
    }
  }
  return k > 0 ? s / k : std::numeric_limits<double>::quiet_NaN();
}

double ConfusionMatrix::GlobalAccuracy() const {
  int64_t diag = 0;
  for (int c = 0; c < m; ++c) diag += counts[size_t(c) * size_t(m) + size_t(c)];
  const int64_t t = Total();
  return t > 0 ? double(diag) / double(t) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace semvox
