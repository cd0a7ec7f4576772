#include "objects/proposal_training.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace semvox {

std::vector<Box2i> GroundTruthBoxes(const SupportView& v, const ProposalTrainingOptions& options) {
  struct Acc {
    Box2i box{1 << 30, 1 << 30, -1, -1};
    std::vector<float> depth;
  };
  std::map<int, Acc> objects;
  const int w = v.view->rgb.width, h = v.view->rgb.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (v.truth->at(x, y) != 1 /* kClutter */ || v.instance->at(x, y) < 0) continue;
      Acc& a = objects[v.instance->at(x, y)];
      a.box.x0 = std::min(a.box.x0, x), a.box.y0 = std::min(a.box.y0, y);
      a.box.x1 = std::max(a.box.x1, x + 1), a.box.y1 = std::max(a.box.y1, y + 1);
      a.depth.push_back(v.view->depth.at(x, y));
    }
  std::vector<Box2i> out;
  for (auto& [instance, a] : objects) {
    if (int(a.depth.size()) < options.min_gt_pixels) continue;
    std::nth_element(a.depth.begin(), a.depth.begin() + long(a.depth.size() / 2), a.depth.end());
    const double z = a.depth[a.depth.size() / 2];
    const double wm = a.box.width() * z / v.view->camera.fx, hm = a.box.height() * z / v.view->camera.fy;
    const ProposalOptions& p = options.proposals;
    if (wm < p.min_side_m || wm > p.max_side_m || hm < p.min_side_m || hm > p.max_side_m) continue;
    out.push_back(a.box);
  }
  return out;
}

Result<std::vector<float>> Nyu4PixelProbabilities(const ViewClassifier& nyu4, const RenderedView& view) {
  Result<ViewClassification> c = nyu4.Classify(view);
  if (!c.ok()) return c.status();
  if (c->tree_marginals.num_labels != 4) return Status::InvalidInput("NYU-4 classifier: expected 4 classes, got " + std::to_string(c->tree_marginals.num_labels));
  std::vector<float> out(c->superpixels.label.data.size() * 4);
  for (size_t i = 0; i < c->superpixels.label.data.size(); ++i)
    for (int k = 0; k < 4; ++k) out[i * 4 + size_t(k)] = float(c->tree_marginals.at(c->superpixels.label.data[i], k));
  return out;
}

