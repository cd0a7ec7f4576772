#include "objects/support_clutter.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>

#include "perception/view_classifier.h"

namespace semvox {
namespace {

double MsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

bool SupportClutterOptions::Check(std::string* error) const {
  if (!CheckOptions(*this, Options(), error)) return false;
  if (!superpixels.Check(error) || !features.Check(error) || !crf.Check(error)) return false;
  if (!(min_label_purity > 0 && min_label_purity <= 1)) {
    if (error) *error = "min_label_purity = " + std::to_string(min_label_purity) + ". Violated constraint: 0 < min_label_purity <= 1";
    return false;
  }
  if (!(no_depth_other_probability >= 1.0 / 3 && no_depth_other_probability < 1)) {
    if (error) *error = "no_depth_other_probability = " + std::to_string(no_depth_other_probability) + ". Violated constraint: 1/3 <= value < 1";
    return false;
  }
  return true;
}

Status AddSupportTrainingView(const RenderedView& view, const Image<int32_t>& truth, const SupportClutterOptions& options,
                              SupportTrainingSet* set) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("support/clutter options: " + error);
  Result<Superpixels> sp = ComputeSuperpixels(view.rgb, options.superpixels);
  if (!sp.ok()) return sp.status();
  Result<SupportFeatures> features = ComputeSupportFeatures(view, *sp, options.features);
  if (!features.ok()) return features.status();
  const std::vector<int> classes = SuperpixelClasses(*sp, truth, options.min_label_purity);
  for (int s = 0; s < sp->count; ++s) {
    if (classes[size_t(s)] < 0 || !features->has_depth[size_t(s)]) continue;
    const float* row = &features->rows[size_t(s) * kSupportFeatureDims];
    set->rows.insert(set->rows.end(), row, row + kSupportFeatureDims);
    set->labels.push_back(classes[size_t(s)]);
  }
  return Status::Ok();
}

void CapRowsPerClass(const std::vector<int>& caps, SupportTrainingSet* set) {
  std::vector<int> count(kNumSupportClasses, 0), seen(kNumSupportClasses, 0);
  for (int l : set->labels) ++count[size_t(l)];
  SupportTrainingSet out;
  for (size_t i = 0; i < set->labels.size(); ++i) {
    const int l = set->labels[i];
    const int max_per_class = caps[size_t(l)];
    // Keep row i when it starts a new multiple of count / max_per_class (evenly spread over the views).
    const int64_t before = int64_t(seen[size_t(l)]) * max_per_class / std::max(1, count[size_t(l)]);
    const int64_t after = int64_t(seen[size_t(l)] + 1) * max_per_class / std::max(1, count[size_t(l)]);
    ++seen[size_t(l)];
    if (count[size_t(l)] > max_per_class && after == before) continue;
    out.rows.insert(out.rows.end(), set->rows.begin() + long(i * kSupportFeatureDims), set->rows.begin() + long((i + 1) * kSupportFeatureDims));
    out.labels.push_back(l);
  }
  *set = std::move(out);
}

Result<SupportClutterClassifier> SupportClutterClassifier::Train(const SupportTrainingSet& set, const SupportClutterOptions& options,
                                                                 const SvmOptions& svm_options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("support/clutter options: " + error);
  Result<SvmClassifier> svm = SvmClassifier::Train(set.rows, kSupportFeatureDims, set.labels, kNumSupportClasses, svm_options);
  if (!svm.ok()) return svm.status();
  return SupportClutterClassifier(std::move(svm).value(), options);
}

Result<SupportClutterClassifier> SupportClutterClassifier::Load(const std::string& path, const SupportClutterOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("support/clutter options: " + error);
  Result<SvmClassifier> svm = SvmClassifier::Load(path);
  if (!svm.ok()) return svm.status();
  if (svm->dims() != kSupportFeatureDims || svm->num_classes() != kNumSupportClasses)
    return Status::InvalidInput(path + ": SVM has " + std::to_string(svm->dims()) + " dims and " + std::to_string(svm->num_classes()) +
                                " classes, expected 8 and 3 (hint: not a support/clutter model; retrain with `semvox train`)");
  return SupportClutterClassifier(std::move(svm).value(), options);
}

ImageF32 PixelHeights(const RenderedView& view) {
  const int w = view.depth.width, h = view.depth.height;
  ImageF32 out(w, h, 1, 0.f);
  const Eigen::Matrix3d R = view.world_from_camera.linear();
  const Eigen::Vector3d t = view.world_from_camera.translation();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float d = view.depth.at(x, y);
      if (d > 0) out.at(x, y) = float((t + R * (view.camera.PixelRay(x, y) * double(d))).z());
    }
  return out;
}

Result<SupportClutterView> SupportClutterClassifier::Classify(const RenderedView& view) const {
  SupportClutterView out;
  auto t0 = std::chrono::steady_clock::now();
  Result<Superpixels> sp = ComputeSuperpixels(view.rgb, options_.superpixels);
  if (!sp.ok()) return sp.status();
  out.superpixels = std::move(sp).value();
  out.ms_superpixels = MsSince(t0);
  t0 = std::chrono::steady_clock::now();
  Result<SupportFeatures> features = ComputeSupportFeatures(view, out.superpixels, options_.features);
  if (!features.ok()) return features.status();
  out.features = std::move(features).value();
  out.ms_features = MsSince(t0);
  t0 = std::chrono::steady_clock::now();
  const int count = out.superpixels.count;
  out.superpixel_probabilities.assign(size_t(count) * kNumSupportClasses, 0.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, count, 16), [&](const tbb::blocked_range<int>& range) {
    for (int s = range.begin(); s < range.end(); ++s) {
      double* p = &out.superpixel_probabilities[size_t(s) * kNumSupportClasses];
      if (out.features.has_depth[size_t(s)]) {
        svm_.PredictProbabilities(&out.features.rows[size_t(s) * kSupportFeatureDims], p);
      } else {
        const double q = options_.no_depth_other_probability;
        p[kSupportSurface] = p[kClutter] = 0.5 * (1 - q);
        p[kOtherSurface] = q;
      }
    }
  });
  out.ms_svm = MsSince(t0);
  t0 = std::chrono::steady_clock::now();
  const int w = view.rgb.width, h = view.rgb.height;
  const size_t n = size_t(w) * size_t(h);
  out.probabilities.resize(n * kNumSupportClasses);
  for (size_t i = 0; i < n; ++i) {
    const int s = out.superpixels.label.data[i];
    for (int c = 0; c < kNumSupportClasses; ++c)
      out.probabilities[i * kNumSupportClasses + size_t(c)] = float(out.superpixel_probabilities[size_t(s) * kNumSupportClasses + size_t(c)]);
  }
  if (options_.use_crf) {
    const ImageF32 height = PixelHeights(view);
    Result<std::vector<float>> q =
        CoarseGridMeanField({&view.rgb, &height, &view.normal}, options_.crf, out.probabilities, kNumSupportClasses, options_.crf_grid_factor);
    if (!q.ok()) return q.status();
    out.probabilities = std::move(q).value();
  }
  out.ms_crf = MsSince(t0);
  out.labels = Image<int32_t>(w, h, 1, kOtherSurface);
  for (size_t i = 0; i < n; ++i) {
    const float* p = &out.probabilities[i * kNumSupportClasses];
    out.labels.data[i] = int32_t(std::max_element(p, p + kNumSupportClasses) - p);
  }
  return out;
}

}  // namespace semvox
