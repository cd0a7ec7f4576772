#include "objects/random_forest.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <sstream>

#include "core/file_util.h"
#include "core/hash.h"

namespace semvox {

bool RandomForestOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (trees < 1) return fail("random forest: trees must be >= 1");
  if (features_per_split < 0) return fail("random forest: features_per_split must be >= 0");
  if (min_leaf < 1 || max_depth < 1) return fail("random forest: min_leaf and max_depth must be >= 1");
  if (!(probability_floor >= 0 && probability_floor < 1)) return fail("random forest: probability_floor must be in [0, 1)");
  return true;
}

namespace {

// A node: a split (feature >= 0: x[feature] <= threshold goes to `left`, else `right`) or a leaf
// (feature = -1: the class shares leaf_class / leaf_share [begin, end)).
struct Node {
  int feature = -1;
  float threshold = 0;
  int left = -1, right = -1;
  int begin = 0, end = 0;
};

struct Tree {
  std::vector<Node> nodes;
  std::vector<int> leaf_class;
  std::vector<float> leaf_share;
};

// Uniform integer in [0, n) from the standard-fixed mt19937_64 output (portable, unlike
// std::uniform_int_distribution).
size_t Below(std::mt19937_64* rng, size_t n) { return size_t((*rng)() % uint64_t(n)); }

class TreeBuilder {
 public:
  TreeBuilder(std::span<const float> x, int dims, std::span<const int> y, std::span<const double> w, int K,
              const RandomForestOptions& o, int mtry, uint64_t seed)
      : x_(x), dims_(dims), y_(y), w_(w), K_(K), o_(o), mtry_(mtry), rng_(seed) {}

  Tree Build() {
    const size_t n = y_.size();
    std::vector<int> rows(n);
    for (size_t i = 0; i < n; ++i) rows[i] = int(Below(&rng_, n));  // Bootstrap sample.
    std::sort(rows.begin(), rows.end());
    Grow(rows, 0);
    return std::move(tree_);
  }

 private:
  int Leaf(const std::vector<int>& rows) {
    std::vector<double> c(size_t(K_), 0.0);
    double total = 0;
    for (int r : rows) c[size_t(y_[size_t(r)])] += w_[size_t(r)], total += w_[size_t(r)];
    Node node;
    node.begin = int(tree_.leaf_class.size());
    for (int k = 0; k < K_; ++k)
      if (c[size_t(k)] > 0) tree_.leaf_class.push_back(k), tree_.leaf_share.push_back(float(c[size_t(k)] / total));
    node.end = int(tree_.leaf_class.size());
    tree_.nodes.push_back(node);
    return int(tree_.nodes.size()) - 1;
  }

  int Grow(const std::vector<int>& rows, int depth) {
    const size_t n = rows.size();
    std::vector<double> total(size_t(K_), 0.0);
    int first = y_[size_t(rows[0])];
    bool pure = true;
    for (int r : rows) total[size_t(y_[size_t(r)])] += w_[size_t(r)], pure &= y_[size_t(r)] == first;
    if (pure || depth >= o_.max_depth || n < size_t(2 * o_.min_leaf)) return Leaf(rows);
    double W = 0, parent = 0;
    for (double t : total) W += t, parent += t * t;
    parent /= W;
    // Candidate dimensions: the first mtry of a partial Fisher-Yates shuffle.
    std::vector<int> dims(static_cast<size_t>(dims_));
    std::iota(dims.begin(), dims.end(), 0);
    for (int i = 0; i < mtry_; ++i) std::swap(dims[size_t(i)], dims[size_t(i) + Below(&rng_, size_t(dims_ - i))]);
    // Maximise sum_k cl_k^2 / wl + sum_k cr_k^2 / wr (= W minus the weighted Gini impurity of the children).
    double best = parent * (1 + 1e-12) + 1e-12;
    int best_dim = -1;
    float best_t = 0;
    std::vector<int> order(rows.size());
    std::vector<double> left(static_cast<size_t>(K_), 0.0);
    for (int i = 0; i < mtry_; ++i) {
      const int d = dims[size_t(i)];
      auto value = [&](int r) { return x_[size_t(r) * size_t(dims_) + size_t(d)]; };
      order = rows;
      std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return value(a) < value(b); });
      std::fill(left.begin(), left.end(), 0.0);
      double wl = 0, sl = 0, sr = parent * W;
      std::vector<double> right = total;
      for (size_t j = 0; j + 1 < n; ++j) {
        const int r = order[j];
        const size_t c = size_t(y_[size_t(r)]);
        const double wr_ = w_[size_t(r)];
        sl += 2 * left[c] * wr_ + wr_ * wr_;
        sr += -2 * right[c] * wr_ + wr_ * wr_;
        left[c] += wr_, right[c] -= wr_, wl += wr_;
        if (j + 1 < size_t(o_.min_leaf) || n - (j + 1) < size_t(o_.min_leaf)) continue;
        const float a = value(r), b = value(order[j + 1]);
        if (!(a < b)) continue;
        const double wr = W - wl;
        if (wl <= 0 || wr <= 0) continue;
        const double score = sl / wl + sr / wr;
        if (score > best) {
          best = score, best_dim = d;
          best_t = a + (b - a) * 0.5f;
          if (!(best_t < b)) best_t = a;
        }
      }
    }
    if (best_dim < 0) return Leaf(rows);
    std::vector<int> l, r;
    for (int row : rows) (x_[size_t(row) * size_t(dims_) + size_t(best_dim)] <= best_t ? l : r).push_back(row);
    const int me = int(tree_.nodes.size());
    tree_.nodes.push_back(Node{});
    const int li = Grow(l, depth + 1);
    const int ri = Grow(r, depth + 1);
    Node& node = tree_.nodes[size_t(me)];
    node.feature = best_dim, node.threshold = best_t, node.left = li, node.right = ri;
    return me;
  }

  std::span<const float> x_;
  int dims_;
  std::span<const int> y_;
  std::span<const double> w_;
  int K_;
  const RandomForestOptions& o_;
  int mtry_;
  std::mt19937_64 rng_;
  Tree tree_;
};

}  // namespace

