// Support structure / clutter / other for every pixel of a view: the support/clutter paper's pipeline
// (Sec. 3): SLIC superpixels -> Table 2 features -> RBF SVM with probability outputs (Sec. 4.2, Wu et al.
// 2004 pairwise coupling) -> unary of a fully connected pixel CRF with appearance, smoothness, height and
// normal kernels solved by mean-field (Sec. 5, dense_crf.h).
//
//   SupportTrainingSet set;
//   AddSupportTrainingView(view, truth, options, &set);        // truth: SupportClass per pixel, -1 ignore
//   Result<SupportClutterClassifier> clf = SupportClutterClassifier::Train(set, options, SvmOptions{});
//   Result<SupportClutterView> out = clf->Classify(view);      // out->probabilities: w x h x 3
//
// Classes: support (surfaces that hold objects: table tops, counters, shelf boards, ...; the floor is not
// one, as in the paper: "support structures can not lie on the ground"), clutter (small objects on them),
// other. The probability order everywhere is (support, clutter, other).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/option_table.h"
#include "core/status.h"
#include "objects/dense_crf.h"
#include "objects/support_features.h"
#include "objects/svm_classifier.h"
#include "perception/superpixels.h"
#include "render/view_renderer.h"

namespace semvox {

enum SupportClass : int { kSupportSurface = 0, kClutter = 1, kOtherSurface = 2 };
inline constexpr int kNumSupportClasses = 3;
// Label written to support_clutter.ply: 1 support, 2 clutter, 0 other.
inline uint8_t SupportPlyLabel(int support_class) { return support_class == kOtherSurface ? 0 : uint8_t(support_class + 1); }

struct SupportClutterOptions {
  // SLIC at 12 px: clutter (books, boxes, paper) is small; at 20 px (the per-view classifier's) the validation
  // clutter recall of the SVM drops from 0.42 to 0.22 (seeds 0-5 / 100-101, docs/objects.md).
  SuperpixelOptions superpixels = [] {
    SuperpixelOptions o;
    o.region_size_px = 12;
    return o;
  }();
  SupportFeatureOptions features;
  DenseCrfOptions crf;
  bool use_crf = true;
  // The dense CRF's messages on a grid this many times coarser than the view (CoarseGridMeanField in
  // dense_crf.h; each pixel's last update keeps its own unary): 2 takes a quarter of the 1's time with the
  // validation scores of docs/objects.md. [1, 8].
  int crf_grid_factor = 2;
  // A training superpixel takes the majority class of its labelled pixels when that class covers at least
  // this fraction of them. (0, 1].
  double min_label_purity = 0.6;
  // Superpixels without depth (holes, beyond max depth) are "other" with this probability (the rest split
  // evenly): with no 3D cue the SVM's features mean nothing. [1/3, 1).
  double no_depth_other_probability = 0.9;

  // The fields users set (section `objects`): meaning, unit and range.
  static const OptionTable<SupportClutterOptions>& Options() {
    using O = SupportClutterOptions;
    static const OptionTable<O> table = JoinOptions<O>({
        {OptionSwitch(&O::use_crf, "use_crf",
                      "dense pixel CRF on the SVM's superpixel probabilities (false: the SVM's output)")},
        {OptionNumber(&O::crf_grid_factor, "crf_grid_factor", 1, 8, "",
                      "dense CRF messages on a grid this many times coarser than the view, each pixel's last update at full resolution (1: every pixel)")},
        NestedOptions(&O::crf, DenseCrfOptions::Options()),
    });
    return table;
  }
  bool Check(std::string* error) const;
};

struct SupportTrainingSet {
  std::vector<float> rows;  // kSupportFeatureDims per row.
  std::vector<int> labels;  // SupportClass.
};

// Segments `view`, computes its features and adds every superpixel with depth whose pixels' majority class
// (`truth`, SupportClass or -1) is pure enough.
Status AddSupportTrainingView(const RenderedView& view, const Image<int32_t>& truth, const SupportClutterOptions& options,
                              SupportTrainingSet* set);
// Keeps at most max_per_class[c] rows of class c (an even stride over the rows: deterministic).
void CapRowsPerClass(const std::vector<int>& max_per_class, SupportTrainingSet* set);

struct SupportClutterView {
  Superpixels superpixels;
  SupportFeatures features;
  std::vector<double> superpixel_probabilities;  // count x 3: the SVM's unary.
  std::vector<float> probabilities;              // width x height x 3: CRF marginals (or the unary).
  Image<int32_t> labels;                         // Argmax per pixel (SupportClass).
  double ms_superpixels = 0, ms_features = 0, ms_svm = 0, ms_crf = 0;
};

class SupportClutterClassifier {
 public:
  static Result<SupportClutterClassifier> Train(const SupportTrainingSet& set, const SupportClutterOptions& options,
                                                const SvmOptions& svm_options);
  Result<SupportClutterView> Classify(const RenderedView& view) const;

  Status Save(const std::string& path) const { return svm_.Save(path); }
  static Result<SupportClutterClassifier> Load(const std::string& path, const SupportClutterOptions& options);

  const SupportClutterOptions& options() const { return options_; }
  const SvmClassifier& svm() const { return svm_; }

 private:
  SupportClutterClassifier(SvmClassifier svm, SupportClutterOptions options) : svm_(std::move(svm)), options_(std::move(options)) {}
  SvmClassifier svm_;
  SupportClutterOptions options_;
};

// World z of every pixel's hit (0 without depth), for the CRF's height kernel.
ImageF32 PixelHeights(const RenderedView& view);

}  // namespace semvox
