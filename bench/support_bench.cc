// Support / clutter / other: permutohedral against brute-force mean-field, and per-view cost.
//
//   support_bench [--model models/support_clutter.svm] [--seed 100] [--repeats 3] [--refinement 1] [--refinement-5d 1]
//                 [--small-refinement 1] [--small-refinement-5d 1] [--exact-smoothness 1] [--height-grid 0.25]
//                 [--height-grid-position 0.5] [--small-only 0|1|2 (2: the check image only)]
//   support_bench --kernel-shape D [--refinement-5d R]   (the lattice's kernel between two points in D dimensions)
//   support_bench --train OUT.svm [--train-seeds 0-39] [--val-seeds 100-109]   (same as `semvox train`'s step)
//   support_bench --validate MODEL.svm [--val-seeds 100-109] [--grid-factor F] [--iterations N]
//                 (the model's validation scores, svm and svm_crf, as `semvox train` reports them)
//
// 0. The check image of objects/dense_crf_check.h (40 x 30, the settings of
//    DenseCrf.PermutohedralMeanFieldMatchesBruteForce, i.e. the pipeline's filters, unless overridden by
//    --small-refinement[-5d], --exact-smoothness, --height-grid[-position]): max and mean |dQ|, times.
// 1. Small image (64 x 48, a generated validation view): mean-field marginals with the lattice and with
//    exact O(n^2) kernel sums; max and mean |dQ|, argmax disagreements, both times (same refinements as 0);
//    then each kernel's first normalised message alone, fast against exact, and brute force against itself
//    with the unary perturbed by 1e-4 (the mean-field's conditioning).
// 2. 640 x 480: the lattice's mean-field time; brute force's time extrapolated from the exact messages of
//    `--sample` pixels (n^2 is ~10^11 kernel evaluations per kernel and iteration at this size), and the
//    fast first message against those exact ones.
// 3. Per-view cost of the whole classifier at 640 x 480 (superpixels, features, SVM, CRF), when a model is given.
// A/B runs are interleaved within one process; the machine is shared, so read ratios, not absolute times.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <utility>

#include "objects/dense_crf_check.h"
#include "objects/proposal_training.h"
#include "objects/support_training.h"

using namespace semvox;

namespace {

double Ms(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<uint64_t> Seeds(const std::string& text) {
  std::vector<uint64_t> out;
  const size_t dash = text.find('-');
  if (dash == std::string::npos) return {std::stoull(text)};
  for (uint64_t s = std::stoull(text.substr(0, dash)); s <= std::stoull(text.substr(dash + 1)); ++s) out.push_back(s);
  return out;
}

// The first view of apartment `seed` with support pixels, at width x height.
bool FirstView(uint64_t seed, int width, int height, RenderedView* view, Image<int32_t>* truth) {
  TrainingViewsOptions views;
  views.width = width, views.height = height;
  bool found = false;
  Status st = ForEachSupportView(seed, views, SupportTruthOptions{}, [&](const SupportView& v) {
    if (found) return Status::Ok();
    int support = 0;
    for (int32_t c : v.truth->data) support += c == kSupportSurface;
    if (support < int(v.truth->data.size() / 50)) return Status::Ok();
    *view = *v.view;
    *truth = *v.truth;
    found = true;
    return Status::Ok();
  });
  return st.ok() && found;
}

// Unary: the SVM's when a model is given, else the truth blurred with noise (60% on the true class).
std::vector<float> Unary(const RenderedView& view, const Image<int32_t>& truth, const SupportClutterClassifier* clf) {
  const size_t n = truth.data.size();
  std::vector<float> p(n * kNumSupportClasses);
  if (clf) {
    Result<SupportClutterView> out = clf->Classify(view);
    if (out.ok()) {
      for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < kNumSupportClasses; ++c)
          p[i * kNumSupportClasses + size_t(c)] = float(out->superpixel_probabilities[size_t(out->superpixels.label.data[i]) * kNumSupportClasses + size_t(c)]);
      return p;
    }
  }
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.f, 0.4f);
  for (size_t i = 0; i < n; ++i) {
    float s = 0;
    for (int c = 0; c < kNumSupportClasses; ++c) s += (p[i * 3 + size_t(c)] = (truth.data[i] == c ? 0.6f : 0.f) + u(rng));
    for (int c = 0; c < kNumSupportClasses; ++c) p[i * 3 + size_t(c)] /= s;
  }
  return p;
}

