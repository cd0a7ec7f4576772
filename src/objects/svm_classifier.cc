#include "objects/svm_classifier.h"

#include <immintrin.h>
#include <svm.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <sstream>

#include "core/file_util.h"

namespace semvox {
namespace {

void Quiet(const char*) {}

// libsvm's training and its rand() are global state: one training at a time.
std::mutex& TrainMutex() {
  static std::mutex m;
  return m;
}

double Intersection(const float* a, const float* b, int dims) {
  double s = 0;
  for (int k = 0; k < dims; ++k) s += std::min(a[k], b[k]);
  return s;
}

std::string TempPath() {
  char name[] = "/tmp/semvox_svm_XXXXXX";
  const int fd = mkstemp(name);
  if (fd >= 0) close(fd);
  return name;
}

// exp(x) of four doubles x <= 0, AVX2 + FMA: x = n ln 2 + r with |r| <= ln 2 / 2 (ln 2 in two parts), e^r by
// its Taylor series to degree 12 (truncation below 2e-16 relative), times 2^n from the exponent bits; x below
// -708 gives 0 (e^x < 3e-308). Relative error a few 1e-16 against glibc's exp.
__attribute__((target("avx2,fma"))) inline __m256d ExpNonPositiveAvx2(__m256d x) {
  const __m256d low = _mm256_set1_pd(-708.0);
  const __m256d underflow = _mm256_cmp_pd(x, low, _CMP_LT_OQ);
  x = _mm256_max_pd(x, low);
  const __m256d n = _mm256_round_pd(_mm256_mul_pd(x, _mm256_set1_pd(1.4426950408889634)), _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
  __m256d r = _mm256_fnmadd_pd(n, _mm256_set1_pd(6.93147180369123816490e-01), x);
  r = _mm256_fnmadd_pd(n, _mm256_set1_pd(1.90821492927058770002e-10), r);
  static constexpr double kInvFactorial[13] = {1.0, 1.0, 1.0 / 2, 1.0 / 6, 1.0 / 24, 1.0 / 120, 1.0 / 720, 1.0 / 5040, 1.0 / 40320,
                                                1.0 / 362880, 1.0 / 3628800, 1.0 / 39916800, 1.0 / 479001600};
  __m256d p = _mm256_set1_pd(kInvFactorial[12]);
  for (int k = 11; k >= 0; --k) p = _mm256_fmadd_pd(p, r, _mm256_set1_pd(kInvFactorial[k]));
  const __m256i e = _mm256_slli_epi64(_mm256_add_epi64(_mm256_cvtepi32_epi64(_mm256_cvtpd_epi32(n)), _mm256_set1_epi64x(1023)), 52);
  return _mm256_andnot_pd(underflow, _mm256_mul_pd(p, _mm256_castsi256_pd(e)));
}

// The RBF kernel values exp(-gamma |q - sv_i|^2) of a query against support vectors stored column-wise
// (cols[k * stride + i], stride a multiple of 4, zero padded), four support vectors per step; out[i + 1].value
// receives K(q, sv_i) for i < l.
__attribute__((target("avx2,fma"))) void RbfKernelsAvx2(const double* q, const double* cols, size_t stride, int dims, int l,
                                                        double gamma, svm_node* out) {
  const __m256d neg_gamma = _mm256_set1_pd(-gamma);
  alignas(32) double k4[4];
  for (int i = 0; i < l; i += 4) {
    __m256d sum = _mm256_setzero_pd();
    for (int k = 0; k < dims; ++k) {
      const __m256d d = _mm256_sub_pd(_mm256_set1_pd(q[k]), _mm256_loadu_pd(cols + size_t(k) * stride + size_t(i)));
      sum = _mm256_fmadd_pd(d, d, sum);
    }
    _mm256_store_pd(k4, ExpNonPositiveAvx2(_mm256_mul_pd(neg_gamma, sum)));
    for (int j = 0; j < 4 && i + j < l; ++j) out[i + j + 1].value = k4[j];
  }
}

}  // namespace

bool SvmOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(c > 0)) return fail("c = " + std::to_string(c) + ". Violated constraint: c > 0");
  if (!(gamma > 0)) return fail("gamma = " + std::to_string(gamma) + ". Violated constraint: gamma > 0");
  if (!(tolerance > 0)) return fail("tolerance = " + std::to_string(tolerance) + ". Violated constraint: tolerance > 0");
  if (!(cache_mb > 0)) return fail("cache_mb = " + std::to_string(cache_mb) + ". Violated constraint: cache_mb > 0");
  return true;
}

