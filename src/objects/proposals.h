// Generic object proposals: the MST-CRF paper's "priming object detection" (Sec. 4).
//
//   Result<std::vector<CandidateWindow>> c = CandidateWindows(view, superpixels, nyu4, options);  // Sec. 4.1/4.2
//   std::vector<float> f = WindowFeature(gradients, nyu4_integral, box, options);                  // 76-D
//   Result<ObjectProposer> det = ObjectProposer::Train(rows, labels, options);                     // HI-kernel SVM
//   Result<ViewProposals> out = det->Propose(view, superpixels, nyu4);                             // scored 2D + 3D boxes
//   ProposalMerger merger;  merger.Add(out->proposals);  merger.WriteJson("object_proposals.json", &fusion);
//
// Candidates: bounding boxes of every region of a hierarchical grouping of the superpixels (selective
// search, the paper's [40]: greedy merging of the most similar neighbours by colour-histogram intersection,
// size and fill), kept when both metric sides (from the median depth in the box) lie in [5, 50] cm. With
// `sample_by_semantics` a candidate is kept with probability p(furniture) + p(props) averaged over the box
// (Sec. 4.2; a hash of the seed and the box, so the draw does not depend on the order of evaluation).
// Feature: gradient-orientation histograms (0-360 deg, 9 bins, magnitude weighted, each L1-normalised) of
// intensity and depth in the four blocks around the box border between the box shrunk and enlarged by 5 px
// (2 x 4 x 9 = 72), plus the four NYU-4 class probabilities averaged over the box and renormalised (76-D).
// Classifier: SVM with the histogram-intersection kernel; the score is its probability of "object".
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/option_table.h"
#include "core/status.h"
#include "objects/svm_classifier.h"
#include "perception/superpixels.h"
#include "render/view_renderer.h"

namespace semvox {

class SupportClutterFusion;

inline constexpr int kBoundaryFeatureDims = 72;
inline constexpr int kProposalFeatureDims = 76;

struct ProposalOptions {
  double min_side_m = 0.05;          // Objects' sides between these (the paper: 5 and 50 cm). > 0.
  double max_side_m = 0.50;          // >= min_side_m.
  int border_px = 5;                 // Blocks between the box shrunk and enlarged by this. >= 1.
  int colour_bins = 16;              // Per RGB channel, for the grouping's colour similarity. [2, 64].
  bool sample_by_semantics = true;   // Keep a candidate with probability p(furniture) + p(props).
  uint64_t seed = 1;                 // For that draw.
  double nms_iou = 0.5;              // Non-maximum suppression between scored boxes of a view. (0, 1].
  int max_per_view = 50;             // Best boxes kept per view after suppression. >= 1.
  double min_score = 0.0;
  double depth_band_m = 0.25;        // 3D box: pixels within this of the box's median depth. > 0.

