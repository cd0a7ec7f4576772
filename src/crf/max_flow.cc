#include "crf/max_flow.h"

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstdlib>

namespace semvox {
namespace {

[[noreturn]] void MaxFlowInvariantFailed(const char* what) {
  std::fprintf(stderr, "semvox: MaxFlowGraph invariant violated: %s\n", what);
  std::abort();
}

#define MAXFLOW_CHECK(cond) \
  do {                      \
    if (!(cond)) MaxFlowInvariantFailed(#cond); \
  } while (0)

}  // namespace

template <typename Capacity>
void MaxFlowGraph<Capacity>::NegativeCapacity() {
  MaxFlowInvariantFailed("capacities must be >= 0 (and not NaN)");
}

template <typename Capacity>
MaxFlowGraph<Capacity>::MaxFlowGraph(int num_nodes) {
  MAXFLOW_CHECK(num_nodes >= 0);
  nodes_.resize(num_nodes);
}

template <typename Capacity>
void MaxFlowGraph<Capacity>::UnbuildArcs() {
  // Topology changes after the arcs were built: go back to the edge list (residuals become capacities).
  const int m = static_cast<int>(edge_arc_.size());
  edge_tail_.resize(m);
  edge_head_.resize(m);
  edge_cap_.resize(m);
  edge_rev_cap_.resize(m);
  for (int e = 0; e < m; ++e) {
    const Arc& fwd = arcs_[edge_arc_[e].forward];
    const Arc& rev = arcs_[fwd.sister];
    edge_tail_[e] = rev.head;
    edge_head_[e] = fwd.head;
    edge_cap_[e] = fwd.residual;
    edge_rev_cap_[e] = rev.residual;
  }
  std::vector<Arc>().swap(arcs_);
  arcs_valid_ = false;
}

template <typename Capacity>
int MaxFlowGraph<Capacity>::AddNodes(int count) {
  MAXFLOW_CHECK(count >= 0);
  if (arcs_valid_ && count > 0) UnbuildArcs();
  const int first = num_nodes();
  nodes_.resize(nodes_.size() + count);
  return first;
}

template <typename Capacity>
int MaxFlowGraph<Capacity>::AddEdge(int i, int j, Capacity cap_ij, Capacity cap_ji) {
  MAXFLOW_CHECK(i >= 0 && i < num_nodes() && j >= 0 && j < num_nodes());
  MAXFLOW_CHECK(i != j);
  MAXFLOW_CHECK(cap_ij >= 0 && cap_ji >= 0);
  if (arcs_valid_) UnbuildArcs();
  const size_t e = edge_arc_.size();
  edge_tail_.push_back(i);
  edge_head_.push_back(j);
  if (!edge_cap_.empty() || cap_ij != 0 || cap_ji != 0) {
    // Capacities are stored only once one is non-zero (callers that set them later save the memory).
    edge_cap_.resize(e, Capacity(0));
    edge_rev_cap_.resize(e, Capacity(0));
    edge_cap_.push_back(cap_ij);
    edge_rev_cap_.push_back(cap_ji);
  }
  edge_arc_.push_back(EdgeArcs{-1, -1});
  return static_cast<int>(edge_arc_.size()) - 1;
}

template <typename Capacity>
void MaxFlowGraph<Capacity>::AddTerminalCapacities(int node, Capacity source_cap, Capacity sink_cap) {
  MAXFLOW_CHECK(node >= 0 && node < num_nodes());
  MAXFLOW_CHECK(source_cap >= 0 && sink_cap >= 0);
  // Flow through source -> node -> sink is pushed at once; only the excess stays as a terminal arc.
  flow_ += std::min(source_cap, sink_cap);
  const Capacity delta = source_cap - sink_cap;
  Capacity& tc = nodes_[node].terminal_cap;
  if ((tc > 0 && delta < 0) || (tc < 0 && delta > 0)) {
    flow_ += std::min(tc < 0 ? -tc : tc, delta < 0 ? -delta : delta);
  }
  tc += delta;
}

template <typename Capacity>
void MaxFlowGraph<Capacity>::ResetCapacities() {
  for (Node& n : nodes_) n.terminal_cap = 0;
  if (arcs_valid_) {
    for (Arc& a : arcs_) a.residual = 0;
  } else {
    std::fill(edge_cap_.begin(), edge_cap_.end(), Capacity(0));
    std::fill(edge_rev_cap_.begin(), edge_rev_cap_.end(), Capacity(0));
  }
  flow_ = 0;
  solved_ = false;
}

template <typename Capacity>
void MaxFlowGraph<Capacity>::ResetTerminalCapacities() {
  for (Node& n : nodes_) n.terminal_cap = 0;
  flow_ = 0;
  solved_ = false;
}

template <typename Capacity>
void MaxFlowGraph<Capacity>::PrepareConcurrentEdgeUpdates() {
  if (edge_cap_.size() < edge_arc_.size()) {
    edge_cap_.resize(edge_arc_.size(), Capacity(0));
    edge_rev_cap_.resize(edge_arc_.size(), Capacity(0));
  }
}

template <typename Capacity>
void MaxFlowGraph<Capacity>::SetEdgeCapacitiesBeforeBuild(int edge, Capacity cap_ij, Capacity cap_ji) {
  MAXFLOW_CHECK(edge >= 0 && edge < num_edges());
  if (edge_cap_.size() < edge_arc_.size()) {
    edge_cap_.resize(edge_arc_.size(), Capacity(0));
    edge_rev_cap_.resize(edge_arc_.size(), Capacity(0));
  }
  edge_cap_[edge] = cap_ij;
  edge_rev_cap_[edge] = cap_ji;
}

template <typename Capacity>
void MaxFlowGraph<Capacity>::ReserveEdges(size_t count) {
  edge_tail_.reserve(count);
  edge_head_.reserve(count);
  edge_arc_.reserve(count);
}

template <typename Capacity>
void MaxFlowGraph<Capacity>::BuildArcs() {
  const int n = num_nodes();
  const int m = static_cast<int>(edge_tail_.size());
  first_arc_.assign(n + 1, 0);
  for (int e = 0; e < m; ++e) {
    ++first_arc_[edge_tail_[e] + 1];
    ++first_arc_[edge_head_[e] + 1];
  }
  for (int v = 0; v < n; ++v) first_arc_[v + 1] += first_arc_[v];
  std::vector<int> fill(first_arc_.begin(), first_arc_.end() - 1);
  arcs_.resize(2 * static_cast<size_t>(m));
  for (int e = 0; e < m; ++e) {
    const int i = edge_tail_[e], j = edge_head_[e];
    const int fa = fill[i]++, ra = fill[j]++;
    const bool stored = static_cast<size_t>(e) < edge_cap_.size();
    arcs_[fa] = Arc{j, ra, stored ? edge_cap_[e] : Capacity(0)};
    arcs_[ra] = Arc{i, fa, stored ? edge_rev_cap_[e] : Capacity(0)};
    edge_arc_[e] = EdgeArcs{fa, ra};
  }
  // The edge list is now held by the arcs; free it.
  std::vector<int>().swap(edge_tail_);
  std::vector<int>().swap(edge_head_);
  std::vector<Capacity>().swap(edge_cap_);
  std::vector<Capacity>().swap(edge_rev_cap_);
  arcs_valid_ = true;
}

template <typename Capacity>
size_t MaxFlowGraph<Capacity>::MemoryBytes() const {
  return nodes_.capacity() * sizeof(Node) + first_arc_.capacity() * sizeof(int) +
         arcs_.capacity() * sizeof(Arc) + edge_arc_.capacity() * sizeof(EdgeArcs) +
         (edge_tail_.capacity() + edge_head_.capacity()) * sizeof(int) +
         (edge_cap_.capacity() + edge_rev_cap_.capacity()) * sizeof(Capacity) +
         orphans_.capacity() * sizeof(int);
}

template <typename Capacity>
inline void MaxFlowGraph<Capacity>::Activate(int node) {
  Node& n = nodes_[node];
  if (n.next_active != kNone) return;  // Already queued (or the node being processed).
  if (queue_last_ != kNone) {
    nodes_[queue_last_].next_active = node;
  } else {
    queue_first_ = node;
  }
  queue_last_ = node;
  n.next_active = node;  // Last in the queue points to itself.
}

template <typename Capacity>
inline int MaxFlowGraph<Capacity>::NextActive() {
  while (queue_first_ != kNone) {
    const int node = queue_first_;
    Node& n = nodes_[node];
    if (n.next_active == node) {
      queue_first_ = queue_last_ = kNone;
    } else {
      queue_first_ = n.next_active;
    }
    n.next_active = kNone;
    if (n.parent != kNone) return node;  // Nodes that became free meanwhile are skipped.
  }
  return kNone;
}

template <typename Capacity>
void MaxFlowGraph<Capacity>::Augment(int mid, int s_node, int t_node) {
  // Bottleneck along source -> s_node -> (mid) -> t_node -> sink.
  Capacity f = arcs_[mid].residual;
  int x = s_node;
  while (nodes_[x].parent != kTerminal) {
    const int a = nodes_[x].parent;  // x -> parent; flow runs parent -> x on the sister arc.
    f = std::min(f, arcs_[arcs_[a].sister].residual);
    x = arcs_[a].head;
  }
  f = std::min(f, nodes_[x].terminal_cap);
  x = t_node;
  while (nodes_[x].parent != kTerminal) {
    const int a = nodes_[x].parent;  // Flow runs x -> parent on this arc.
    f = std::min(f, arcs_[a].residual);
    x = arcs_[a].head;
  }
  f = std::min(f, -nodes_[x].terminal_cap);

  // Push f; saturated tree arcs turn their child into an orphan.
  arcs_[mid].residual -= f;
  arcs_[arcs_[mid].sister].residual += f;
  x = s_node;
  while (nodes_[x].parent != kTerminal) {
    const int a = nodes_[x].parent;
    Arc& down = arcs_[arcs_[a].sister];
    arcs_[a].residual += f;
    down.residual -= f;
    const int parent = arcs_[a].head;
    if (down.residual == 0) {
      nodes_[x].parent = kOrphan;
      orphans_.push_back(x);
    }
    x = parent;
  }
  nodes_[x].terminal_cap -= f;
  if (nodes_[x].terminal_cap == 0) {
    nodes_[x].parent = kOrphan;
    orphans_.push_back(x);
  }
  x = t_node;
  while (nodes_[x].parent != kTerminal) {
    const int a = nodes_[x].parent;
    arcs_[arcs_[a].sister].residual += f;
    arcs_[a].residual -= f;
    const int parent = arcs_[a].head;
    if (arcs_[a].residual == 0) {
      nodes_[x].parent = kOrphan;
      orphans_.push_back(x);
    }
    x = parent;
  }
  nodes_[x].terminal_cap += f;
  if (nodes_[x].terminal_cap == 0) {
    nodes_[x].parent = kOrphan;
    orphans_.push_back(x);
  }
  flow_ += f;
  ++num_augmentations_;
}

template <typename Capacity>
void MaxFlowGraph<Capacity>::ProcessOrphan(int p, bool sink_tree) {
  constexpr int kInfiniteDistance = INT_MAX;
  int best_arc = kNone;
  int best_distance = kInfiniteDistance;
  const int begin = first_arc_[p], end = first_arc_[p + 1];
  // 1. Find a new parent q in the same tree with residual capacity on the tree direction whose path to
  //    the terminal does not pass through an orphan; prefer the one closest to the terminal.
  for (int a = begin; a < end; ++a) {
    const Arc& arc = arcs_[a];
    const Capacity residual = sink_tree ? arc.residual : arcs_[arc.sister].residual;
    if (!(residual > 0)) continue;
    const int q = arc.head;
    const Node& qn = nodes_[q];
    if (qn.parent == kNone || qn.in_sink_tree != sink_tree) continue;
    // Walk towards the terminal until a node with a fresh distance, the terminal or an orphan.
    int d = 0;
    int j = q;
    for (;;) {
      Node& jn = nodes_[j];
      if (jn.timestamp == time_) {
        d += jn.distance;
        break;
      }
      ++d;
      if (jn.parent == kTerminal) {
        jn.timestamp = time_;
        jn.distance = 1;
        break;
      }
      if (jn.parent == kOrphan) {
        d = kInfiniteDistance;
        break;
      }
      j = arcs_[jn.parent].head;
    }
    if (d == kInfiniteDistance) continue;
    if (d < best_distance) {
      best_distance = d;
      best_arc = a;
    }
    // Cache the distances found along the walk.
    for (j = q; nodes_[j].timestamp != time_; j = arcs_[nodes_[j].parent].head) {
      nodes_[j].timestamp = time_;
      nodes_[j].distance = d--;
    }
    // A parent attached to the terminal is as close as any: stop scanning (the auxiliary node of a large
    // Robust P^n clique has an arc to every member).
    if (best_distance == 1) break;
  }
  Node& pn = nodes_[p];
  if (best_arc != kNone) {
    pn.parent = best_arc;
    pn.timestamp = time_;
    pn.distance = best_distance + 1;
    return;
  }
  // 2. No parent: p becomes free. Neighbours in the tree that could reach p become active again, and
  //    p's children become orphans.
  for (int a = begin; a < end; ++a) {
    const Arc& arc = arcs_[a];
    const int q = arc.head;
    Node& qn = nodes_[q];
    if (qn.parent == kNone || qn.in_sink_tree != sink_tree) continue;
    const Capacity residual = sink_tree ? arc.residual : arcs_[arc.sister].residual;
    if (residual > 0) Activate(q);
    if (qn.parent >= 0 && arcs_[qn.parent].head == p) {
      qn.parent = kOrphan;
      orphans_.push_back(q);
    }
  }
  pn.parent = kNone;
}

template <typename Capacity>
Capacity MaxFlowGraph<Capacity>::Solve() {
  MAXFLOW_CHECK(!solved_);  // Call ResetCapacities() between two solves.
  if (!arcs_valid_) BuildArcs();
  solved_ = true;
  num_augmentations_ = 0;
  queue_first_ = queue_last_ = kNone;
  orphans_.clear();
  time_ = 0;
  const int n = num_nodes();
  for (int v = 0; v < n; ++v) {
    Node& node = nodes_[v];
    node.next_active = kNone;
    node.timestamp = 0;
    if (node.terminal_cap != 0) {
      node.in_sink_tree = node.terminal_cap < 0;
      node.parent = kTerminal;
      node.distance = 1;
      Activate(v);
    } else {
      node.parent = kNone;
      node.in_sink_tree = false;
    }
  }

  int current = kNone;
  for (;;) {
    int p = current;
    if (p != kNone) {
      nodes_[p].next_active = kNone;
      if (nodes_[p].parent == kNone) p = kNone;
    }
    if (p == kNone) {
      p = NextActive();
      if (p == kNone) break;
    }
    // Growth: extend p's tree over arcs with residual capacity in the tree direction; stop at the first
    // arc into the other tree (a source-to-sink path).
    Node& pn = nodes_[p];
    int path_arc = kNone;  // Arc from the source tree to the sink tree ...
    int path_s = kNone, path_t = kNone;  // ... and its two ends.
    const int begin = first_arc_[p], end = first_arc_[p + 1];
    if (!pn.in_sink_tree) {
      for (int a = begin; a < end; ++a) {
        if (!(arcs_[a].residual > 0)) continue;
        const int q = arcs_[a].head;
        Node& qn = nodes_[q];
        if (qn.parent == kNone) {
          qn.in_sink_tree = false;
          qn.parent = arcs_[a].sister;
          qn.timestamp = pn.timestamp;
          qn.distance = pn.distance + 1;
          Activate(q);
        } else if (qn.in_sink_tree) {
          path_arc = a;
          path_s = p;
          path_t = q;
          break;
        } else if (qn.timestamp <= pn.timestamp && qn.distance > pn.distance) {
          // q is in the same tree but farther from the source: shorten its path through p.
          qn.parent = arcs_[a].sister;
          qn.timestamp = pn.timestamp;
          qn.distance = pn.distance + 1;
        }
      }
    } else {
      for (int a = begin; a < end; ++a) {
        const int sister = arcs_[a].sister;
        if (!(arcs_[sister].residual > 0)) continue;
        const int q = arcs_[a].head;
        Node& qn = nodes_[q];
        if (qn.parent == kNone) {
          qn.in_sink_tree = true;
          qn.parent = sister;
          qn.timestamp = pn.timestamp;
          qn.distance = pn.distance + 1;
          Activate(q);
        } else if (!qn.in_sink_tree) {
          path_arc = sister;
          path_s = q;
          path_t = p;
          break;
        } else if (qn.timestamp <= pn.timestamp && qn.distance > pn.distance) {
          qn.parent = sister;
          qn.timestamp = pn.timestamp;
          qn.distance = pn.distance + 1;
        }
      }
    }
    ++time_;
    if (path_arc == kNone) {
      current = kNone;
      continue;
    }
    // p may have more paths: keep it as the current node, marked active so that it is not queued twice.
    nodes_[p].next_active = p;
    current = p;
    Augment(path_arc, path_s, path_t);
    // Adoption: orphans may create new orphans; process them in order.
    for (size_t k = 0; k < orphans_.size(); ++k) {
      const int o = orphans_[k];
      ProcessOrphan(o, nodes_[o].in_sink_tree);
    }
    orphans_.clear();
  }
  return flow_;
}

template class MaxFlowGraph<double>;
template class MaxFlowGraph<float>;
template class MaxFlowGraph<int64_t>;

}  // namespace semvox