struct SvmClassifier::Impl {
  SvmKernel kernel = SvmKernel::kRbf;
  std::vector<double> mean, inv_std;  // RBF: standardisation.
  // Histogram intersection: training rows kept for the kernel values at prediction (serial -> row); only the
  // support vectors' rows after Load.
  std::map<int, std::vector<float>> kernel_rows;
  int num_train = 0;
  std::vector<svm_node> nodes;        // Storage the trained model's SV pointers point into.
  std::vector<int> class_of_svm_label_index;  // libsvm label order -> our class.
  svm_model* model = nullptr;
  bool loaded = false;
  // RBF: the support vectors as dense rows, and a shallow copy of `model` whose kernel is PRECOMPUTED and whose
  // SV i is just its serial i + 1, so that libsvm's pairwise Platt scaling and coupling run on kernel values
  // computed here: all of a query's exp(-gamma |x - sv|^2) in one pass over dense rows (libsvm's sparse kernel
  // walks two node lists per support vector). Same sums in the same order and the same exp, so the values are
  // libsvm's own to the last bit (SvmClassifier.FastKernelPathsMatchLibsvm). Models over kMaxDenseDims
  // features keep libsvm's path.
  static constexpr int kMaxDenseDims = 64;  // The query row lives on the stack.
  std::vector<double> sv_rows;
  std::vector<double> sv_cols;  // The same, column-wise (feature k of sv i at k * sv_stride + i), for AVX2.
  size_t sv_stride = 0;
  bool avx2 = false;
  std::vector<svm_node> serial_nodes;
  std::vector<svm_node*> serial_sv;
  svm_model precomputed{};
  bool dense_rbf = false;
  ~Impl() {
    if (model) svm_free_and_destroy_model(&model);
  }
  // Sets up the dense RBF path from `model`; false when a support vector has a feature index outside [1, dims].
  bool PrepareDenseRbf(int dims) {
    dense_rbf = false;
    if (kernel != SvmKernel::kRbf || !model || dims > kMaxDenseDims) return true;  // Wider rows: libsvm's own path.
    const int l = model->l;
    sv_rows.assign(size_t(l) * size_t(dims), 0.0);
    serial_nodes.assign(size_t(l) * 2, svm_node{-1, 0.0});
    serial_sv.resize(size_t(l));
    for (int i = 0; i < l; ++i) {
      for (const svm_node* x = model->SV[i]; x->index != -1; ++x) {
        if (x->index < 1 || x->index > dims) return false;
        sv_rows[size_t(i) * size_t(dims) + size_t(x->index - 1)] = x->value;
      }
      serial_nodes[size_t(i) * 2] = {0, double(i + 1)};
      serial_sv[size_t(i)] = &serial_nodes[size_t(i) * 2];
    }
    sv_stride = (size_t(l) + 3) / 4 * 4;
    sv_cols.assign(sv_stride * size_t(dims), 0.0);
    for (int i = 0; i < l; ++i)
      for (int k = 0; k < dims; ++k) sv_cols[size_t(k) * sv_stride + size_t(i)] = sv_rows[size_t(i) * size_t(dims) + size_t(k)];
    avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    precomputed = *model;
    precomputed.param.kernel_type = PRECOMPUTED;
    precomputed.SV = serial_sv.data();
    dense_rbf = true;
    return true;
  }
  // Kernel values of one standardised query against every support vector, as libsvm's precomputed query:
  // x[i + 1] = (i + 1, K(query, sv_i)). With AVX2 and FMA four support vectors per step and a vector exp (a few
  // 1e-16 from libsvm's values; SvmClassifier.FastKernelPathsMatchLibsvm), else libsvm's sums and exp exactly.
  void DenseRbfQuery(const float* row, int dims, std::vector<svm_node>* x) const {
    const int l = model->l;
    double q[kMaxDenseDims];
    for (int k = 0; k < dims; ++k) q[k] = (double(row[k]) - mean[size_t(k)]) * inv_std[size_t(k)];
    if (x->size() != size_t(l) + 2) {
      x->resize(size_t(l) + 2);
      for (int i = 0; i < l; ++i) (*x)[size_t(i) + 1].index = i + 1;
    }
    (*x)[0] = {0, 0.0};
    (*x)[size_t(l) + 1] = {-1, 0.0};
    if (avx2) {
      RbfKernelsAvx2(q, sv_cols.data(), sv_stride, dims, l, model->param.gamma, x->data());
      return;
    }
    for (int i = 0; i < l; ++i) {
      // libsvm's RBF: the squared differences summed in feature order, then exp(-gamma sum).
      const double* sv = &sv_rows[size_t(i) * size_t(dims)];
      double sum = 0;
      for (int k = 0; k < dims; ++k) {
        const double d = q[k] - sv[k];
        sum += d * d;
      }
      (*x)[size_t(i) + 1] = {i + 1, std::exp(-model->param.gamma * sum)};
    }
  }
  // libsvm nodes for one query row.
  std::vector<svm_node> Query(const float* row, int dims) const {
    std::vector<svm_node> x;
    if (kernel == SvmKernel::kRbf) {
      x.reserve(size_t(dims) + 1);
      for (int k = 0; k < dims; ++k) x.push_back({k + 1, (double(row[k]) - mean[size_t(k)]) * inv_std[size_t(k)]});
    } else {
      x.assign(size_t(num_train) + 2, svm_node{0, 0.0});
      x[0] = {0, 0.0};
      for (int i = 1; i <= num_train; ++i) x[size_t(i)].index = i;
      for (const auto& [serial, r] : kernel_rows) x[size_t(serial)].value = Intersection(row, r.data(), dims);
    }
    x.push_back({-1, 0.0});
    return x;
  }
};

