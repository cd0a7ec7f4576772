// A multi-class SVM with probability outputs, on libsvm (Chang and Lin 2011): one-against-one C-SVC,
// pairwise coupling of Platt-scaled pairwise probabilities (Wu, Lin and Weng 2004, libsvm's
// svm_predict_probability). Two kernels:
//   kRbf                    exp(-gamma |x - y|^2) on standardised features (the support/clutter paper, Sec. 4.2)
//   kHistogramIntersection  sum_k min(x_k, y_k) (the MST-CRF paper, Sec. 4.1), as a precomputed kernel
//
//   Result<SvmClassifier> svm = SvmClassifier::Train(rows, dims, labels, num_classes, SvmOptions{});
//   std::vector<double> p(num_classes);
//   svm->PredictProbabilities(row, p.data());  // sums to 1
//
// libsvm stays inside svm_classifier.cc. Deterministic: libsvm's cross-validation shuffles with rand(),
// seeded from options.seed before training.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/status.h"

namespace semvox {

enum class SvmKernel { kRbf, kHistogramIntersection };

struct SvmOptions {
  SvmKernel kernel = SvmKernel::kRbf;
  double c = 4.0;                // Soft-margin cost C. > 0.
  double gamma = 0.25;           // RBF width on standardised features (per dimension). > 0.
  bool balance_classes = true;   // Weight class c's cost by n / (k n_c): the classes are imbalanced (Sec. 4.2).
  double tolerance = 1e-3;       // libsvm's stopping tolerance eps. > 0.
  double cache_mb = 200;         // libsvm's kernel cache, MB. > 0.
  uint64_t seed = 1;             // Seeds libsvm's probability cross-validation shuffle.

  bool Check(std::string* error) const;
};

class SvmClassifier {
 public:
  // `rows`: n x dims features; `labels` in [0, num_classes). Every class must occur at least twice (libsvm's
  // internal cross-validation for the probabilities needs it).
  static Result<SvmClassifier> Train(const std::vector<float>& rows, int dims, const std::vector<int>& labels,
                                     int num_classes, const SvmOptions& options);
  // p[c] = P(class c | row), c in [0, num_classes); sums to 1.
  void PredictProbabilities(const float* row, double* p) const;
  // The same with libsvm's own kernel evaluation (the RBF kernel one support vector at a time): the
  // reference PredictProbabilities is tested against.
  void PredictProbabilitiesWithLibsvmKernel(const float* row, double* p) const;

  Status Save(const std::string& path) const;  // Atomic.
  static Result<SvmClassifier> Load(const std::string& path);

  int dims() const { return dims_; }
  int num_classes() const { return num_classes_; }
  int num_support_vectors() const;

  SvmClassifier(SvmClassifier&&) noexcept;
  SvmClassifier& operator=(SvmClassifier&&) noexcept;
  ~SvmClassifier();

 private:
  SvmClassifier();
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int dims_ = 0, num_classes_ = 0;
};

}  // namespace semvox