  // The fields users set (section `objects`): meaning, unit and range.
  static const OptionTable<ProposalOptions>& Options() {
    using O = ProposalOptions;
    static const OptionTable<O> table = {
        OptionNumber(&O::min_score, "min_score", 0, 1, "",
                     "proposals scoring below this (the SVM's probability of an object) are dropped"),
    };
    return table;
  }
  bool Check(std::string* error) const;
};

struct Box2i {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // Pixels [x0, x1) x [y0, y1).
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  bool operator==(const Box2i& o) const { return x0 == o.x0 && y0 == o.y0 && x1 == o.x1 && y1 == o.y1; }
};
double BoxIoU(const Box2i& a, const Box2i& b);

struct CandidateWindow {
  Box2i box;
  double semantic = 0;           // Mean p(furniture) + p(props) in the box.
  double width_m = 0, height_m = 0;
};

// Per-pixel NYU-4 probabilities (ground, structure, furniture, props), w x h x 4, as integral images for
// O(1) box means.
struct ClassIntegral {
  int width = 0, height = 0;
  std::vector<double> sum;  // (w + 1) x (h + 1) x 4.
  static ClassIntegral Build(int width, int height, const std::vector<float>& probabilities);
  std::array<double, 4> Mean(const Box2i& box) const;
};

struct GradientMaps {
  ImageF32 intensity_magnitude, intensity_bin, depth_magnitude, depth_bin;  // bin in [0, 9), as float.
  static GradientMaps Compute(const RenderedView& view);
};

struct CandidateStats {
  int regions = 0, windows = 0, sized = 0, sampled = 0;  // After grouping, dedup, size filter, sampling.
};

// Candidate windows of one view. `nyu4`: w x h x 4 probabilities (may be empty when sampling is off).
std::vector<CandidateWindow> CandidateWindows(const RenderedView& view, const Superpixels& superpixels, const ClassIntegral& nyu4,
                                              const ProposalOptions& options, CandidateStats* stats);

// The 76-D feature of one box.
std::vector<float> WindowFeature(const GradientMaps& gradients, const ClassIntegral& nyu4, const Box2i& box, int border_px);

struct ObjectProposal {
  Box2i box;
  double score = 0;
  bool has_3d = false;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero(), size = Eigen::Vector3d::Zero();  // World, metres.
};

struct ViewProposals {
  std::vector<ObjectProposal> proposals;  // Best first, after suppression.
  CandidateStats stats;
  double ms_candidates = 0, ms_features = 0, ms_svm = 0;
};

class ObjectProposer {
 public:
  // rows: n x 76; labels 1 object, 0 background.
  static Result<ObjectProposer> Train(const std::vector<float>& rows, const std::vector<int>& labels, const ProposalOptions& options,
                                      const SvmOptions& svm_options);
  Result<ViewProposals> Propose(const RenderedView& view, const Superpixels& superpixels, const std::vector<float>& nyu4) const;
  double Score(const std::vector<float>& feature) const;

  Status Save(const std::string& path) const { return svm_.Save(path); }
  static Result<ObjectProposer> Load(const std::string& path, const ProposalOptions& options);
  const ProposalOptions& options() const { return options_; }
  void set_options(const ProposalOptions& options) { options_ = options; }
  int num_support_vectors() const { return svm_.num_support_vectors(); }

 private:
  ObjectProposer(SvmClassifier svm, ProposalOptions options) : svm_(std::move(svm)), options_(options) {}
  SvmClassifier svm_;
  ProposalOptions options_;
};

// The 3D box of a 2D box: world points of its pixels within depth_band_m of the median depth, 5th to 95th
// percentile per axis. False when fewer than 10 pixels have depth.
bool BackProject(const RenderedView& view, const Box2i& box, double depth_band_m, Eigen::Vector3d* centre, Eigen::Vector3d* size);

// 3D proposals merged across views: a proposal joins the first merged box it overlaps with 3D IoU >= min_iou
// (score-weighted mean of centre and size, best score kept), else starts a new one.
class ProposalMerger {
 public:
  explicit ProposalMerger(double min_iou = 0.25) : min_iou_(min_iou) {}
  void Add(const std::vector<ObjectProposal>& proposals);
  struct Merged {
    Eigen::Vector3d centre, size;
    double score = 0, weight = 0;
    int views = 0;
  };
  const std::vector<Merged>& merged() const { return merged_; }
  // object_proposals.json: {"proposals": [{"centre": [x, y, z], "size": [dx, dy, dz], "score": s, "views": n,
  // "supporting_surface": {"z": top of the support voxels under it, "voxels": n} or null}], ...}, best first.
  // The supporting surface is looked up among `fusion`'s support voxels (may be null). Atomic.
  // Centres and supporting-surface heights mapped by `input_from_world` (the canonical frame back to the
  // input frame); sizes stay along the canonical axes.
  Status WriteJson(const std::string& path, const SupportClutterFusion* fusion, double voxel_size_m,
                   const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity()) const;

 private:
  double min_iou_;
  std::vector<Merged> merged_;
};

}  // namespace semvox