SvmClassifier::SvmClassifier() : impl_(std::make_unique<Impl>()) {}
SvmClassifier::SvmClassifier(SvmClassifier&&) noexcept = default;
SvmClassifier& SvmClassifier::operator=(SvmClassifier&&) noexcept = default;
SvmClassifier::~SvmClassifier() = default;

int SvmClassifier::num_support_vectors() const { return impl_->model ? svm_get_nr_sv(impl_->model) : 0; }

Result<SvmClassifier> SvmClassifier::Train(const std::vector<float>& rows, int dims, const std::vector<int>& labels,
                                           int num_classes, const SvmOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("SVM options: " + error);
  if (dims < 1 || num_classes < 2) return Status::InvalidInput("SVM: need dims >= 1 and num_classes >= 2");
  const size_t n = labels.size();
  if (rows.size() != n * size_t(dims)) return Status::InvalidInput("SVM: rows and labels disagree in count");
  std::vector<int> per_class(size_t(num_classes), 0);
  for (int l : labels) {
    if (l < 0 || l >= num_classes) return Status::InvalidInput("SVM: label " + std::to_string(l) + " outside [0, num_classes)");
    ++per_class[size_t(l)];
  }
  for (int c = 0; c < num_classes; ++c)
    if (per_class[size_t(c)] < 2)
      return Status::InvalidInput("SVM: class " + std::to_string(c) + " has " + std::to_string(per_class[size_t(c)]) +
                                  " training rows (hint: at least 2 per class; add training views)");
  SvmClassifier svm;
  svm.dims_ = dims;
  svm.num_classes_ = num_classes;
  Impl& m = *svm.impl_;
  m.kernel = options.kernel;
  m.num_train = int(n);
  if (m.kernel == SvmKernel::kRbf) {
    m.mean.assign(size_t(dims), 0.0);
    m.inv_std.assign(size_t(dims), 1.0);
    for (size_t i = 0; i < n; ++i)
      for (int k = 0; k < dims; ++k) m.mean[size_t(k)] += rows[i * size_t(dims) + size_t(k)] / double(n);
    std::vector<double> var(size_t(dims), 0.0);
    for (size_t i = 0; i < n; ++i)
      for (int k = 0; k < dims; ++k) {
        const double d = rows[i * size_t(dims) + size_t(k)] - m.mean[size_t(k)];
        var[size_t(k)] += d * d / double(n);
      }
    for (int k = 0; k < dims; ++k) m.inv_std[size_t(k)] = var[size_t(k)] > 1e-12 ? 1.0 / std::sqrt(var[size_t(k)]) : 1.0;
    m.nodes.reserve(n * (size_t(dims) + 1));
    for (size_t i = 0; i < n; ++i) {
      for (int k = 0; k < dims; ++k)
        m.nodes.push_back({k + 1, (double(rows[i * size_t(dims) + size_t(k)]) - m.mean[size_t(k)]) * m.inv_std[size_t(k)]});
      m.nodes.push_back({-1, 0.0});
    }
  } else {
    // Precomputed kernel: row i is (0: serial i+1), (j: K(x_i, x_j)) for j = 1..n.
    m.nodes.reserve(n * (n + 2));
    for (size_t i = 0; i < n; ++i) {
      m.nodes.push_back({0, double(i + 1)});
      for (size_t j = 0; j < n; ++j)
        m.nodes.push_back({int(j + 1), Intersection(&rows[i * size_t(dims)], &rows[j * size_t(dims)], dims)});
      m.nodes.push_back({-1, 0.0});
    }
  }
  std::vector<svm_node*> x(n);
  const size_t stride = m.kernel == SvmKernel::kRbf ? size_t(dims) + 1 : n + 2;
  for (size_t i = 0; i < n; ++i) x[i] = &m.nodes[i * stride];
  std::vector<double> y(labels.begin(), labels.end());
  svm_problem problem{int(n), y.data(), x.data()};
  svm_parameter param{};
  param.svm_type = C_SVC;
  param.kernel_type = m.kernel == SvmKernel::kRbf ? RBF : PRECOMPUTED;
  param.gamma = options.gamma;
  param.cache_size = options.cache_mb;
  param.eps = options.tolerance;
  param.C = options.c;
  param.shrinking = 1;
  param.probability = 1;
  std::vector<int> weight_label(static_cast<size_t>(num_classes));
  std::vector<double> weight(static_cast<size_t>(num_classes));
  if (options.balance_classes) {
    for (int c = 0; c < num_classes; ++c) {
      weight_label[size_t(c)] = c;
      weight[size_t(c)] = double(n) / (double(num_classes) * per_class[size_t(c)]);
    }
    param.nr_weight = num_classes;
    param.weight_label = weight_label.data();
    param.weight = weight.data();
  }
  if (const char* e = svm_check_parameter(&problem, &param)) return Status::InvalidInput(std::string("SVM: libsvm rejects the parameters: ") + e);
  {
    std::lock_guard<std::mutex> lock(TrainMutex());
    svm_set_print_string_function(&Quiet);
    std::srand(unsigned(options.seed));
    m.model = svm_train(&problem, &param);
  }
  if (!m.model) return Status::Internal("SVM: libsvm training failed");
  if (m.kernel == SvmKernel::kHistogramIntersection)
    for (size_t i = 0; i < n; ++i) m.kernel_rows[int(i + 1)] = std::vector<float>(rows.begin() + long(i * size_t(dims)), rows.begin() + long((i + 1) * size_t(dims)));
  m.class_of_svm_label_index.resize(size_t(svm_get_nr_class(m.model)));
  std::vector<int> svm_labels(m.class_of_svm_label_index.size());
  svm_get_labels(m.model, svm_labels.data());
  for (size_t i = 0; i < svm_labels.size(); ++i) m.class_of_svm_label_index[i] = svm_labels[i];
  if (!m.PrepareDenseRbf(dims)) return Status::Internal("SVM: libsvm returned a support vector outside the feature range");
  return svm;
}

