#include "perception/knn_unary.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

namespace semvox {

std::vector<double> ClassFrequencyNormalisedProbability(std::span<const int> neighbour_counts,
                                                        std::span<const int64_t> training_counts) {
  const size_t m = neighbour_counts.size();
  std::vector<double> p(m, 0.0);
  int64_t k = 0, n = 0;
  for (size_t j = 0; j < m; ++j) {
    k += neighbour_counts[j];
    n += j < training_counts.size() ? training_counts[j] : 0;
  }
  auto uniform_over_seen = [&] {
    int seen = 0;
    for (size_t j = 0; j < m; ++j) seen += j < training_counts.size() && training_counts[j] > 0;
    for (size_t j = 0; j < m; ++j)
      p[j] = seen > 0 ? (j < training_counts.size() && training_counts[j] > 0 ? 1.0 / seen : 0.0) : 1.0 / double(m);
    return p;
  };
  if (k == 0) return uniform_over_seen();
  double sum = 0;
  for (size_t j = 0; j < m; ++j) {
    const double f = neighbour_counts[j], fbar = double(k) - f;
    const double F = j < training_counts.size() ? double(training_counts[j]) : 0.0, Fbar = double(n) - F;
    if (f <= 0 || F <= 0) continue;  // r_j = 0.
    if (fbar <= 0) {                 // Every neighbour has label j: r_j is infinite.
      std::fill(p.begin(), p.end(), 0.0);
      p[j] = 1.0;
      return p;
    }
    p[j] = (f / fbar) * (Fbar / F);
    sum += p[j];
  }
  if (!(sum > 0)) return uniform_over_seen();
  for (double& v : p) v /= sum;
  return p;
}

bool KnnOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (k < 1) return fail("k = " + std::to_string(k) + ". Violated constraint: k >= 1");
  if (!(probability_floor >= 0 && probability_floor < 1))
    return fail("probability_floor = " + std::to_string(probability_floor) +
                ". Violated constraint: 0 <= probability_floor < 1 / num_classes");
  if (leaf_max_size < 1) return fail("leaf_max_size = " + std::to_string(leaf_max_size) + ". Violated constraint: leaf_max_size >= 1");
  return true;
}

namespace {

// nanoflann dataset adaptor over a row-major float matrix.
struct RowMajorPoints {
  const std::vector<float>* data = nullptr;
  size_t dims = 0;
  size_t kdtree_get_point_count() const { return dims ? data->size() / dims : 0; }
  float kdtree_get_pt(size_t i, size_t d) const { return (*data)[i * dims + d]; }
  template <class Bbox>
  bool kdtree_get_bbox(Bbox&) const { return false; }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, RowMajorPoints>,
                                                   RowMajorPoints, -1, uint32_t>;

constexpr char kMagic[8] = {'S', 'V', 'K', 'N', 'N', '0', '0', '1'};

}  // namespace

struct KnnClassifier::Impl {
  int dims = 0;
  int num_classes = 0;
  KnnOptions options;
  std::vector<float> features;  // Standardised when options.standardise.
  std::vector<int> labels;
  std::vector<float> mean, inv_std;  // Per dimension; identity when not standardising.
  std::vector<int64_t> class_counts;
  RowMajorPoints points;
  std::unique_ptr<KdTree> tree;

