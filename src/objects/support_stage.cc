#include "objects/support_stage.h"

#include <chrono>
#include <filesystem>
#include <sstream>

namespace semvox {

bool SupportStageOptions::Check(std::string* error) const {
  return CheckOptions(*this, Options(), error) && classifier.Check(error) && fusion.Check(error) && proposal.Check(error);
}

std::string SupportStageSummary::BriefReport() const {
  std::ostringstream s;
  s << "support/clutter: " << views << " views, " << voxels << " voxels (" << support_voxels << " support, " << clutter_voxels
    << " clutter), " << proposals << " object proposals; " << int(ms_classify / std::max(1, views)) << " ms per view classification, "
    << int(ms_proposals / std::max(1, views)) << " ms per view proposals";
  return s.str();
}

Result<std::unique_ptr<SupportClutterStage>> SupportClutterStage::Create(const SupportStageOptions& options, const std::string& models_dir) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("support stage options: " + error);
  Result<SupportClutterClassifier> clf = SupportClutterClassifier::Load(models_dir + "/support_clutter.svm", options.classifier);
  if (!clf.ok()) return clf.status();
  std::unique_ptr<SupportClutterStage> stage(new SupportClutterStage(options, std::move(clf).value()));
  if (options.proposals) {
    Result<ViewClassifier> nyu4 = ViewClassifier::Load(models_dir + "/nyu4", ViewClassifierOptions{});
    if (!nyu4.ok()) return nyu4.status();
    stage->nyu4_ = std::make_unique<ViewClassifier>(std::move(nyu4).value());
    Result<ObjectProposer> det = ObjectProposer::Load(models_dir + "/object_proposals.svm", options.proposal);
    if (!det.ok()) return det.status();
    stage->proposer_ = std::make_unique<ObjectProposer>(std::move(det).value());
  }
  return stage;
}

Result<SupportClutterStage::ViewResult> SupportClutterStage::Process(const RenderedView& view, const ViewClassification* segmented) const {
  ViewResult r;
  auto t0 = std::chrono::steady_clock::now();
  Result<SupportClutterView> out = classifier_.Classify(view);
  if (!out.ok()) return out.status();
  r.ms_classify = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (proposer_) {
    t0 = std::chrono::steady_clock::now();
    const bool reuse = segmented && segmented->superpixels.label.width == view.camera.width &&
                       segmented->superpixels.label.height == view.camera.height;
    Result<ViewClassification> c = reuse ? nyu4_->Classify(segmented->superpixels, segmented->observations) : nyu4_->Classify(view);
    if (!c.ok()) return c.status();
    std::vector<float> p(c->superpixels.label.data.size() * 4);
    for (size_t i = 0; i < c->superpixels.label.data.size(); ++i)
      for (int k = 0; k < 4; ++k) p[i * 4 + size_t(k)] = float(c->tree_marginals.at(c->superpixels.label.data[i], k));
    Result<ViewProposals> props = proposer_->Propose(view, out->superpixels, p);
    if (!props.ok()) return props.status();
    r.proposals = std::move(props->proposals);
    r.ms_proposals = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  r.probabilities = std::move(out->probabilities);
  return r;
}

Status SupportClutterStage::Add(const RenderedView& view, ViewResult result) {
  SEMVOX_RETURN_IF_ERROR(fusion_.AddView(view, result.probabilities));
  if (proposer_) merger_.Add(result.proposals);
  summary_.ms_classify += result.ms_classify;
  summary_.ms_proposals += result.ms_proposals;
  ++summary_.views;
  return Status::Ok();
}

Status SupportClutterStage::AddView(const RenderedView& view) {
  Result<ViewResult> r = Process(view);
  if (!r.ok()) return r.status();
  return Add(view, std::move(r).value());
}

Status SupportClutterStage::Write(const std::string& outdir, const VoxelGrid& grid, const Eigen::Isometry3d& input_from_world) const {
  namespace fs = std::filesystem;
  SEMVOX_RETURN_IF_ERROR(fusion_.WritePly((fs::path(outdir) / "support_clutter.ply").string(), input_from_world));
  SEMVOX_RETURN_IF_ERROR(fusion_.WriteTopView((fs::path(outdir) / "support_clutter_topview.png").string(), grid));
  if (proposer_) SEMVOX_RETURN_IF_ERROR(merger_.WriteJson((fs::path(outdir) / "object_proposals.json").string(), &fusion_, options_.fusion.voxel_size_m, input_from_world));
  return Status::Ok();
}

SupportStageSummary SupportClutterStage::summary() const {
  SupportStageSummary s = summary_;
  s.voxels = fusion_.num_voxels();
  for (const SupportVoxel& v : fusion_.Voxels()) s.support_voxels += v.label == 1, s.clutter_voxels += v.label == 2;
  s.proposals = merger_.merged().size();
  return s;
}

}  // namespace semvox