void SvmClassifier::PredictProbabilities(const float* row, double* p) const {
  std::vector<double> q(impl_->class_of_svm_label_index.size());
  if (impl_->dense_rbf) {
    thread_local std::vector<svm_node> x;
    impl_->DenseRbfQuery(row, dims_, &x);
    svm_predict_probability(&impl_->precomputed, x.data(), q.data());
  } else if (impl_->kernel == SvmKernel::kHistogramIntersection) {
    // libsvm reads x[serial] for each support vector's serial only: one buffer per thread, indices set once,
    // the support vectors' kernel values written per query.
    thread_local std::vector<svm_node> x;
    const size_t size = size_t(impl_->num_train) + 2;
    if (x.size() != size || x[size - 1].index != -1 || x[size - 2].index != impl_->num_train) {
      x.assign(size, svm_node{0, 0.0});
      for (int i = 1; i <= impl_->num_train; ++i) x[size_t(i)].index = i;
      x[size - 1] = {-1, 0.0};
    }
    for (const auto& [serial, r] : impl_->kernel_rows) x[size_t(serial)].value = Intersection(row, r.data(), dims_);
    svm_predict_probability(impl_->model, x.data(), q.data());
  } else {
    const std::vector<svm_node> x = impl_->Query(row, dims_);
    svm_predict_probability(impl_->model, x.data(), q.data());
  }
  std::fill(p, p + num_classes_, 0.0);
  for (size_t i = 0; i < q.size(); ++i) p[impl_->class_of_svm_label_index[i]] = q[i];
}

void SvmClassifier::PredictProbabilitiesWithLibsvmKernel(const float* row, double* p) const {
  const std::vector<svm_node> x = impl_->Query(row, dims_);
  std::vector<double> q(impl_->class_of_svm_label_index.size());
  svm_predict_probability(impl_->model, x.data(), q.data());
  std::fill(p, p + num_classes_, 0.0);
  for (size_t i = 0; i < q.size(); ++i) p[impl_->class_of_svm_label_index[i]] = q[i];
}

