#include "crf/energy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>

namespace semvox {
namespace {

[[noreturn]] void EnergyMisuse(const std::string& what) {
  std::fprintf(stderr, "semvox: CrfEnergy misuse: %s\n", what.c_str());
  std::abort();
}

}  // namespace

CrfEnergy::CrfEnergy(int num_nodes, int num_labels) : num_nodes_(num_nodes), num_labels_(num_labels) {
  if (num_nodes < 0 || num_labels < 1) {
    EnergyMisuse("CrfEnergy(num_nodes = " + std::to_string(num_nodes) + ", num_labels = " +
                 std::to_string(num_labels) + "): need num_nodes >= 0 and num_labels >= 1");
  }
  unary_.assign(static_cast<size_t>(num_nodes) * num_labels, 0.0f);
}

size_t CrfEnergy::Index(int node, CrfLabel label) const {
  if (node < 0 || node >= num_nodes_ || label < 0 || label >= num_labels_) {
    EnergyMisuse("unary index (node " + std::to_string(node) + ", label " + std::to_string(label) +
                 ") out of range");
  }
  return static_cast<size_t>(label) * num_nodes_ + node;
}

void CrfEnergy::SetUnaries(int node, std::span<const float> costs) {
  if (static_cast<int>(costs.size()) != num_labels_) EnergyMisuse("SetUnaries: costs.size() != num_labels");
  for (int l = 0; l < num_labels_; ++l) unary_[Index(node, l)] = costs[l];
}

int CrfEnergy::AddCompatibilityModel(std::vector<float> matrix) {
  if (matrix.size() != static_cast<size_t>(num_labels_) * num_labels_) {
    EnergyMisuse("AddCompatibilityModel: matrix has " + std::to_string(matrix.size()) +
                 " entries, expected num_labels^2");
  }
  models_.push_back(std::move(matrix));
  return static_cast<int>(models_.size());
}

bool CrfEnergy::IsMetric(int model) const {
  if (model == kPottsModel) return true;
  const int L = num_labels_;
  for (int a = 0; a < L; ++a) {
    for (int b = 0; b < L; ++b) {
      const float v = ModelCost(model, a, b);
      if ((a == b) != (v == 0.0f) || v < 0 || v != ModelCost(model, b, a)) return false;
      for (int c = 0; c < L; ++c) {
        if (v > ModelCost(model, a, c) + ModelCost(model, c, b)) return false;
      }
    }
  }
  return true;
}

void CrfEnergy::AddEdge(int i, int j, float weight, int model) {
  if (i < 0 || i >= num_nodes_ || j < 0 || j >= num_nodes_ || i == j) {
    EnergyMisuse("AddEdge(" + std::to_string(i) + ", " + std::to_string(j) +
                 "): nodes must be distinct and in [0, num_nodes)");
  }
  if (model < 0 || model >= num_models()) EnergyMisuse("AddEdge: unknown model " + std::to_string(model));
  edges_.push_back(Edge{i, j, weight, model});
}

int CrfEnergy::AddRobustPnClique(std::vector<int> nodes, const RobustPnParams& params,
                                 std::vector<float> node_weights) {
  if (!node_weights.empty() && node_weights.size() != nodes.size()) {
    EnergyMisuse("AddRobustPnClique: node_weights.size() != nodes.size()");
  }
  if (!params.gamma.empty() && static_cast<int>(params.gamma.size()) != num_labels_) {
    EnergyMisuse("AddRobustPnClique: gamma.size() = " + std::to_string(params.gamma.size()) +
                 ", expected num_labels = " + std::to_string(num_labels_) + " (or empty)");
  }
  double total = 0;
  for (size_t k = 0; k < nodes.size(); ++k) {
    if (nodes[k] < 0 || nodes[k] >= num_nodes_) {
      EnergyMisuse("AddRobustPnClique: node " + std::to_string(nodes[k]) + " out of range");
    }
    const float w = node_weights.empty() ? 1.0f : node_weights[k];
    clique_nodes_.push_back(nodes[k]);
    clique_weights_.push_back(w);
    total += w;
  }
  clique_offsets_.push_back(static_cast<int>(clique_nodes_.size()));
  clique_total_weight_.push_back(total);
  for (int l = 0; l < num_labels_; ++l) clique_gamma_.push_back(params.gamma.empty() ? 0.0f : params.gamma[l]);
  clique_gamma_max_.push_back(params.gamma_max);
  clique_q_.push_back(params.truncation_q);
  return num_cliques() - 1;
}

double CrfEnergy::CliquePotentialFromWeights(int c, std::span<const double> label_weight) const {
  const double W = clique_total_weight_[c];
  double best = clique_gamma_max_[c];
  for (int l = 0; l < num_labels_; ++l) {
    const double disagreeing = std::max(0.0, W - label_weight[l]);
    best = std::min(best, clique_gamma(c, l) + clique_slope(c, l) * disagreeing);
  }
  return best;
}

double CrfEnergy::CliquePotential(int c, std::span<const CrfLabel> labels) const {
  std::vector<double> weight(num_labels_, 0.0);
  const auto nodes = clique_nodes(c);
  const auto weights = clique_weights(c);
  for (size_t k = 0; k < nodes.size(); ++k) weight[labels[nodes[k]]] += weights[k];
  return CliquePotentialFromWeights(c, weight);
}

bool CrfEnergy::Check(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  for (size_t k = 0; k < unary_.size(); ++k) {
    if (!std::isfinite(unary_[k])) {
      std::ostringstream os;
      os << "unary(node " << k % num_nodes_ << ", label " << k / num_nodes_ << ") = " << unary_[k]
         << ". Violated constraint: finite";
      return fail(os.str());
    }
  }
  for (size_t m = 0; m < models_.size(); ++m) {
    for (float v : models_[m]) {
      if (!std::isfinite(v)) {
        return fail("compatibility model " + std::to_string(m + 1) + " has a non-finite entry. Violated constraint: finite");
      }
    }
  }
  for (size_t e = 0; e < edges_.size(); ++e) {
    if (!std::isfinite(edges_[e].weight) || edges_[e].weight < 0) {
      std::ostringstream os;
      os << "edge " << e << " weight = " << edges_[e].weight << ". Violated constraint: finite and >= 0";
      return fail(os.str());
    }
  }
  for (int c = 0; c < num_cliques(); ++c) {
    std::ostringstream os;
    os << "clique " << c << ": ";
    const double W = clique_total_weight_[c];
    const float q = clique_q_[c], gmax = clique_gamma_max_[c];
    for (float w : clique_weights(c)) {
      if (!(w > 0) || !std::isfinite(w)) {
        os << "node weight = " << w << ". Violated constraint: node weights > 0";
        return fail(os.str());
      }
    }
    if (!(q > 0) || !(2.0 * q <= W * (1 + 1e-6))) {  // Float slack.
      os << "truncation_q = " << q << " with total node weight " << W
         << ". Violated constraint: 0 < truncation_q <= total weight / 2";
      return fail(os.str());
    }
    if (!std::isfinite(gmax)) {
      os << "gamma_max = " << gmax << ". Violated constraint: finite";
      return fail(os.str());
    }
    for (int l = 0; l < num_labels_; ++l) {
      const float g = clique_gamma(c, l);
      if (!std::isfinite(g) || g > gmax) {
        os << "gamma[" << l << "] = " << g << ", gamma_max = " << gmax << ". Violated constraint: gamma[l] <= gamma_max";
        return fail(os.str());
      }
    }
  }
  return true;
}

double CrfEnergy::UnaryEnergy(std::span<const CrfLabel> labels) const {
  double sum = 0;
  for (int i = 0; i < num_nodes_; ++i) sum += unary(i, labels[i]);
  return sum;
}

double CrfEnergy::PairwiseEnergy(std::span<const CrfLabel> labels) const {
  double sum = 0;
  for (const Edge& e : edges_) sum += EdgeCost(e, labels[e.i], labels[e.j]);
  return sum;
}

double CrfEnergy::HigherOrderEnergy(std::span<const CrfLabel> labels) const {
  double sum = 0;
  std::vector<double> weight(num_labels_);
  for (int c = 0; c < num_cliques(); ++c) {
    std::fill(weight.begin(), weight.end(), 0.0);
    const auto nodes = clique_nodes(c);
    const auto weights = clique_weights(c);
    for (size_t k = 0; k < nodes.size(); ++k) weight[labels[nodes[k]]] += weights[k];
    sum += CliquePotentialFromWeights(c, weight);
  }
  return sum;
}

double CrfEnergy::Evaluate(std::span<const CrfLabel> labels) const {
  if (static_cast<int>(labels.size()) != num_nodes_) EnergyMisuse("Evaluate: labels.size() != num_nodes");
  for (CrfLabel l : labels) {
    if (l < 0 || l >= num_labels_) EnergyMisuse("Evaluate: label " + std::to_string(l) + " out of range");
  }
  return UnaryEnergy(labels) + PairwiseEnergy(labels) + HigherOrderEnergy(labels);
}

std::vector<CrfLabel> CrfEnergy::UnaryArgmin() const {
  std::vector<CrfLabel> labels(num_nodes_, 0);
  std::vector<float> best(unary_.begin(), unary_.begin() + num_nodes_);
  for (int l = 1; l < num_labels_; ++l) {
    const float* u = unary_.data() + static_cast<size_t>(l) * num_nodes_;
    for (int i = 0; i < num_nodes_; ++i) {
      if (u[i] < best[i]) {
        best[i] = u[i];
        labels[i] = l;
      }
    }
  }
  return labels;
}

NodeIncidence CrfEnergy::EdgeIncidence() const {
  NodeIncidence inc;
  inc.offsets.assign(num_nodes_ + 1, 0);
  for (const Edge& e : edges_) {
    ++inc.offsets[e.i + 1];
    ++inc.offsets[e.j + 1];
  }
  for (int v = 0; v < num_nodes_; ++v) inc.offsets[v + 1] += inc.offsets[v];
  inc.items.resize(inc.offsets[num_nodes_]);
  std::vector<int> fill(inc.offsets.begin(), inc.offsets.end() - 1);
  for (size_t k = 0; k < edges_.size(); ++k) {
    inc.items[fill[edges_[k].i]++] = static_cast<int>(k);
    inc.items[fill[edges_[k].j]++] = static_cast<int>(k);
  }
  return inc;
}

NodeIncidence CrfEnergy::CliqueIncidence() const {
  NodeIncidence inc;
  inc.offsets.assign(num_nodes_ + 1, 0);
  for (int node : clique_nodes_) ++inc.offsets[node + 1];
  for (int v = 0; v < num_nodes_; ++v) inc.offsets[v + 1] += inc.offsets[v];
  inc.items.resize(inc.offsets[num_nodes_]);
  std::vector<int> fill(inc.offsets.begin(), inc.offsets.end() - 1);
  for (int c = 0; c < num_cliques(); ++c) {
    for (int node : clique_nodes(c)) inc.items[fill[node]++] = c;
  }
  return inc;
}

size_t CrfEnergy::MemoryBytes() const {
  size_t bytes = unary_.capacity() * sizeof(float) + edges_.capacity() * sizeof(Edge);
  for (const auto& m : models_) bytes += m.capacity() * sizeof(float);
  bytes += (clique_offsets_.capacity() + clique_nodes_.capacity()) * sizeof(int) +
           (clique_weights_.capacity() + clique_gamma_.capacity() + clique_gamma_max_.capacity() +
            clique_q_.capacity()) * sizeof(float) + clique_total_weight_.capacity() * sizeof(double);
  return bytes;
}

}  // namespace semvox
