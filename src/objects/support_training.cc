#include "objects/support_training.h"

#include <chrono>
#include <cmath>

namespace semvox {

double ClassRecall(const ConfusionMatrix& cm, int c) { return cm.Recall(c); }

double ClassIoU(const ConfusionMatrix& cm, int c) {
  int64_t tp = cm.counts[size_t(c) * size_t(cm.m) + size_t(c)], fp = 0, fn = 0;
  for (int k = 0; k < cm.m; ++k) {
    if (k == c) continue;
    fn += cm.counts[size_t(c) * size_t(cm.m) + size_t(k)];
    fp += cm.counts[size_t(k) * size_t(cm.m) + size_t(c)];
  }
  return tp + fp + fn > 0 ? double(tp) / double(tp + fp + fn) : std::nan("");
}

nlohmann::json SupportTrainingSummary::ToJson() const {
  auto r4 = [](double v) { return std::isfinite(v) ? std::round(1e4 * v) / 1e4 : -1.0; };
  nlohmann::json j;
  j["train_views"] = train_views;
  j["val_views"] = val_views;
  j["train_rows_per_class"] = train_rows_per_class;
  j["support_vectors"] = support_vectors;
  j["ms_per_view"] = std::round(ms_per_view * 10) / 10;
  const char* names[kNumSupportClasses] = {"support", "clutter", "other"};
  for (const auto& [key, cm] : {std::pair<const char*, const ConfusionMatrix*>{"svm", &svm_only}, {"svm_crf", &crf}}) {
    for (int c = 0; c < kNumSupportClasses; ++c) {
      j[key]["recall"][names[c]] = r4(ClassRecall(*cm, c));
      j[key]["iou"][names[c]] = r4(ClassIoU(*cm, c));
    }
    j[key]["global_accuracy"] = r4(cm->GlobalAccuracy());
  }
  return j;
}

Status ValidateSupportClutter(const SupportClutterClassifier& clf, const SupportTrainingOptions& options, SupportTrainingSummary* s) {
  double ms = 0;
  for (uint64_t seed : options.val_seeds)
    SEMVOX_RETURN_IF_ERROR(ForEachSupportView(seed, options.views, options.truth, [&](const SupportView& v) {
      Result<SupportClutterView> out = clf.Classify(*v.view);
      if (!out.ok()) return out.status();
      ms += out->ms_superpixels + out->ms_features + out->ms_svm + out->ms_crf;
      Image<int32_t> svm_labels(v.view->rgb.width, v.view->rgb.height, 1, kOtherSurface);
      for (size_t i = 0; i < svm_labels.data.size(); ++i) {
        const double* p = &out->superpixel_probabilities[size_t(out->superpixels.label.data[i]) * kNumSupportClasses];
        svm_labels.data[i] = int32_t(std::max_element(p, p + kNumSupportClasses) - p);
      }
      s->svm_only.AddImages(*v.truth, svm_labels);
      s->crf.AddImages(*v.truth, out->labels);
      ++s->val_views;
      return Status::Ok();
    }));
  s->ms_per_view = s->val_views > 0 ? ms / s->val_views : 0;
  return Status::Ok();
}

Result<SupportClutterClassifier> TrainSupportClutter(const SupportTrainingOptions& options, SupportTrainingSummary* summary) {
  if (options.max_rows_per_class < 2)
    return Status::InvalidInput("max_rows_per_class = " + std::to_string(options.max_rows_per_class) + ". Violated constraint: >= 2");
  const auto t0 = std::chrono::steady_clock::now();
  SupportTrainingSummary s;
  SupportTrainingSet set;
  for (uint64_t seed : options.train_seeds)
    SEMVOX_RETURN_IF_ERROR(ForEachSupportView(seed, options.views, options.truth, [&](const SupportView& v) {
      ++s.train_views;
      return AddSupportTrainingView(*v.view, *v.truth, options.classifier, &set);
    }));
  if (options.max_other_rows < 2)
    return Status::InvalidInput("max_other_rows = " + std::to_string(options.max_other_rows) + ". Violated constraint: >= 2");
  CapRowsPerClass({options.max_rows_per_class, options.max_rows_per_class, options.max_other_rows}, &set);
  s.train_rows_per_class.assign(kNumSupportClasses, 0);
  for (int l : set.labels) ++s.train_rows_per_class[size_t(l)];
  Result<SupportClutterClassifier> clf = SupportClutterClassifier::Train(set, options.classifier, options.svm);
  if (!clf.ok()) return clf.status();
  s.support_vectors = clf->svm().num_support_vectors();
  SEMVOX_RETURN_IF_ERROR(ValidateSupportClutter(*clf, options, &s));
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (summary) *summary = std::move(s);
  return clf;
}

}  // namespace semvox
