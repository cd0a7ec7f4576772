// Per-view classifier cost: milliseconds per view for SLIC superpixels, the 15-D observations,
// the two k-NN unaries, the tree CRF (exact sum-product + max-product) and the union CRF (loopy BP), on
// one core (OpenCV limited to one thread). Not a test: prints a table.
//
//   perception_bench [--width 640] [--height 480] [--train-seeds 2] [--val-seed 100] [--slic-iterations 10]
//
// The classifier is trained first (not timed) on generated apartments at the same resolution.
#include <opencv2/core.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>

#include "perception/training_data.h"
#include "perception/view_classifier.h"

using namespace semvox;

namespace {

double CpuMs() { return 1000.0 * double(std::clock()) / CLOCKS_PER_SEC; }

}  // namespace

int main(int argc, char** argv) {
  int width = 640, height = 480, train_seeds = 2, slic_iterations = SuperpixelOptions{}.iterations;
  uint64_t val_seed = 100;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--width")) width = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--height")) height = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--train-seeds")) train_seeds = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--val-seed")) val_seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (!std::strcmp(argv[i], "--slic-iterations")) slic_iterations = std::atoi(argv[i + 1]);
    else {
      std::fprintf(stderr, "perception_bench: unknown option %s\n", argv[i]);
      return 2;
    }
  }
  cv::setNumThreads(1);
  const LabelLevel level = Nyu4Level();
  ViewClassifierOptions options;
  options.superpixels.iterations = slic_iterations;
  TrainingViewsOptions views;
  views.width = width;
  views.height = height;
  TrainingSet set;
  for (int seed = 0; seed < train_seeds; ++seed) {
    const Status st = ForEachApartmentView(uint64_t(seed), views, [&](const LabelledView& v) {
      return AddTrainingView(*v.view, level.Map(*v.nyu40), options, &set);
    });
    if (!st.ok()) {
      std::fprintf(stderr, "perception_bench: %s\n", st.message().c_str());
      return 1;
    }
  }
  Result<ViewClassifier> clf = ViewClassifier::Train(set, level.num_classes(), options);
  if (!clf.ok()) {
    std::fprintf(stderr, "perception_bench: %s\n", clf.status().message().c_str());
    return 1;
  }
  double ms[5] = {0, 0, 0, 0, 0};  // superpixels, observations, knn, tree, union (CPU ms).
  int n_views = 0;
  long superpixels = 0;
  ConfusionMatrix cm(level.num_classes());
  const Status st = ForEachApartmentView(val_seed, views, [&](const LabelledView& v) {
    double t = CpuMs();
    Result<Superpixels> sp = ComputeSuperpixels(v.view->rgb, options.superpixels);
    if (!sp.ok()) return sp.status();
    ms[0] += CpuMs() - t;
    t = CpuMs();
    Result<ViewObservations> obs = ComputeObservations(*v.view, *sp, options.observations);
    if (!obs.ok()) return obs.status();
    ms[1] += CpuMs() - t;
    superpixels += sp->count;
    // Classify() runs k-NN, tree and union together; time them through the public pieces it uses.
    t = CpuMs();
    Result<ViewClassification> c = clf->Classify(*sp, *obs);
    if (!c.ok()) return c.status();
    const double classify = CpuMs() - t;
    // Split the classify time: rerun the tree and union parts alone on the k-NN output.
    t = CpuMs();
    Result<PairwiseModel> tree = BuildViewCrf(c->observations, BuildTreeGraph(c->observations), c->knn, {}, false, options.crf);
    Marginals marg;
    std::vector<int> map;
    if (tree.ok()) {
      (void)TreeSumProduct(*tree, &marg);
      (void)TreeMaxProduct(*tree, &map);
    }
    const double tree_ms = CpuMs() - t;
    t = CpuMs();
    Result<PairwiseModel> uni = BuildViewCrf(c->observations, BuildUnionCoverageGraph(c->observations), c->knn, {}, true, options.crf);
    if (uni.ok()) (void)LoopyBeliefPropagation(*uni, options.loopy, &marg);
    const double union_ms = CpuMs() - t;
    ms[3] += tree_ms;
    ms[4] += union_ms;
    ms[2] += std::max(0.0, classify - tree_ms - union_ms);
    cm.AddImages(level.Map(*v.nyu40), PixelLabels(c->superpixels, c->tree_labels));
    ++n_views;
    return Status::Ok();
  });
  if (!st.ok() || n_views == 0) {
    std::fprintf(stderr, "perception_bench: %s\n", st.ok() ? "no validation view" : st.message().c_str());
    return 1;
  }
  std::printf("SLIC iterations %d\n", slic_iterations);
  std::printf("%dx%d, %d views of seed %llu, %.0f superpixels/view, %zu training rows (image+3D), one core\n", width,
              height, n_views, (unsigned long long)val_seed, double(superpixels) / n_views, set.full_labels.size());
  const char* names[5] = {"superpixels (SLIC)", "observations (15-D)", "k-NN unaries (f1, f2)", "tree CRF (sum+max)", "union CRF (loopy)"};
  double total_tree = 0;
  for (int k = 0; k < 5; ++k) {
    std::printf("  %-24s %8.1f ms/view\n", names[k], ms[k] / n_views);
    if (k < 4) total_tree += ms[k] / n_views;
  }
  std::printf("  %-24s %8.1f ms/view (target <= 150)\n", "superpixels..tree BP", total_tree);
  std::printf("  tree CRF NYU-4 global accuracy on these views: %.3f\n", cm.GlobalAccuracy());
  return 0;
}