  void Build() {
    points.data = &features;
    points.dims = size_t(dims);
    tree = std::make_unique<KdTree>(dims, points, nanoflann::KDTreeSingleIndexAdaptorParams(size_t(options.leaf_max_size)));
  }
  // The k nearest training rows of `z` (raw features: standardised here): their indices and squared distances
  // (nanoflann's L2 adaptor), nearest first; returns how many were found.
  size_t Nearest(std::span<const float> z, size_t k, std::vector<uint32_t>* idx, std::vector<float>* dist) const {
    std::vector<float> q(static_cast<size_t>(dims));
    for (int d = 0; d < dims; ++d) q[size_t(d)] = (z[size_t(d)] - mean[size_t(d)]) * inv_std[size_t(d)];
    idx->resize(k);
    dist->resize(k);
    return tree->knnSearch(q.data(), k, idx->data(), dist->data());
  }
};

KnnClassifier::KnnClassifier(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
KnnClassifier::KnnClassifier(KnnClassifier&&) noexcept = default;
KnnClassifier& KnnClassifier::operator=(KnnClassifier&&) noexcept = default;
KnnClassifier::~KnnClassifier() = default;

int KnnClassifier::dims() const { return impl_->dims; }
int KnnClassifier::num_classes() const { return impl_->num_classes; }
size_t KnnClassifier::size() const { return impl_->labels.size(); }
const std::vector<int64_t>& KnnClassifier::class_counts() const { return impl_->class_counts; }
const KnnOptions& KnnClassifier::options() const { return impl_->options; }

Result<KnnClassifier> KnnClassifier::Train(std::vector<float> features, int dims, std::vector<int> labels,
                                           int num_classes, const KnnOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("knn: " + error);
  if (dims < 1 || num_classes < 1)
    return Status::InvalidInput("knn: dims = " + std::to_string(dims) + ", num_classes = " +
                                std::to_string(num_classes) + ". Violated constraint: both >= 1");
  if (options.probability_floor * num_classes >= 1)
    return Status::InvalidInput("knn: probability_floor = " + std::to_string(options.probability_floor) +
                                ". Violated constraint: probability_floor < 1 / num_classes = " +
                                std::to_string(1.0 / num_classes));
  if (labels.empty() || features.size() != labels.size() * size_t(dims))
    return Status::InvalidInput("knn: expected " + std::to_string(labels.size()) + " rows of " + std::to_string(dims) +
                                " features (got " + std::to_string(features.size()) + " values) and at least one row");
  auto impl = std::make_unique<Impl>();
  impl->dims = dims;
  impl->num_classes = num_classes;
  impl->options = options;
  impl->class_counts.assign(size_t(num_classes), 0);
  for (int l : labels) {
    if (l < 0 || l >= num_classes)
      return Status::InvalidInput("knn: label " + std::to_string(l) + " outside [0, " + std::to_string(num_classes) + ")");
    ++impl->class_counts[size_t(l)];
  }
  for (float v : features)
    if (!std::isfinite(v)) return Status::InvalidInput("knn: non-finite training feature");
  impl->mean.assign(size_t(dims), 0.0f);
  impl->inv_std.assign(size_t(dims), 1.0f);
  const size_t n = labels.size();
  if (options.standardise) {
    for (int d = 0; d < dims; ++d) {
      double s = 0, s2 = 0;
      for (size_t i = 0; i < n; ++i) {
        const double v = features[i * size_t(dims) + size_t(d)];
        s += v;
        s2 += v * v;
      }
      const double m = s / double(n), var = std::max(0.0, s2 / double(n) - m * m);
      impl->mean[size_t(d)] = float(m);
      impl->inv_std[size_t(d)] = var > 1e-12 ? float(1.0 / std::sqrt(var)) : 1.0f;  // Constant dims stay as they are.
    }
    for (size_t i = 0; i < n; ++i)
      for (int d = 0; d < dims; ++d) {
        float& v = features[i * size_t(dims) + size_t(d)];
        v = (v - impl->mean[size_t(d)]) * impl->inv_std[size_t(d)];
      }
  }
  impl->features = std::move(features);
  impl->labels = std::move(labels);
  impl->Build();
  return KnnClassifier(std::move(impl));
}

namespace {

// Mean of the square roots of nanoflann's squared distances; 0 without any.
double MeanDistance(const std::vector<float>& squared, size_t count) {
  double sum = 0;
  for (size_t i = 0; i < count; ++i) sum += std::sqrt(double(squared[i]));
  return count ? sum / double(count) : 0.0;
}

}  // namespace

std::vector<int> KnnClassifier::NeighbourCounts(std::span<const float> z) const {
  double unused = 0;
  return NeighbourCountsAndDistance(z, &unused);
}

std::vector<int> KnnClassifier::NeighbourCountsAndDistance(std::span<const float> z, double* distance) const {
  const Impl& m = *impl_;
  std::vector<int> counts(size_t(m.num_classes), 0);
  *distance = std::numeric_limits<double>::quiet_NaN();
  if (z.size() != size_t(m.dims)) return counts;
  std::vector<uint32_t> idx;
  std::vector<float> dist;
  const size_t found = m.Nearest(z, std::min(size_t(m.options.k), m.labels.size()), &idx, &dist);
  for (size_t i = 0; i < found; ++i) ++counts[size_t(m.labels[idx[i]])];
  *distance = MeanDistance(dist, found);
  return counts;
}

std::vector<double> KnnClassifier::Probabilities(std::span<const float> z) const {
  double unused = 0;
  return Probabilities(z, &unused);
}

std::vector<double> KnnClassifier::Probabilities(std::span<const float> z, double* neighbour_distance) const {
  std::vector<double> p = ClassFrequencyNormalisedProbability(NeighbourCountsAndDistance(z, neighbour_distance), impl_->class_counts);
  const double floor = impl_->options.probability_floor;
  if (floor > 0) {
    double sum = 0;
    for (double& v : p) sum += (v = std::max(v, floor));
    for (double& v : p) v /= sum;
  }
  return p;
}

double KnnClassifier::NeighbourDistance(std::span<const float> z) const {
  double distance = 0;
  NeighbourCountsAndDistance(z, &distance);
  return distance;
}

double KnnClassifier::TrainingNeighbourDistanceQuantile(double q, size_t max_rows) const {
  const Impl& m = *impl_;
  const size_t rows = m.labels.size();
  if (rows < 2) return 0.0;
  const size_t k = std::min(size_t(m.options.k), rows - 1);
  const size_t n = max_rows > 0 ? std::min(rows, max_rows) : rows;
  std::vector<double> own(n);
  std::vector<uint32_t> idx(k + 1);
  std::vector<float> dist(k + 1);
  for (size_t j = 0; j < n; ++j) {
    const size_t r = j * rows / n;  // An even stride over the rows (all of them when n = rows).
    const size_t found = m.tree->knnSearch(&m.features[r * size_t(m.dims)], k + 1, idx.data(), dist.data());
    // Leave the observation itself out (or, among exact duplicates, one of them); the rest are its neighbours.
    size_t self = found;
    for (size_t i = 0; i < found; ++i)
      if (idx[i] == r) self = i;
    if (self == found) self = 0;
    double sum = 0;
    size_t used = 0;
    for (size_t i = 0; i < found && used < k; ++i)
      if (i != self) sum += std::sqrt(double(dist[i])), ++used;
    own[j] = used ? sum / double(used) : 0.0;
  }
  const double t = std::clamp(q, 0.0, 1.0) * double(n - 1);
  const size_t lo = size_t(std::floor(t)), hi = std::min(lo + 1, n - 1);
  std::nth_element(own.begin(), own.begin() + std::ptrdiff_t(lo), own.end());
  const double a = own[lo];
  const double b = hi == lo ? a : *std::min_element(own.begin() + std::ptrdiff_t(lo) + 1, own.end());
  return a + (t - double(lo)) * (b - a);
}

Status KnnClassifier::Save(const std::string& path) const {
  const Impl& m = *impl_;
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return Status::InvalidInput(FileError(path, "cannot open for writing", "check the directory exists"));
    auto put = [&](const void* p, size_t bytes) { out.write(static_cast<const char*>(p), std::streamsize(bytes)); };
    const int32_t header[4] = {m.dims, m.num_classes, m.options.k, m.options.leaf_max_size};
    const double floor = m.options.probability_floor;
    const uint8_t standardise = m.options.standardise;
    const uint64_t n = m.labels.size();
    put(kMagic, sizeof(kMagic));
    put(header, sizeof(header));
    put(&floor, sizeof(floor));
    put(&standardise, 1);
    put(&n, sizeof(n));
    put(m.mean.data(), m.mean.size() * sizeof(float));
    put(m.inv_std.data(), m.inv_std.size() * sizeof(float));
    put(m.features.data(), m.features.size() * sizeof(float));
    put(m.labels.data(), m.labels.size() * sizeof(int));
    if (!out) return Status::Internal(FileError(path, "write failed", "check free disk space"));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    return Status::Internal(FileError(path, "cannot rename the temporary model file"));
  }
  return Status::Ok();
}

Result<KnnClassifier> KnnClassifier::Load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::InvalidInput(FileError(path, "cannot open k-NN model", "run `semvox train` or check the path"));
  auto get = [&](void* p, size_t bytes) { return bool(in.read(static_cast<char*>(p), std::streamsize(bytes))); };
  char magic[8];
  int32_t header[4];
  double floor = 0;
  uint8_t standardise = 0;
  uint64_t n = 0;
  if (!get(magic, 8) || std::memcmp(magic, kMagic, 8) != 0)
    return Status::InvalidInput(FileError(path, "not a semvox k-NN model (bad magic)", "re-run `semvox train`"));
  if (!get(header, sizeof(header)) || !get(&floor, sizeof(floor)) || !get(&standardise, 1) || !get(&n, sizeof(n)))
    return Status::InvalidInput(FileError(path, "truncated k-NN model header", "re-run `semvox train`"));
  const int dims = header[0], num_classes = header[1];
  constexpr uint64_t kMaxRows = uint64_t(1) << 32;
  if (dims < 1 || dims > 1024 || num_classes < 1 || num_classes > 4096 || n == 0 || n > kMaxRows)
    return Status::InvalidInput(FileError(path, "implausible k-NN model header", "re-run `semvox train`"));
  const size_t d_count = static_cast<size_t>(dims), n_rows = static_cast<size_t>(n);
  std::vector<float> mean(d_count), inv_std(d_count), features(n_rows * d_count);
  std::vector<int> labels(n_rows);
  if (!get(mean.data(), mean.size() * 4) || !get(inv_std.data(), inv_std.size() * 4) ||
      !get(features.data(), features.size() * 4) || !get(labels.data(), labels.size() * sizeof(int)))
    return Status::InvalidInput(FileError(path, "truncated k-NN model: expected " + std::to_string(n) + " rows",
                                          "re-run `semvox train`"));
  // The stored rows are already standardised: rebuild the index on them as they are, so that a loaded
  // model answers bit for bit as the saved one.
  KnnOptions options;
  options.k = header[2];
  options.leaf_max_size = header[3];
  options.probability_floor = floor;
  options.standardise = standardise != 0;
  std::string error;
  if (!options.Check(&error) || options.probability_floor * num_classes >= 1)
    return Status::InvalidInput(FileError(path, "bad k-NN options: " + error, "re-run `semvox train`"));
  auto impl = std::make_unique<Impl>();
  impl->dims = dims;
  impl->num_classes = num_classes;
  impl->options = options;
  impl->class_counts.assign(size_t(num_classes), 0);
  for (int l : labels) {
    if (l < 0 || l >= num_classes)
      return Status::InvalidInput(FileError(path, "label " + std::to_string(l) + " outside [0, " + std::to_string(num_classes) + ")",
                                            "re-run `semvox train`"));
    ++impl->class_counts[size_t(l)];
  }
  for (float v : features)
    if (!std::isfinite(v)) return Status::InvalidInput(FileError(path, "non-finite feature", "re-run `semvox train`"));
  impl->mean = std::move(mean);
  impl->inv_std = std::move(inv_std);
  impl->features = std::move(features);
  impl->labels = std::move(labels);
  impl->Build();
  return KnnClassifier(std::move(impl));
}

}  // namespace semvox