Status SvmClassifier::Save(const std::string& path) const {
  const Impl& m = *impl_;
  const std::string tmp = TempPath();
  const int rc = svm_save_model(tmp.c_str(), m.model);
  std::string body;
  Status read = ReadFileBytes(tmp, &body);
  std::remove(tmp.c_str());
  if (rc != 0 || !read.ok()) return Status::Internal(path + ": libsvm could not write its model");
  std::ostringstream out;
  out.precision(9);
  out << "semvox_svm 1\nkernel " << (m.kernel == SvmKernel::kRbf ? "rbf" : "histogram_intersection") << "\ndims " << dims_
      << "\nclasses " << num_classes_ << "\ntrain_rows " << m.num_train << "\n";
  if (m.kernel == SvmKernel::kRbf) {
    out << "mean";
    for (double v : m.mean) out << ' ' << v;
    out << "\ninv_std";
    for (double v : m.inv_std) out << ' ' << v;
    out << "\n";
  } else {
    // Only the support vectors' rows are needed at prediction.
    std::vector<int> serials;
    for (int i = 0; i < m.model->l; ++i) serials.push_back(int(m.model->SV[i][0].value));
    out << "kernel_rows " << serials.size() << "\n";
    for (int s : serials) {
      out << s;
      for (float v : m.kernel_rows.at(s)) out << ' ' << v;
      out << "\n";
    }
  }
  out << "libsvm\n" << body;
  return WriteFileAtomic(path, out.str());
}

Result<SvmClassifier> SvmClassifier::Load(const std::string& path) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  auto bad = [&](const std::string& what) {
    return Status::InvalidInput(path + ": not a semvox SVM model: " + what + " (hint: write it with `semvox train`)");
  };
  const size_t split = bytes.find("\nlibsvm\n");
  if (bytes.rfind("semvox_svm 1\n", 0) != 0 || split == std::string::npos) return bad("missing header");
  std::istringstream in(bytes.substr(0, split));
  SvmClassifier svm;
  Impl& m = *svm.impl_;
  std::string key, kernel;
  int version = 0;
  in >> key >> version >> key >> kernel >> key >> svm.dims_ >> key >> svm.num_classes_ >> key >> m.num_train;
  if (!in || svm.dims_ < 1 || svm.dims_ > 100000 || svm.num_classes_ < 2 || svm.num_classes_ > 1000 || m.num_train < 1) return bad("bad header fields");
  if (kernel == "rbf") {
    m.kernel = SvmKernel::kRbf;
    m.mean.resize(size_t(svm.dims_));
    m.inv_std.resize(size_t(svm.dims_));
    in >> key;
    for (double& v : m.mean) in >> v;
    in >> key;
    for (double& v : m.inv_std) in >> v;
  } else if (kernel == "histogram_intersection") {
    m.kernel = SvmKernel::kHistogramIntersection;
    size_t count = 0;
    in >> key >> count;
    if (!in || count > size_t(m.num_train)) return bad("bad kernel_rows count");
    for (size_t i = 0; i < count; ++i) {
      int serial = 0;
      in >> serial;
      if (serial < 1 || serial > m.num_train) return bad("kernel row serial out of range");
      std::vector<float> row(static_cast<size_t>(svm.dims_));
      for (float& v : row) in >> v;
      m.kernel_rows[serial] = std::move(row);
    }
  } else {
    return bad("unknown kernel '" + kernel + "'");
  }
  if (!in) return bad("truncated header");
  const std::string tmp = TempPath();
  SEMVOX_RETURN_IF_ERROR(WriteFileAtomic(tmp, bytes.substr(split + 8)));
  m.model = svm_load_model(tmp.c_str());
  std::remove(tmp.c_str());
  if (!m.model) return bad("libsvm cannot parse the model");
  if (svm_check_probability_model(m.model) == 0) return bad("the model has no probability estimates");
  m.class_of_svm_label_index.resize(size_t(svm_get_nr_class(m.model)));
  std::vector<int> labels(m.class_of_svm_label_index.size());
  svm_get_labels(m.model, labels.data());
  for (size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] < 0 || labels[i] >= svm.num_classes_) return bad("class label out of range");
    m.class_of_svm_label_index[i] = labels[i];
  }
  if (!m.PrepareDenseRbf(svm.dims_)) return bad("a support vector's feature index is outside [1, dims]");
  return svm;
}

}  // namespace semvox