struct RandomForest::Impl {
  int dims = 0, K = 0;
  double floor = 0;
  std::vector<Tree> trees;
};

RandomForest::RandomForest(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RandomForest::RandomForest(RandomForest&&) noexcept = default;
RandomForest& RandomForest::operator=(RandomForest&&) noexcept = default;
RandomForest::~RandomForest() = default;

int RandomForest::dims() const { return impl_->dims; }
int RandomForest::num_classes() const { return impl_->K; }
int RandomForest::num_trees() const { return int(impl_->trees.size()); }
size_t RandomForest::num_nodes() const {
  size_t n = 0;
  for (const Tree& t : impl_->trees) n += t.nodes.size();
  return n;
}

Result<RandomForest> RandomForest::Train(std::span<const float> features, int dims, std::span<const int> labels, int num_classes,
                                         const RandomForestOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput(error);
  if (dims < 1 || num_classes < 1) return Status::InvalidInput("random forest: dims and num_classes must be >= 1");
  if (labels.empty() || features.size() != labels.size() * size_t(dims))
    return Status::InvalidInput("random forest: need one row of dims features per label, and at least one row");
  if (options.probability_floor * num_classes >= 1) return Status::InvalidInput("random forest: probability_floor must be below 1 / num_classes");
  std::vector<int64_t> count(size_t(num_classes), 0);
  for (int y : labels) {
    if (y < 0 || y >= num_classes) return Status::InvalidInput("random forest: label " + std::to_string(y) + " outside [0, num_classes)");
    ++count[size_t(y)];
  }
  for (float v : features)
    if (!std::isfinite(v)) return Status::InvalidInput("random forest: a feature is not finite");
  std::vector<double> w(labels.size(), 1.0);
  if (options.balance_classes) {
    int present = 0;
    for (int64_t c : count) present += c > 0;
    for (size_t i = 0; i < labels.size(); ++i) w[i] = double(labels.size()) / (double(present) * double(count[size_t(labels[i])]));
  }
  const int mtry = std::min(dims, options.features_per_split > 0 ? options.features_per_split : std::max(1, int(std::lround(std::sqrt(double(dims))))));
  auto impl = std::make_unique<Impl>();
  impl->dims = dims, impl->K = num_classes, impl->floor = options.probability_floor;
  impl->trees.resize(size_t(options.trees));
  tbb::parallel_for(0, options.trees, [&](int t) {
    TreeBuilder b(features, dims, labels, w, num_classes, options, mtry, SplitMix64(options.seed * 0x100000001B3ull + uint64_t(t)));
    impl->trees[size_t(t)] = b.Build();
  });
  return RandomForest(std::move(impl));
}

std::vector<double> RandomForest::Probabilities(std::span<const float> x) const {
  const Impl& m = *impl_;
  std::vector<double> p(size_t(m.K), 0.0);
  if (x.size() != size_t(m.dims)) return p;
  for (const Tree& t : m.trees) {
    int n = 0;
    while (t.nodes[size_t(n)].feature >= 0) {
      const Node& node = t.nodes[size_t(n)];
      n = x[size_t(node.feature)] <= node.threshold ? node.left : node.right;
    }
    const Node& leaf = t.nodes[size_t(n)];
    for (int i = leaf.begin; i < leaf.end; ++i) p[size_t(t.leaf_class[size_t(i)])] += t.leaf_share[size_t(i)];
  }
  double sum = 0;
  for (double& v : p) v = std::max(v / double(m.trees.size()), m.floor), sum += v;
  for (double& v : p) v /= sum;
  return p;
}

Status RandomForest::Save(const std::string& path) const {
  const Impl& m = *impl_;
  std::string s;
  char buf[64];
  s += "semvox_random_forest 1\n";
  std::snprintf(buf, sizeof buf, "%d %d %zu %.9g\n", m.dims, m.K, m.trees.size(), m.floor);
  s += buf;
  for (const Tree& t : m.trees) {
    s += "tree " + std::to_string(t.nodes.size()) + "\n";
    for (const Node& n : t.nodes) {
      if (n.feature >= 0) {
        std::snprintf(buf, sizeof buf, "S %d %.9g %d %d\n", n.feature, double(n.threshold), n.left, n.right);
        s += buf;
      } else {
        s += "L " + std::to_string(n.end - n.begin);
        for (int i = n.begin; i < n.end; ++i) {
          std::snprintf(buf, sizeof buf, " %d %.7g", t.leaf_class[size_t(i)], double(t.leaf_share[size_t(i)]));
          s += buf;
        }
        s += "\n";
      }
    }
  }
  return WriteFileAtomic(path, s);
}

Result<RandomForest> RandomForest::Load(const std::string& path) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  std::istringstream in(bytes);
  auto bad = [&](const std::string& what) {
    return Status::InvalidInput(FileError(path, "not a random forest model: " + what, "re-run `semvox train`"));
  };
  std::string magic;
  int version = 0;
  if (!(in >> magic >> version) || magic != "semvox_random_forest" || version != 1) return bad("bad header");
  auto impl = std::make_unique<Impl>();
  size_t trees = 0;
  if (!(in >> impl->dims >> impl->K >> trees >> impl->floor) || impl->dims < 1 || impl->K < 1 || trees < 1 || trees > 100000 ||
      !(impl->floor >= 0 && impl->floor * impl->K < 1))
    return bad("bad sizes");
  impl->trees.resize(trees);
  for (size_t ti = 0; ti < trees; ++ti) {
    Tree& t = impl->trees[ti];
    std::string word;
    size_t nodes = 0;
    if (!(in >> word >> nodes) || word != "tree" || nodes < 1 || nodes > 10000000) return bad("tree " + std::to_string(ti) + ": bad size");
    t.nodes.resize(nodes);
    for (size_t i = 0; i < nodes; ++i) {
      Node& n = t.nodes[i];
      std::string kind;
      if (!(in >> kind)) return bad("tree " + std::to_string(ti) + ": truncated");
      if (kind == "S") {
        if (!(in >> n.feature >> n.threshold >> n.left >> n.right) || n.feature < 0 || n.feature >= impl->dims || !std::isfinite(n.threshold) ||
            n.left <= int(i) || n.right <= int(i) || n.left >= int(nodes) || n.right >= int(nodes))
          return bad("tree " + std::to_string(ti) + " node " + std::to_string(i) + ": bad split");
      } else if (kind == "L") {
        int m = 0;
        if (!(in >> m) || m < 1 || m > impl->K) return bad("tree " + std::to_string(ti) + " node " + std::to_string(i) + ": bad leaf");
        n.begin = int(t.leaf_class.size());
        for (int k = 0; k < m; ++k) {
          int c = -1;
          float share = -1;
          if (!(in >> c >> share) || c < 0 || c >= impl->K || !(share >= 0 && share <= 1.0001f))
            return bad("tree " + std::to_string(ti) + " node " + std::to_string(i) + ": bad leaf share");
          t.leaf_class.push_back(c), t.leaf_share.push_back(share);
        }
        n.end = int(t.leaf_class.size());
      } else {
        return bad("tree " + std::to_string(ti) + " node " + std::to_string(i) + ": expected S or L");
      }
    }
  }
  return RandomForest(std::move(impl));
}

}  // namespace semvox
