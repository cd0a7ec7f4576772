// The object-search-priors stage of `semvox run`: per view support / clutter / other and generic
// object proposals, fused over the views; exports support_clutter.ply, support_clutter_topview.png and
// object_proposals.json.
//
//   Result<std::unique_ptr<SupportClutterStage>> stage = SupportClutterStage::Create(SupportStageOptions{}, models_dir);
//   for (each rendered view, RenderOptions::voxel_size_m = grid resolution)  (*stage)->AddView(view);
//   (*stage)->Write(outdir, grid);
//   (*stage)->summary().BriefReport()
//
// The classification (superpixels, features, SVM, dense CRF) runs on the view as rendered: 320 x 240
// matches the training views' resolution (the CRF's pixel scales and the SLIC size are in pixels).
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>

#include "core/option_table.h"
#include "core/status.h"
#include "core/voxel_grid.h"
#include "objects/proposals.h"
#include "objects/support_clutter.h"
#include "objects/support_fusion.h"
#include "perception/view_classifier.h"
#include "render/view_renderer.h"

namespace semvox {

struct SupportStageOptions {
  bool enabled = true;                    // Needs semantic.enabled.
  SupportClutterOptions classifier;
  SupportFusionOptions fusion;            // voxel_size_m: the map's resolution.
  bool proposals = true;                  // Needs nyu4.* and object_proposals.svm.
  ProposalOptions proposal = [] {
    ProposalOptions o;
    o.min_score = 0.5;
    return o;
  }();
  double merge_iou = 0.25;

  // The fields users set (section `objects`, with those of classifier, fusion and proposal): meaning, unit and range.
  static const OptionTable<SupportStageOptions>& Options() {
    using O = SupportStageOptions;
    static const OptionTable<O> table = JoinOptions<O>({
        {
            OptionSwitch(&O::enabled, "enabled",
                         "classify support / clutter / other in every classification view (needs semantic.enabled): "
                         "support_clutter.ply, support_clutter_topview.png"),
            OptionSwitch(&O::proposals, "proposals", "also generic object proposals, merged across views: object_proposals.json"),
        },
        NestedOptions(&O::classifier, SupportClutterOptions::Options()),
        NestedOptions(&O::fusion, SupportFusionOptions::Options()),
        NestedOptions(&O::proposal, ProposalOptions::Options()),
        {OptionNumber(&O::merge_iou, "merge_iou", 0.01, 1, "", "3D IoU at which proposals of different views merge")},
    });
    return table;
  }
  bool Check(std::string* error) const;
};

struct SupportStageSummary {
  int views = 0;
  size_t voxels = 0, support_voxels = 0, clutter_voxels = 0, proposals = 0;
  double ms_classify = 0, ms_proposals = 0;  // Total.
  std::string BriefReport() const;
};

class SupportClutterStage {
 public:
  // Loads MODELS/support_clutter.svm and, with proposals, MODELS/nyu4.* and MODELS/object_proposals.svm.
  static Result<std::unique_ptr<SupportClutterStage>> Create(const SupportStageOptions& options, const std::string& models_dir);
  // One view's results before fusion.
  struct ViewResult {
    std::vector<float> probabilities;  // w x h x 3 (support, clutter, other).
    std::vector<ObjectProposal> proposals;
    double ms_classify = 0, ms_proposals = 0;
  };
  // Classifies one view and (with proposals) finds its 3D proposals. Const and safe to call on several
  // views at once; the results then go to Add in view order, so the fused outputs do not depend on threads.
  // `segmented`: the view's classification by a per-view classifier with the default segmentation
  // (ViewClassifierOptions' superpixels and observations, as the proposals' NYU-4 classifier uses); its
  // superpixels and observations are reused instead of segmenting the view again. Null: segment here.
  Result<ViewResult> Process(const RenderedView& view, const ViewClassification* segmented = nullptr) const;
  // Fuses one processed view's probabilities and merges its proposals.
  Status Add(const RenderedView& view, ViewResult result);
  // Process then Add.
  Status AddView(const RenderedView& view);
  // OUTDIR/support_clutter.ply, OUTDIR/support_clutter_topview.png (on `grid`), OUTDIR/object_proposals.json.
  // Coordinates in support_clutter.ply and object_proposals.json are mapped by `input_from_world`.
  Status Write(const std::string& outdir, const VoxelGrid& grid, const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity()) const;
  // Counts of the fused voxels and merged proposals so far, and the time spent.
  SupportStageSummary summary() const;
  const SupportClutterFusion& fusion() const { return fusion_; }

 private:
  SupportClutterStage(SupportStageOptions options, SupportClutterClassifier classifier)
      : options_(std::move(options)), classifier_(std::move(classifier)), fusion_(options_.fusion), merger_(options_.merge_iou) {}
  SupportStageOptions options_;
  SupportClutterClassifier classifier_;
  std::unique_ptr<ViewClassifier> nyu4_;
  std::unique_ptr<ObjectProposer> proposer_;
  SupportClutterFusion fusion_;
  ProposalMerger merger_;
  SupportStageSummary summary_;
};

}  // namespace semvox
