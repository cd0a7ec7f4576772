#include "objects/svm_classifier.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "tests/test_util.h"

namespace semvox {
namespace {

// Three Gaussian blobs in 4-D (class c centred at 2c on every axis), unequal class sizes.
void Blobs(int n, uint64_t seed, std::vector<float>* rows, std::vector<int>* labels, bool nonnegative) {
  std::mt19937 rng(static_cast<uint32_t>(seed));
  std::normal_distribution<float> g(0.f, 0.7f);
  for (int i = 0; i < n; ++i) {
    const int c = i % 7 < 4 ? 0 : (i % 7 < 6 ? 1 : 2);
    for (int k = 0; k < 4; ++k) {
      float v = 2.f * c + g(rng);
      if (nonnegative) v = std::abs(v) + 0.1f;
      rows->push_back(v);
    }
    labels->push_back(c);
  }
}

class SvmKernels : public ::testing::TestWithParam<SvmKernel> {};

TEST_P(SvmKernels, ProbabilitiesSumToOneAndClassifyHeldOutRows) {
  std::vector<float> rows, test_rows;
  std::vector<int> labels, test_labels;
  Blobs(350, 1, &rows, &labels, GetParam() == SvmKernel::kHistogramIntersection);
  Blobs(140, 2, &test_rows, &test_labels, GetParam() == SvmKernel::kHistogramIntersection);
  SvmOptions options;
  options.kernel = GetParam();
  Result<SvmClassifier> svm = SvmClassifier::Train(rows, 4, labels, 3, options);
  ASSERT_TRUE(svm.ok()) << svm.status().message();
  int correct = 0;
  for (size_t i = 0; i < test_labels.size(); ++i) {
    double p[3];
    svm->PredictProbabilities(&test_rows[i * 4], p);
    EXPECT_NEAR(p[0] + p[1] + p[2], 1.0, 1e-9);
    for (double v : p) EXPECT_TRUE(v >= 0 && v <= 1);
    correct += int(std::max_element(p, p + 3) - p) == test_labels[i];
  }
  // The blobs are 2 apart with sigma 0.7 per axis (4 axes): the Bayes error is under 1%.
  EXPECT_GE(correct, int(0.9 * test_labels.size()));
}

TEST_P(SvmKernels, SaveLoadRoundTripGivesTheSameProbabilities) {
  std::vector<float> rows;
  std::vector<int> labels;
  Blobs(200, 3, &rows, &labels, GetParam() == SvmKernel::kHistogramIntersection);
  SvmOptions options;
  options.kernel = GetParam();
  Result<SvmClassifier> svm = SvmClassifier::Train(rows, 4, labels, 3, options);
  ASSERT_TRUE(svm.ok());
  testing::ScratchDir dir("svm");
  ASSERT_TRUE(svm->Save(dir.File("m.svm")).ok());
  Result<SvmClassifier> loaded = SvmClassifier::Load(dir.File("m.svm"));
  ASSERT_TRUE(loaded.ok()) << loaded.status().message();
  for (size_t i = 0; i < 20; ++i) {
    double a[3], b[3];
    svm->PredictProbabilities(&rows[i * 4], a);
    loaded->PredictProbabilities(&rows[i * 4], b);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-6);
  }
}

INSTANTIATE_TEST_SUITE_P(Kernels, SvmKernels, ::testing::Values(SvmKernel::kRbf, SvmKernel::kHistogramIntersection));

// The prediction paths against libsvm's own kernel evaluation: the RBF kernel evaluated densely (all support
// vectors at once) and the histogram-intersection queries in a reused buffer, on models trained here and on
// the shipped support / clutter (RBF, 4,155 support vectors, 8 features) and proposal (histogram
// intersection, 76 features) models: the probabilities agree to 1e-12 on rows spread over the feature space.
TEST(SvmClassifier, FastKernelPathsMatchLibsvm) {
  std::vector<SvmClassifier> models;
  for (SvmKernel kernel : {SvmKernel::kRbf, SvmKernel::kHistogramIntersection}) {
    std::vector<float> rows;
    std::vector<int> labels;
    Blobs(300, 5, &rows, &labels, kernel == SvmKernel::kHistogramIntersection);
    SvmOptions options;
    options.kernel = kernel;
    Result<SvmClassifier> trained = SvmClassifier::Train(rows, 4, labels, 3, options);
    ASSERT_TRUE(trained.ok()) << trained.status().message();
    models.push_back(std::move(trained).value());
  }
  for (const char* name : {"support_clutter.svm", "object_proposals.svm"}) {
    Result<SvmClassifier> shipped = SvmClassifier::Load(std::string(SEMVOX_SOURCE_DIR) + "/models/" + name);
    ASSERT_TRUE(shipped.ok()) << shipped.status().message();
    models.push_back(std::move(shipped).value());
  }
  std::mt19937 rng(11);
  for (const SvmClassifier& svm : models) {
    double max_diff = 0, moved = 0;
    std::vector<float> row(size_t(svm.dims()));
    std::vector<double> a(size_t(svm.num_classes())), b(a.size());
    for (int i = 0; i < 500; ++i) {
      std::uniform_real_distribution<float> u(-1.f, 4.f), w(0.f, 4.f / float(svm.dims()));
      for (float& v : row) v = svm.dims() > 8 ? w(rng) : u(rng);
      svm.PredictProbabilities(row.data(), a.data());
      svm.PredictProbabilitiesWithLibsvmKernel(row.data(), b.data());
      for (size_t c = 0; c < a.size(); ++c)
        max_diff = std::max(max_diff, std::abs(a[c] - b[c])), moved = std::max(moved, std::abs(a[c] - 1.0 / double(a.size())));
    }
    std::printf("%d features, %d support vectors: fast path against libsvm's kernel, max |dp| %.2e, largest distance from uniform %.2f\n",
                svm.dims(), svm.num_support_vectors(), max_diff, moved);
    EXPECT_LE(max_diff, 1e-12);
    EXPECT_GT(moved, 0.2);  // The rows reach confident predictions: the comparison is not between uniform outputs.
  }
}

TEST(SvmClassifier, TrainingIsDeterministic) {
  std::vector<float> rows;
  std::vector<int> labels;
  Blobs(150, 4, &rows, &labels, false);
  Result<SvmClassifier> a = SvmClassifier::Train(rows, 4, labels, 3, SvmOptions{});
  Result<SvmClassifier> b = SvmClassifier::Train(rows, 4, labels, 3, SvmOptions{});
  ASSERT_TRUE(a.ok() && b.ok());
  testing::ScratchDir dir("svm_det");
  ASSERT_TRUE(a->Save(dir.File("a")).ok());
  ASSERT_TRUE(b->Save(dir.File("b")).ok());
  EXPECT_EQ(testing::ReadText(dir.File("a")), testing::ReadText(dir.File("b")));
}

TEST(SvmClassifier, RejectsBadInputWithClearMessages) {
  std::vector<float> rows = {0, 1, 2, 3};
  Result<SvmClassifier> few = SvmClassifier::Train(rows, 1, {0, 0, 1, 1}, 3, SvmOptions{});
  ASSERT_FALSE(few.ok());
  EXPECT_NE(few.status().message().find("class 2 has 0 training rows"), std::string::npos) << few.status().message();
  testing::ScratchDir dir("svm_bad");
  testing::WriteText(dir.File("bad.svm"), "semvox_svm 1\nkernel rbf\n");
  Result<SvmClassifier> bad = SvmClassifier::Load(dir.File("bad.svm"));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("bad.svm"), std::string::npos);
  EXPECT_FALSE(SvmClassifier::Load(dir.File("missing.svm")).ok());
}

}  // namespace
}  // namespace semvox
