// Boost's Boykov-Kolmogorov max-flow behind the graph interface of crf_internal::RunAlphaExpansion, for
// benchmarks only (crf_bench, voxelcrf_bench): the same alpha-expansion driver on another max-flow.
#pragma once
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/property_map/property_map.hpp>
#include <vector>

namespace semvox::bench {

// Boost's BK behind the interface of crf_internal::RunAlphaExpansion. Vertices: the CRF/auxiliary nodes,
// then source and sink; terminal capacities become arcs source -> v and v -> sink (with reverse arcs).
class BoostBkGraph {
 public:
  struct ArcId {
    int id = 0;
  };
  using Graph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, ArcId>;
  using EdgeDesc = boost::graph_traits<Graph>::edge_descriptor;

  int AddNodes(int count) {
    const int first = n_;
    n_ += count;
    terminal_.resize(n_, 0.0);
    return first;
  }
  int AddEdge(int i, int j, double cap_ij, double cap_ji) {
    pairs_.emplace_back(i, j);
    init_caps_.push_back(cap_ij);
    init_caps_.push_back(cap_ji);
    return static_cast<int>(pairs_.size()) - 1;
  }
  void ResetFlow() { constant_flow_ = 0; }
  void SetTerminalCapacity(int v, double source_minus_sink) { terminal_[v] = source_minus_sink; }
  void SetEdgeCapacities(int e, double cap_ij, double cap_ji) {
    if (!built_) {
      init_caps_[2 * e] = cap_ij;
      init_caps_[2 * e + 1] = cap_ji;
      return;
    }
    capacity_[csr_of_arc_[2 * e]] = cap_ij;
    capacity_[csr_of_arc_[2 * e + 1]] = cap_ji;
  }
  void AddTerminalCapacities(int v, double source_cap, double sink_cap) {
    constant_flow_ += std::min(source_cap, sink_cap);
    const double delta = source_cap - sink_cap;
    double& tc = terminal_[v];
    if ((tc > 0 && delta < 0) || (tc < 0 && delta > 0)) constant_flow_ += std::min(std::abs(tc), std::abs(delta));
    tc += delta;
  }
  double Solve() {
    if (!built_) Build();
    const int E = static_cast<int>(pairs_.size());
    for (int v = 0; v < n_; ++v) {
      const int base = 2 * E + 4 * v;
      capacity_[csr_of_arc_[base + 0]] = std::max(terminal_[v], 0.0);   // source -> v
      capacity_[csr_of_arc_[base + 1]] = 0;                             // v -> source
      capacity_[csr_of_arc_[base + 2]] = std::max(-terminal_[v], 0.0);  // v -> sink
      capacity_[csr_of_arc_[base + 3]] = 0;                             // sink -> v
    }
    std::copy(capacity_.begin(), capacity_.end(), residual_.begin());
    const auto edge_index = get(boost::edge_index, graph_);
    const auto vertex_index = get(boost::vertex_index, graph_);
    const double flow = boost::boykov_kolmogorov_max_flow(
        graph_, boost::make_iterator_property_map(capacity_.begin(), edge_index),
        boost::make_iterator_property_map(residual_.begin(), edge_index),
        boost::make_iterator_property_map(reverse_.begin(), edge_index),
        boost::make_iterator_property_map(predecessor_.begin(), vertex_index),
        boost::make_iterator_property_map(color_.begin(), vertex_index),
        boost::make_iterator_property_map(distance_.begin(), vertex_index), vertex_index, n_, n_ + 1);
    return flow + constant_flow_;
  }
  // Boost colours the sink tree white (source tree black, free nodes gray).
  bool InSinkSegment(int v) const { return color_[v] == boost::white_color; }
  size_t MemoryBytes() const {
    return graph_.m_forward.m_rowstart.capacity() * sizeof(size_t) +
           graph_.m_forward.m_column.capacity() * sizeof(size_t) + num_arcs_ * sizeof(ArcId) +
           (capacity_.capacity() + residual_.capacity()) * sizeof(double) + reverse_.capacity() * sizeof(EdgeDesc) +
           predecessor_.capacity() * sizeof(EdgeDesc) + color_.capacity() + distance_.capacity() * sizeof(long) +
           csr_of_arc_.capacity() * sizeof(int);
  }

 private:
  void Build() {
    const int E = static_cast<int>(pairs_.size());
    const int s = n_, t = n_ + 1;
    std::vector<std::pair<int, int>> arcs;
    std::vector<ArcId> ids;
    arcs.reserve(2 * E + 4 * static_cast<size_t>(n_));
    for (int e = 0; e < E; ++e) {
      arcs.emplace_back(pairs_[e].first, pairs_[e].second);
      arcs.emplace_back(pairs_[e].second, pairs_[e].first);
    }
    for (int v = 0; v < n_; ++v) {
      arcs.emplace_back(s, v);
      arcs.emplace_back(v, s);
      arcs.emplace_back(v, t);
      arcs.emplace_back(t, v);
    }
    num_arcs_ = arcs.size();
    ids.resize(num_arcs_);
    for (size_t k = 0; k < num_arcs_; ++k) ids[k].id = static_cast<int>(k);
    graph_ = Graph(boost::edges_are_unsorted_multi_pass, arcs.begin(), arcs.end(), ids.begin(), n_ + 2);
    std::vector<std::pair<int, int>>().swap(arcs);
    std::vector<ArcId>().swap(ids);
    csr_of_arc_.assign(num_arcs_, -1);
    std::vector<EdgeDesc> by_arc(num_arcs_);
    const auto edge_index = get(boost::edge_index, graph_);
    for (auto [it, end] = boost::edges(graph_); it != end; ++it) {
      const int id = graph_[*it].id;
      csr_of_arc_[id] = static_cast<int>(get(edge_index, *it));
      by_arc[id] = *it;
    }
    reverse_.resize(num_arcs_);
    for (size_t k = 0; k < num_arcs_; ++k) reverse_[csr_of_arc_[k]] = by_arc[k ^ 1];
    capacity_.assign(num_arcs_, 0.0);
    residual_.assign(num_arcs_, 0.0);
    for (int e = 0; e < E; ++e) {
      capacity_[csr_of_arc_[2 * e]] = init_caps_[2 * e];
      capacity_[csr_of_arc_[2 * e + 1]] = init_caps_[2 * e + 1];
    }
    std::vector<double>().swap(init_caps_);
    predecessor_.resize(n_ + 2);
    color_.resize(n_ + 2);
    distance_.resize(n_ + 2);
    built_ = true;
  }

  int n_ = 0;
  bool built_ = false;
  std::vector<std::pair<int, int>> pairs_;
  std::vector<double> init_caps_;
  std::vector<double> terminal_;
  double constant_flow_ = 0;
  Graph graph_;
  size_t num_arcs_ = 0;
  std::vector<int> csr_of_arc_;  // Our arc id (2e, 2e+1, then 4 per node) -> CSR edge index.
  std::vector<double> capacity_, residual_;
  std::vector<EdgeDesc> reverse_, predecessor_;
  std::vector<boost::default_color_type> color_;
  std::vector<long> distance_;
};

}  // namespace semvox::bench
