#include "objects/proposals.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "objects/support_fusion.h"
#include "render/camera.h"
#include "tests/perception/test_views.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

// A 20 cm box (30 x 30 px at 1 m depth, focal 150 px) in front of a uniform wall 1.5 m away.
RenderedView BoxScene() {
  return testing::MakeView(300, 200, Eigen::Isometry3d::Identity(), [](int x, int y) {
    testing::PixelSample s;
    const bool box = x >= 120 && x < 150 && y >= 75 && y < 105;
    s.depth = box ? 1.0f : 1.5f;
    s.normal = Eigen::Vector3f(0, 0, -1);
    s.color = box ? Rgb8{200, 40, 40} : Rgb8{90, 90, 100};
    return s;
  });
}

Superpixels Grid(int w, int h, int cell) {
  Superpixels sp;
  sp.label = Image<int32_t>(w, h, 1, 0);
  const int cols = (w + cell - 1) / cell;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) sp.label.at(x, y) = (y / cell) * cols + x / cell;
  sp.count = cols * ((h + cell - 1) / cell);
  return sp;
}

TEST(ObjectProposals, HierarchicalGroupingFindsTheObjectsBox) {
  const RenderedView view = BoxScene();
  ASSERT_NEAR(view.camera.fx, 150.0, 1e-9);
  const Superpixels sp = Grid(300, 200, 15);  // The object is exactly 2 x 2 cells.
  ProposalOptions options;
  options.sample_by_semantics = false;
  CandidateStats stats;
  const ClassIntegral uniform = ClassIntegral::Build(300, 200, {});
  const std::vector<CandidateWindow> c = CandidateWindows(view, sp, uniform, options, &stats);
  double best = 0;
  for (const CandidateWindow& w : c) {
    best = std::max(best, BoxIoU(w.box, Box2i{120, 75, 150, 105}));
    EXPECT_GE(w.width_m, options.min_side_m);
    EXPECT_LE(w.height_m, options.max_side_m);
  }
  EXPECT_DOUBLE_EQ(best, 1.0);
  EXPECT_EQ(stats.regions, 2 * sp.count - 1);  // A full merge hierarchy over a connected image.
  EXPECT_LT(stats.sized, stats.windows);
}

TEST(ObjectProposals, SamplingKeepsCandidatesByTheirSemanticProbability) {
  const RenderedView view = BoxScene();
  const Superpixels sp = Grid(300, 200, 15);
  // p(furniture) + p(props) = 0 everywhere: sampling keeps nothing; = 1: everything.
  for (float object : {0.f, 1.f}) {
    std::vector<float> p(300 * 200 * 4, 0.f);
    for (size_t i = 0; i < p.size(); i += 4) p[i + 3] = object, p[i + 1] = 1 - object;
    ProposalOptions options;
    CandidateStats stats;
    CandidateWindows(view, sp, ClassIntegral::Build(300, 200, p), options, &stats);
    EXPECT_EQ(stats.sampled, object > 0 ? stats.sized : 0);
  }
}

TEST(ObjectProposals, BoundaryFeatureIsNormalisedPerBlockAndCarriesClassProbabilities) {
  const RenderedView view = BoxScene();
  const GradientMaps g = GradientMaps::Compute(view);
  std::vector<float> p(300 * 200 * 4, 0.f);
  for (size_t i = 0; i < p.size(); i += 4) p[i + 2] = 0.25f, p[i + 3] = 0.75f;
  const std::vector<float> f = WindowFeature(g, ClassIntegral::Build(300, 200, p), Box2i{120, 75, 150, 105}, 5);
  ASSERT_EQ(f.size(), size_t(kProposalFeatureDims));
  for (int block = 0; block < 8; ++block) {
    double s = 0;
    for (int b = 0; b < 9; ++b) s += f[size_t(block * 9 + b)];
    EXPECT_NEAR(s, 1.0, 1e-5) << "block " << block;  // Every block crosses the object's edge.
  }
  // The top block's intensity gradient points down into the brighter-red... at least one bin dominates.
  EXPECT_GT(*std::max_element(f.begin(), f.begin() + 9), 0.5f);
  EXPECT_NEAR(f[72], 0.f, 1e-6f);
  EXPECT_NEAR(f[74], 0.25f, 1e-5f);
  EXPECT_NEAR(f[75], 0.75f, 1e-5f);
}

TEST(ObjectProposals, BackProjectionAndMergingAcrossViews) {
  const RenderedView view = BoxScene();
  Eigen::Vector3d centre, size;
  ASSERT_TRUE(BackProject(view, Box2i{120, 75, 150, 105}, 0.25, &centre, &size));
  // Camera at the origin looking along +z (identity pose): the box face at z = 1, 0.2 m wide.
  EXPECT_NEAR(centre.z(), 1.0, 1e-4);
  EXPECT_NEAR(size.x(), 0.18, 0.02);  // 5th-95th percentile of the pixel centres.
  ObjectProposal a;
  a.has_3d = true, a.centre = centre, a.size = Eigen::Vector3d(0.2, 0.2, 0.2), a.score = 0.8;
  ObjectProposal b = a;
  b.centre.x() += 0.02, b.score = 0.6;
  ObjectProposal far = a;
  far.centre.x() += 1.0;
  ProposalMerger merger(0.25);
  merger.Add({a});
  merger.Add({b, far});
  ASSERT_EQ(merger.merged().size(), 2u);
  EXPECT_EQ(merger.merged()[0].views, 2);
  EXPECT_NEAR(merger.merged()[0].score, 0.8, 1e-12);
  EXPECT_NEAR(merger.merged()[0].centre.x(), centre.x() + 0.02 * 0.6 / 1.4, 1e-9);
  testing::ScratchDir dir("proposals");
  ASSERT_TRUE(merger.WriteJson(dir.File("object_proposals.json"), nullptr, 0.05).ok());
  const nlohmann::json j = nlohmann::json::parse(testing::ReadText(dir.File("object_proposals.json")));
  EXPECT_EQ(j["count"], 2);
  EXPECT_TRUE(j["proposals"][0]["supporting_surface"].is_null());
  EXPECT_EQ(j["proposals"][0]["size"].size(), 3u);
}

}  // namespace
}  // namespace semvox