double DetectionCurve::DetectionRateAt(double fppi) const {
  std::vector<std::pair<double, int>> s = scored;
  std::stable_sort(s.begin(), s.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  int tp = 0, fp = 0;
  double best = 0;
  for (const auto& [score, hit] : s) {
    (hit ? tp : fp)++;
    if (fp > fppi * views) break;
    best = std::max(best, ground_truth > 0 ? double(tp) / ground_truth : 0.0);
  }
  return best;
}

nlohmann::json ProposalTrainingSummary::ToJson() const {
  auto r4 = [](double v) { return std::round(v * 1e4) / 1e4; };
  nlohmann::json j;
  j["train_views"] = train_views;
  j["positives"] = positives;
  j["negatives"] = negatives;
  j["support_vectors"] = support_vectors;
  for (const auto& [key, c] : {std::pair<const char*, const DetectionCurve*>{"sampled", &sampled}, {"all_candidates", &all}}) {
    j[key]["val_views"] = c->views;
    j[key]["ground_truth_boxes"] = c->ground_truth;
    j[key]["candidates_per_view"] = r4(c->candidates);
    j[key]["ms_per_view"] = {{"candidates", r4(c->ms_candidates)}, {"features", r4(c->ms_features)}, {"svm", r4(c->ms_svm)}};
    for (double f : {0.5, 1.0, 2.0, 5.0, 10.0, 20.0}) j[key]["detection_rate_at_fppi"][std::to_string(f).substr(0, 4)] = r4(c->DetectionRateAt(f));
  }
  const double t_all = all.ms_features + all.ms_svm, t_sampled = sampled.ms_features + sampled.ms_svm;
  j["speedup_features_svm"] = t_sampled > 0 ? r4(t_all / t_sampled) : 0.0;
  j["candidate_ratio"] = sampled.candidates > 0 ? r4(all.candidates / sampled.candidates) : 0.0;
  return j;
}

Result<ObjectProposer> TrainObjectProposer(const ProposalTrainingOptions& options, const ViewClassifier& nyu4, ProposalTrainingSummary* summary) {
  std::string error;
  if (!options.proposals.Check(&error)) return Status::InvalidInput("proposal options: " + error);
  ProposalTrainingSummary s;
  std::vector<float> pos, neg;
  ProposalOptions all = options.proposals;
  all.sample_by_semantics = false;
  for (uint64_t seed : options.train_seeds)
    SEMVOX_RETURN_IF_ERROR(ForEachSupportView(seed, options.views, options.truth, [&](const SupportView& v) {
      ++s.train_views;
      const std::vector<Box2i> gt = GroundTruthBoxes(v, options);
      Result<std::vector<float>> p = Nyu4PixelProbabilities(nyu4, *v.view);
      if (!p.ok()) return p.status();
      Result<Superpixels> sp = ComputeSuperpixels(v.view->rgb, options.superpixels);
      if (!sp.ok()) return sp.status();
      const ClassIntegral integral = ClassIntegral::Build(v.view->rgb.width, v.view->rgb.height, *p);
      const GradientMaps gradients = GradientMaps::Compute(*v.view);
      for (const Box2i& b : gt) {
        const std::vector<float> f = WindowFeature(gradients, integral, b, options.proposals.border_px);
        pos.insert(pos.end(), f.begin(), f.end());
      }
      std::vector<CandidateWindow> candidates = CandidateWindows(*v.view, *sp, integral, all, nullptr);
      std::vector<Box2i> negatives;
      for (const CandidateWindow& c : candidates) {
        double best = 0;
        for (const Box2i& b : gt) best = std::max(best, BoxIoU(b, c.box));
        if (best < 0.3) negatives.push_back(c.box);
      }
      const size_t keep = std::min(negatives.size(), size_t(options.max_negatives_per_view));
      for (size_t k = 0; k < keep; ++k) {
        const std::vector<float> f = WindowFeature(gradients, integral, negatives[k * negatives.size() / keep], options.proposals.border_px);
        neg.insert(neg.end(), f.begin(), f.end());
      }
      return Status::Ok();
    }));
  auto thin = [](std::vector<float>* rows, int max_rows) {
    const size_t n = rows->size() / kProposalFeatureDims;
    if (n <= size_t(max_rows)) return;
    std::vector<float> out;
    for (size_t k = 0; k < size_t(max_rows); ++k) {
      const size_t i = k * n / size_t(max_rows);
      out.insert(out.end(), rows->begin() + long(i * kProposalFeatureDims), rows->begin() + long((i + 1) * kProposalFeatureDims));
    }
    *rows = std::move(out);
  };
  thin(&pos, options.max_positives);
  thin(&neg, options.max_negatives);
  s.positives = int(pos.size() / kProposalFeatureDims);
  s.negatives = int(neg.size() / kProposalFeatureDims);
  std::vector<float> rows = pos;
  rows.insert(rows.end(), neg.begin(), neg.end());
  std::vector<int> labels(size_t(s.positives), 1);
  labels.insert(labels.end(), size_t(s.negatives), 0);
  Result<ObjectProposer> proposer = ObjectProposer::Train(rows, labels, options.proposals, options.svm);
  if (!proposer.ok()) return proposer.status();
  // Validation: the same proposer with and without sampling.
  ObjectProposer& det = *proposer;
  for (uint64_t seed : options.val_seeds)
    SEMVOX_RETURN_IF_ERROR(ForEachSupportView(seed, options.views, options.truth, [&](const SupportView& v) {
      const std::vector<Box2i> gt = GroundTruthBoxes(v, options);
      Result<std::vector<float>> p = Nyu4PixelProbabilities(nyu4, *v.view);
      if (!p.ok()) return p.status();
      Result<Superpixels> sp = ComputeSuperpixels(v.view->rgb, options.superpixels);
      if (!sp.ok()) return sp.status();
      for (DetectionCurve* curve : {&s.sampled, &s.all}) {
        ProposalOptions o = options.proposals;
        o.sample_by_semantics = curve == &s.sampled;
        det.set_options(o);
        Result<ViewProposals> out = det.Propose(*v.view, *sp, *p);
        if (!out.ok()) return out.status();
        std::vector<bool> matched(gt.size(), false);
        for (const ObjectProposal& prop : out->proposals) {
          int best = -1;
          double best_iou = 0.5;
          for (size_t g = 0; g < gt.size(); ++g)
            if (!matched[g] && BoxIoU(gt[g], prop.box) >= best_iou) best_iou = BoxIoU(gt[g], prop.box), best = int(g);
          if (best >= 0) matched[size_t(best)] = true;
          curve->scored.push_back({prop.score, best >= 0 ? 1 : 0});
        }
        ++curve->views;
        curve->ground_truth += int(gt.size());
        curve->candidates += out->stats.sampled;
        curve->ms_candidates += out->ms_candidates, curve->ms_features += out->ms_features, curve->ms_svm += out->ms_svm;
      }
      return Status::Ok();
    }));
  det.set_options(options.proposals);
  for (DetectionCurve* c : {&s.sampled, &s.all})
    if (c->views > 0) {
      c->candidates /= c->views;
      c->ms_candidates /= c->views, c->ms_features /= c->views, c->ms_svm /= c->views;
    }
  s.support_vectors = det.num_support_vectors();
  if (summary) *summary = std::move(s);
  return proposer;
}

}  // namespace semvox