// Max and mean of |a_i - b_i| over two equally long vectors.
std::pair<double, double> AbsDiff(const std::vector<float>& a, const std::vector<float>& b) {
  double max_d = 0, mean_d = 0;
  for (size_t i = 0; i < a.size(); ++i) max_d = std::max(max_d, double(std::abs(a[i] - b[i]))), mean_d += std::abs(a[i] - b[i]) / double(a.size());
  return {max_d, mean_d};
}

// The lattice's kernel between two points at feature distance D (random direction, random placement;
// 3000 draws per D): mean and standard deviation of the filtered weight against exp(-D^2 / 2).
void KernelShape(int d, int refinement) {
  std::mt19937 rng(1);
  std::normal_distribution<float> gauss;
  std::uniform_real_distribution<float> place(0.f, 50.f);
  for (double D : {0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5}) {
    double s = 0, s2 = 0;
    const int draws = 3000;
    for (int t = 0; t < draws; ++t) {
      std::vector<float> f(static_cast<size_t>(2 * d)), e(static_cast<size_t>(d));
      double norm = 0;
      for (float& c : e) c = gauss(rng), norm += double(c) * c;
      for (int c = 0; c < d; ++c) f[size_t(c)] = place(rng), f[size_t(d + c)] = f[size_t(c)] + float(D * e[size_t(c)] / std::sqrt(norm));
      PermutohedralLattice lattice;
      lattice.Build(f.data(), 2, d, refinement);
      const std::vector<float> in = {0.f, 1.f};
      std::vector<float> out;
      lattice.Filter(in.data(), 1, &out);
      s += out[0], s2 += double(out[0]) * out[0];
    }
    const double mean = s / draws, exact = std::exp(-0.5 * D * D);
    std::printf("lattice kernel d %d, refinement %d, two points at distance %.1f: exact %.4f, lattice mean %.4f (x%.3f), sd %.4f\n", d, refinement, D,
                exact, mean, mean / exact, std::sqrt(std::max(0.0, s2 / draws - mean * mean)));
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string model, proposals_out, nyu4_prefix = std::string(SEMVOX_SOURCE_DIR) + "/models/nyu4", train_out, train_seeds = "0-39", val_seeds = "100-109";
  uint64_t seed = 100;
  int repeats = 3, sample = 400, region_px = 0;
  double crf_weight_scale = 1.0, svm_c = 0, svm_gamma = 0;
  int other_rows = 0, balance = -1, small_scaled = 0, small_only = 0, kernel_shape = 0;
  std::string validate_model;
  int grid_factor = SupportClutterOptions{}.crf_grid_factor, iterations = DenseCrfOptions{}.iterations;
  // Lattice refinements (DenseCrfOptions::lattice_refinement, lattice_refinement_5d) for the small-image
  // comparisons and for the 640 x 480 runs, and the smoothness / height filters (all runs); default: the
  // pipeline's, DenseCrfOptions{}, which the test uses too.
  int refine_small = DenseCrfOptions{}.lattice_refinement, refine_small_5d = DenseCrfOptions{}.lattice_refinement_5d;
  int refine = DenseCrfOptions{}.lattice_refinement, refine_5d = DenseCrfOptions{}.lattice_refinement_5d;
  double height_grid = DenseCrfOptions{}.height_grid_spacing, height_grid_pos = DenseCrfOptions{}.height_grid_position_spacing;
  int exact_smoothness = DenseCrfOptions{}.exact_smoothness;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--model") model = argv[i + 1];
    else if (a == "--seed") seed = std::stoull(argv[i + 1]);
    else if (a == "--repeats") repeats = std::atoi(argv[i + 1]);
    else if (a == "--sample") sample = std::atoi(argv[i + 1]);
    else if (a == "--train") train_out = argv[i + 1];
    else if (a == "--validate") validate_model = argv[i + 1];
    else if (a == "--grid-factor") grid_factor = std::atoi(argv[i + 1]);
    else if (a == "--iterations") iterations = std::atoi(argv[i + 1]);
    else if (a == "--train-proposals") proposals_out = argv[i + 1];
    else if (a == "--nyu4") nyu4_prefix = argv[i + 1];
    else if (a == "--region-px") region_px = std::atoi(argv[i + 1]);
    else if (a == "--crf-weight-scale") crf_weight_scale = std::atof(argv[i + 1]);
    else if (a == "--svm-c") svm_c = std::atof(argv[i + 1]);
    else if (a == "--other-rows") other_rows = std::atoi(argv[i + 1]);
    else if (a == "--balance") balance = std::atoi(argv[i + 1]);
    else if (a == "--small-scaled") small_scaled = std::atoi(argv[i + 1]);
    else if (a == "--small-only") small_only = std::atoi(argv[i + 1]);
    else if (a == "--kernel-shape") kernel_shape = std::atoi(argv[i + 1]);
    else if (a == "--refinement") refine = std::atoi(argv[i + 1]);
    else if (a == "--refinement-5d") refine_5d = std::atoi(argv[i + 1]);
    else if (a == "--small-refinement") refine_small = std::atoi(argv[i + 1]);
    else if (a == "--small-refinement-5d") refine_small_5d = std::atoi(argv[i + 1]);
    else if (a == "--height-grid") height_grid = std::atof(argv[i + 1]);
    else if (a == "--height-grid-position") height_grid_pos = std::atof(argv[i + 1]);
    else if (a == "--exact-smoothness") exact_smoothness = std::atoi(argv[i + 1]);
    else if (a == "--svm-gamma") svm_gamma = std::atof(argv[i + 1]);
    else if (a == "--train-seeds") train_seeds = argv[i + 1];
    else if (a == "--val-seeds") val_seeds = argv[i + 1];
    else { std::fprintf(stderr, "support_bench: unknown option %s\n", a.c_str()); return 2; }
  }
  if (kernel_shape > 0) {
    if (kernel_shape > 16 || refine_5d < 1 || refine_5d > PermutohedralLattice::kMaxRefinement) {
      std::fprintf(stderr, "support_bench: --kernel-shape takes 1..16 dimensions and --refinement-5d 1..%d\n", PermutohedralLattice::kMaxRefinement);
      return 2;
    }
    KernelShape(kernel_shape, refine_5d);
    return 0;
  }
  if (!proposals_out.empty()) {
    Result<ViewClassifier> nyu4 = ViewClassifier::Load(nyu4_prefix, ViewClassifierOptions{});
    if (!nyu4.ok()) { std::fprintf(stderr, "support_bench: %s\n", nyu4.status().message().c_str()); return 2; }
    ProposalTrainingOptions options;
    options.train_seeds = Seeds(train_seeds);
    options.val_seeds = Seeds(val_seeds);
    ProposalTrainingSummary summary;
    Result<ObjectProposer> det = TrainObjectProposer(options, *nyu4, &summary);
    if (!det.ok()) { std::fprintf(stderr, "support_bench: %s\n", det.status().message().c_str()); return 1; }
    Status st = det->Save(proposals_out);
    if (!st.ok()) { std::fprintf(stderr, "support_bench: %s\n", st.message().c_str()); return 1; }
    std::printf("%s\n", summary.ToJson().dump(2).c_str());
    return 0;
  }
  if (!validate_model.empty()) {
    SupportTrainingOptions options;
    options.val_seeds = Seeds(val_seeds);
    options.classifier.crf_grid_factor = grid_factor;
    options.classifier.crf.iterations = iterations;
    Result<SupportClutterClassifier> clf = SupportClutterClassifier::Load(validate_model, options.classifier);
    if (!clf.ok()) { std::fprintf(stderr, "support_bench: %s\n", clf.status().message().c_str()); return 2; }
    SupportTrainingSummary summary;
    const auto t0 = std::chrono::steady_clock::now();
    Status st = ValidateSupportClutter(*clf, options, &summary);
    if (!st.ok()) { std::fprintf(stderr, "support_bench: %s\n", st.message().c_str()); return 1; }
    summary.seconds = Ms(t0) / 1000;
    std::printf("grid factor %d, %d iterations\n%s\n", grid_factor, iterations, summary.ToJson().dump(2).c_str());
    return 0;
  }
  if (!train_out.empty()) {
    SupportTrainingOptions options;
    options.train_seeds = Seeds(train_seeds);
    options.val_seeds = Seeds(val_seeds);
    // Tuning knobs (defaults: the library's).
    if (region_px > 0) options.classifier.superpixels.region_size_px = region_px;
    DenseCrfOptions& crf = options.classifier.crf;
    crf.appearance_weight *= crf_weight_scale, crf.smoothness_weight *= crf_weight_scale;
    crf.height_weight *= crf_weight_scale, crf.normal_weight *= crf_weight_scale;
    if (svm_c > 0) options.svm.c = svm_c;
    if (svm_gamma > 0) options.svm.gamma = svm_gamma;
    if (other_rows > 0) options.max_other_rows = other_rows;
    if (balance >= 0) options.svm.balance_classes = balance != 0;
    SupportTrainingSummary summary;
    Result<SupportClutterClassifier> clf = TrainSupportClutter(options, &summary);
    if (!clf.ok()) { std::fprintf(stderr, "support_bench: %s\n", clf.status().message().c_str()); return 1; }
    Status st = clf->Save(train_out);
    if (!st.ok()) { std::fprintf(stderr, "support_bench: %s\n", st.message().c_str()); return 1; }
    std::printf("%s\n", summary.ToJson().dump(2).c_str());
    return 0;
  }
  std::unique_ptr<SupportClutterClassifier> clf;
  if (!model.empty()) {
    SupportClutterOptions options;
    options.crf.lattice_refinement = refine, options.crf.lattice_refinement_5d = refine_5d;
    options.crf.height_grid_spacing = height_grid, options.crf.height_grid_position_spacing = height_grid_pos, options.crf.exact_smoothness = exact_smoothness != 0;
    Result<SupportClutterClassifier> loaded = SupportClutterClassifier::Load(model, options);
    if (!loaded.ok()) { std::fprintf(stderr, "support_bench: %s\n", loaded.status().message().c_str()); return 2; }
    clf = std::make_unique<SupportClutterClassifier>(std::move(loaded).value());
  }
  // 0. The test's synthetic 40 x 30 image, the test's settings.
  {
    const SyntheticCrfImage im = MakeSyntheticCrfImage();
    DenseCrfOptions o = SyntheticCrfOptions();
    o.lattice_refinement = refine_small, o.lattice_refinement_5d = refine_small_5d;
    o.height_grid_spacing = height_grid, o.height_grid_position_spacing = height_grid_pos, o.exact_smoothness = exact_smoothness != 0;
    auto t0 = std::chrono::steady_clock::now();
    Result<DenseCrf> crf = DenseCrf::Create({&im.rgb, &im.height, &im.normal}, o);
    if (!crf.ok()) { std::fprintf(stderr, "support_bench: %s\n", crf.status().message().c_str()); return 1; }
    const double t_build = Ms(t0);
    t0 = std::chrono::steady_clock::now();
    const std::vector<float> fast = crf->MeanField(im.p, 3, false);
    const double t_fast = Ms(t0);
    t0 = std::chrono::steady_clock::now();
    const std::vector<float> brute = crf->MeanField(im.p, 3, true);
    const double t_brute = Ms(t0);
    const auto [max_d, mean_d] = AbsDiff(fast, brute);
    std::printf("test image 40x30 (synthetic table top, theta_beta 8 px, weights 1, refinement %d / 5-D %d): |dQ| max %.2e mean %.2e; "
                "lattice build %.0f ms + mean-field %.1f ms, brute force %.0f ms\n",
                o.lattice_refinement, o.lattice_refinement_5d, max_d, mean_d, t_build, t_fast, t_brute);
    if (small_only == 2) return 0;
  }
  // 1. Small image: lattice against exact sums.
  {
    RenderedView view;
    Image<int32_t> truth;
    if (!FirstView(seed, 64, 48, &view, &truth)) { std::fprintf(stderr, "support_bench: no view with support in seed %llu\n", (unsigned long long)seed); return 1; }
    // The CRF as configured (theta_beta 40 px, theta_p 3 px), on a 64 x 48 view. Scaling the pixel scales
    // down with the image (4 px, 1 px) puts neighbouring pixels one standard deviation apart, where the
    // lattice's interpolation is coarse: `--small-scaled 1` measures that case.
    DenseCrfOptions o;
    o.lattice_refinement = refine_small, o.lattice_refinement_5d = refine_small_5d;
    o.height_grid_spacing = height_grid, o.height_grid_position_spacing = height_grid_pos, o.exact_smoothness = exact_smoothness != 0;
    if (small_scaled) o.position_scale_px = o.position_scale_px * 64 / 640, o.smoothness_scale_px = 1.0;
    const ImageF32 height = PixelHeights(view);
    Result<DenseCrf> crf = DenseCrf::Create({&view.rgb, &height, &view.normal}, o);
    if (!crf.ok()) { std::fprintf(stderr, "support_bench: %s\n", crf.status().message().c_str()); return 1; }
    const std::vector<float> p = Unary(view, truth, clf.get());
    double t_fast = 0, t_brute = 0;
    std::vector<float> fast, brute;
    for (int r = 0; r < repeats; ++r) {
      auto t0 = std::chrono::steady_clock::now();
      fast = crf->MeanField(p, kNumSupportClasses, false);
      t_fast += Ms(t0) / repeats;
      t0 = std::chrono::steady_clock::now();
      brute = crf->MeanField(p, kNumSupportClasses, true);
      t_brute += Ms(t0) / repeats;
    }
    double max_d = 0, mean_d = 0;
    int disagree = 0, undecided = 0;  // Pixels whose exact marginal stays below 0.99 (where a mismatch can show).
    const size_t n = truth.data.size();
    for (size_t i = 0; i < n; ++i) {
      int a = 0, b = 0;
      for (int c = 0; c < kNumSupportClasses; ++c) {
        const double d = std::abs(fast[i * 3 + size_t(c)] - brute[i * 3 + size_t(c)]);
        max_d = std::max(max_d, d);
        mean_d += d / double(3 * n);
        if (fast[i * 3 + size_t(c)] > fast[i * 3 + size_t(a)]) a = c;
        if (brute[i * 3 + size_t(c)] > brute[i * 3 + size_t(b)]) b = c;
      }
      disagree += a != b;
      undecided += brute[i * 3 + size_t(b)] < 0.99f;
    }
    std::printf("small image 64x48 (%zu px, %d iterations, unary %s, refinement %d / 5-D %d): theta_beta %.0f px, theta_p %.0f px; %d pixels below 0.99): "
                "|dQ| max %.2e mean %.2e, argmax disagreements %d; lattice %.2f ms, brute force %.1f ms (x%.0f)\n",
                n, o.iterations, clf ? "SVM" : "noisy truth", o.lattice_refinement, o.lattice_refinement_5d, o.position_scale_px, o.smoothness_scale_px, undecided, max_d, mean_d, disagree,
                t_fast, t_brute, t_brute / t_fast);
    // The filters alone: one normalised message per kernel (its weight set to 1, the others 0) from the
    // unary, fast against exact. And the conditioning of the mean-field itself: brute force again with
    // every unary probability scaled by 1 + 1e-4 u, u uniform in [-1, 1] (seed 3), then renormalised.
    const char* names[] = {"appearance", "smoothness", "height", "normal"};
    for (int kernel = 0; kernel < 4; ++kernel) {
      DenseCrfOptions ok = o;
      double* w[] = {&ok.appearance_weight, &ok.smoothness_weight, &ok.height_weight, &ok.normal_weight};
      for (int k = 0; k < 4; ++k) *w[k] = k == kernel ? 1.0 : 0.0;
      Result<DenseCrf> one = DenseCrf::Create({&view.rgb, &height, &view.normal}, ok);
      if (!one.ok()) { std::fprintf(stderr, "support_bench: %s\n", one.status().message().c_str()); return 1; }
      std::vector<float> mf, mb;
      one->Messages(p, kNumSupportClasses, false, &mf);
      one->Messages(p, kNumSupportClasses, true, &mb);
      const auto [mx, mn] = AbsDiff(mf, mb);
      std::printf("  one normalised %s message from the unary: |dm| max %.2e mean %.2e\n", names[kernel], mx, mn);
    }
    {
      std::mt19937 rng(3);
      std::uniform_real_distribution<float> u(-1.f, 1.f);
      std::vector<float> pp = p;
      for (size_t i = 0; i < n; ++i) {
        float s = 0;
        for (int c = 0; c < kNumSupportClasses; ++c) s += (pp[i * 3 + size_t(c)] *= 1.f + 1e-4f * u(rng));
        for (int c = 0; c < kNumSupportClasses; ++c) pp[i * 3 + size_t(c)] /= s;
      }
      const std::vector<float> brute2 = crf->MeanField(pp, kNumSupportClasses, true);
      const auto [mx, mn] = AbsDiff(brute2, brute);
      std::printf("  brute force with the unary perturbed by 1e-4 (relative): |dQ| max %.2e mean %.2e\n", mx, mn);
    }
  }
  if (small_only) return 0;
  // 2. 640 x 480.
  RenderedView view;
  Image<int32_t> truth;
  if (!FirstView(seed, 640, 480, &view, &truth)) { std::fprintf(stderr, "support_bench: no 640x480 view\n"); return 1; }
  {
    DenseCrfOptions o;
    o.lattice_refinement = refine, o.lattice_refinement_5d = refine_5d;
    o.height_grid_spacing = height_grid, o.height_grid_position_spacing = height_grid_pos, o.exact_smoothness = exact_smoothness != 0;
    const ImageF32 height = PixelHeights(view);
    auto t0 = std::chrono::steady_clock::now();
    Result<DenseCrf> crf = DenseCrf::Create({&view.rgb, &height, &view.normal}, o);
    if (!crf.ok()) { std::fprintf(stderr, "support_bench: %s\n", crf.status().message().c_str()); return 1; }
    const double t_build = Ms(t0);
    const std::vector<float> p = Unary(view, truth, clf.get());
    double t_fast = 0;
    for (int r = 0; r < repeats; ++r) {
      t0 = std::chrono::steady_clock::now();
      std::vector<float> q = crf->MeanField(p, kNumSupportClasses, false);
      t_fast += Ms(t0) / repeats;
    }
    // Brute force: exact messages of `sample` evenly spread pixels, scaled to all pixels and iterations.
    const int n = crf->num_pixels();
    t0 = std::chrono::steady_clock::now();
    std::vector<float> exact(size_t(sample) * kNumSupportClasses);
    for (int k = 0; k < sample; ++k) crf->BruteForceMessage(int(int64_t(k) * n / sample), p, kNumSupportClasses, &exact[size_t(k) * kNumSupportClasses]);
    const double t_brute = Ms(t0) / sample * n * o.iterations;
    // The filters' accuracy at full size: the fast messages from the unary at the sampled pixels against
    // their exact messages (sum over the four kernels of w_m times the normalised message).
    std::vector<float> fast;
    crf->Messages(p, kNumSupportClasses, false, &fast);
    double max_dm = 0, mean_dm = 0;
    for (int k = 0; k < sample; ++k)
      for (int c = 0; c < kNumSupportClasses; ++c) {
        const double dm = std::abs(fast[size_t(int64_t(k) * n / sample) * kNumSupportClasses + size_t(c)] - exact[size_t(k) * kNumSupportClasses + size_t(c)]);
        max_dm = std::max(max_dm, dm), mean_dm += dm / double(sample * kNumSupportClasses);
      }
    std::printf("640x480: first message (all kernels, weighted) at the %d sampled pixels, fast against exact: |dm| max %.2e mean %.2e\n", sample, max_dm, mean_dm);
    std::printf("640x480 (%d px, %d iterations, refinement %d / 5-D %d): lattice build %.0f ms + mean-field %.0f ms; brute force (one core, "
                "extrapolated from %d pixels) %.0f s: speed-up x%.0f\n",
                n, o.iterations, o.lattice_refinement, o.lattice_refinement_5d, t_build, t_fast, sample, t_brute / 1000, t_brute / (t_build + t_fast));
  }
  if (clf) {
    double s = 0, f = 0, v = 0, c = 0;
    for (int r = 0; r < repeats; ++r) {
      Result<SupportClutterView> out = clf->Classify(view);
      if (!out.ok()) return 1;
      s += out->ms_superpixels / repeats, f += out->ms_features / repeats, v += out->ms_svm / repeats, c += out->ms_crf / repeats;
    }
    std::printf("per view 640x480: superpixels %.0f ms, features %.0f ms, SVM %.0f ms, CRF %.0f ms, total %.0f ms\n", s, f, v, c, s + f + v + c);
  }
  return 0;
}
