// Max-flow / min-cut on a directed graph with source and sink terminals, by the augmenting-path
// algorithm of Boykov & Kolmogorov, "An Experimental Comparison of Min-Cut/Max-Flow Algorithms for
// Energy Minimization in Vision", PAMI 26(9), 2004 (Sec. 3: growth, augmentation, adoption).
//
// This is semvox's own implementation written from the paper's description (BSD-3-Clause like the rest
// of semvox); it is not derived from maxflow-v3 / gco / libmaxflow (GPL or research-only licences).
//
// Usage: the topology is fixed once, capacities can be reset and the flow recomputed many times
// (alpha-expansion solves one cut per label on the same graph):
//
//   MaxFlowGraph<double> g(num_nodes);
//   int e = g.AddEdge(i, j, /*cap_ij=*/2.0, /*cap_ji=*/0.5);   // edge ids 0, 1, 2, ...
//   g.AddTerminalCapacities(i, /*source_cap=*/3.0, /*sink_cap=*/1.0);
//   double flow = g.Solve();                    // the min-cut value
//   bool on_sink_side = g.InSinkSegment(i);
//   g.ResetCapacities();                         // all capacities 0, topology kept (or
//                                                // ResetTerminalCapacities() + set every edge)
//   g.SetEdgeCapacities(e, 1.0, 1.0); ...; g.Solve();
//
// Cut convention: a node on the sink side pays its source capacity, a node on the source side pays its
// sink capacity, and an edge i->j is cut (pays cap_ij) when i is on the source side and j on the sink
// side. Nodes that are connected to neither terminal's tree end on the source side.
//
// Internals: arcs are stored in CSR order per node (built on the first Solve()), so growth and adoption
// scan contiguous memory; a node keeps a parent arc, a tree flag, and the time stamp / distance of the
// "closest to terminal" adoption heuristic of the paper. Capacities must be finite and >= 0.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace semvox {

template <typename Capacity>
class MaxFlowGraph {
 public:
  explicit MaxFlowGraph(int num_nodes = 0);

  int num_nodes() const { return static_cast<int>(nodes_.size()); }
  int num_edges() const { return static_cast<int>(edge_arc_.size()); }

  // Adds nodes and returns the id of the first one.
  int AddNodes(int count);
  // Avoids reallocation while adding `count` edges.
  void ReserveEdges(size_t count);
  // Adds the pair of arcs i->j (capacity cap_ij) and j->i (cap_ji); returns the edge id. Adding edges
  // after the first Solve() rebuilds the arc arrays on the next Solve().
  int AddEdge(int i, int j, Capacity cap_ij, Capacity cap_ji);
  // Adds to the node's terminal capacities (they accumulate; only the difference matters for the cut,
  // the common part is counted as flow).
  void AddTerminalCapacities(int node, Capacity source_cap, Capacity sink_cap);

  // Sets every capacity to zero and forgets the flow; the topology and edge ids are kept.
  void ResetCapacities();
  // Sets the terminal capacities to zero and forgets the flow, leaving the arcs alone: for callers that
  // then set every edge with SetEdgeCapacities().
  void ResetTerminalCapacities();
  // Forgets the flow only. For callers that then set every node (SetTerminalCapacity/-ies) and every edge
  // with SetEdgeCapacities(); alpha-expansion does (one pass less over the nodes). An edge whose two arcs
  // were zero before Solve() carried no flow and is still zero after it, so it need not be set again.
  void ResetFlow() {
    flow_ = 0;
    solved_ = false;
  }
  // Replaces the node's terminal capacities by source_minus_sink on one side (source when > 0, sink when
  // < 0), no flow: SetTerminalCapacities(node, max(d, 0), max(-d, 0)) without the bookkeeping.
  void SetTerminalCapacity(int node, Capacity source_minus_sink) {
    if (!(source_minus_sink == source_minus_sink)) NegativeCapacity();  // NaN.
    nodes_[node].terminal_cap = source_minus_sink;
  }
  // Replaces the node's terminal capacities (Add... accumulates); the common part counts as flow.
  void SetTerminalCapacities(int node, Capacity source_cap, Capacity sink_cap) {
    if (!(source_cap >= 0 && sink_cap >= 0)) NegativeCapacity();
    flow_ += source_cap < sink_cap ? source_cap : sink_cap;
    nodes_[node].terminal_cap = source_cap - sink_cap;
  }
  // Overwrites the two arc capacities of edge `edge` (valid after ResetCapacities() or before Solve()).
  // Makes SetEdgeCapacities safe to call from several threads at once on distinct edges (until edges are
  // added again): the per-edge capacity arrays it writes before the first Solve() exist.
  void PrepareConcurrentEdgeUpdates();
  void SetEdgeCapacities(int edge, Capacity cap_ij, Capacity cap_ji) {
    if (!(cap_ij >= 0 && cap_ji >= 0)) NegativeCapacity();
    if (!arcs_valid_) return SetEdgeCapacitiesBeforeBuild(edge, cap_ij, cap_ji);
    const EdgeArcs ea = edge_arc_[edge];
    arcs_[ea.forward].residual = cap_ij;
    arcs_[ea.reverse].residual = cap_ji;
  }

  // Computes the maximum flow from source to sink (= the minimum cut value, including the terminal
  // capacity common to both sides) and the cut. Afterwards the residual capacities are left in place;
  // call ResetCapacities() before reusing the graph.
  Capacity Solve();

  // After Solve(): true when the node is on the sink side of the minimum cut.
  bool InSinkSegment(int node) const {
    const Node& n = nodes_[node];
    return n.parent != kNone && n.in_sink_tree;
  }

  // Statistics of the last Solve().
  int64_t num_augmentations() const { return num_augmentations_; }
  // Bytes held by the graph arrays.
  size_t MemoryBytes() const;

 private:
  static constexpr int kNone = -1;      // Parent of a free node (in no tree).
  static constexpr int kTerminal = -2;  // Parent of a node attached directly to its terminal.
  static constexpr int kOrphan = -3;    // Parent of a node whose parent arc was saturated.

  struct Node {
    Capacity terminal_cap = 0;  // > 0: residual from the source; < 0: residual to the sink.
    int parent = kNone;         // Arc from this node to its parent, or kNone / kTerminal / kOrphan.
    int next_active = kNone;    // Intrusive FIFO of active nodes; == own id for the last / current node.
    int timestamp = 0;          // Time at which `distance` was known to be exact.
    int distance = 0;           // Distance to the terminal along parents.
    bool in_sink_tree = false;  // Tree membership when parent != kNone.
  };
  struct Arc {
    int head;           // Node the arc points to.
    int sister;         // The reverse arc.
    Capacity residual;  // Residual capacity.
  };

  [[noreturn]] static void NegativeCapacity();
  void SetEdgeCapacitiesBeforeBuild(int edge, Capacity cap_ij, Capacity cap_ji);
  void BuildArcs();
  void UnbuildArcs();
  void Activate(int node);
  int NextActive();
  // Pushes the bottleneck along source ~> s_node -> (arc) -> t_node ~> sink.
  void Augment(int arc, int s_node, int t_node);
  void ProcessOrphan(int node, bool sink_tree);

  std::vector<Node> nodes_;
  std::vector<int> first_arc_;  // CSR offsets, num_nodes + 1.
  std::vector<Arc> arcs_;
  // Edges as added: arcs are built from these.
  std::vector<int> edge_tail_, edge_head_;
  std::vector<Capacity> edge_cap_, edge_rev_cap_;
  struct EdgeArcs {
    int forward, reverse;
  };
  std::vector<EdgeArcs> edge_arc_;  // Edge id -> its two arcs (after BuildArcs; no dependent load).
  bool arcs_valid_ = false;
  bool solved_ = false;

  int queue_first_ = kNone, queue_last_ = kNone;
  std::vector<int> orphans_;
  int time_ = 0;
  int64_t num_augmentations_ = 0;
  Capacity flow_ = 0;
};

extern template class MaxFlowGraph<double>;
extern template class MaxFlowGraph<float>;
extern template class MaxFlowGraph<int64_t>;

}  // namespace semvox
