#include "crf/max_flow.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <queue>
#include <random>
#include <vector>

namespace semvox {
namespace {

struct TestEdge {
  int i, j;
  double cap_ij, cap_ji;
};
struct TestGraph {
  int n = 0;
  std::vector<double> source, sink;
  std::vector<TestEdge> edges;
};

TestGraph RandomGraph(int n, double density, bool integer, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto cap = [&]() { return integer ? static_cast<double>(rng() % 10) : unit(rng) * 10; };
  TestGraph g;
  g.n = n;
  for (int v = 0; v < n; ++v) {
    g.source.push_back(unit(rng) < 0.5 ? cap() : 0);
    g.sink.push_back(unit(rng) < 0.5 ? cap() : 0);
  }
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (unit(rng) < density) {
        if (rng() % 2) {
          g.edges.push_back({i, j, cap(), unit(rng) < 0.5 ? 0.0 : cap()});
        } else {
          g.edges.push_back({j, i, cap(), unit(rng) < 0.5 ? 0.0 : cap()});
        }
      }
    }
  }
  return g;
}

// Cut cost of a partition (sink_side[v] = true: v with the sink).
double CutCost(const TestGraph& g, const std::vector<bool>& sink_side) {
  double cost = 0;
  for (int v = 0; v < g.n; ++v) cost += sink_side[v] ? g.source[v] : g.sink[v];
  for (const TestEdge& e : g.edges) {
    if (!sink_side[e.i] && sink_side[e.j]) cost += e.cap_ij;
    if (!sink_side[e.j] && sink_side[e.i]) cost += e.cap_ji;
  }
  return cost;
}

double BruteForceMinCut(const TestGraph& g) {
  double best = std::numeric_limits<double>::infinity();
  std::vector<bool> side(g.n);
  for (uint32_t mask = 0; mask < (1u << g.n); ++mask) {
    for (int v = 0; v < g.n; ++v) side[v] = (mask >> v) & 1;
    best = std::min(best, CutCost(g, side));
  }
  return best;
}

// Edmonds-Karp on a dense matrix: an independent reference for graphs too big to enumerate.
double EdmondsKarp(const TestGraph& g) {
  const int n = g.n + 2, s = g.n, t = g.n + 1;
  std::vector<std::vector<double>> r(n, std::vector<double>(n, 0.0));
  for (int v = 0; v < g.n; ++v) {
    r[s][v] += g.source[v];
    r[v][t] += g.sink[v];
  }
  for (const TestEdge& e : g.edges) {
    r[e.i][e.j] += e.cap_ij;
    r[e.j][e.i] += e.cap_ji;
  }
  double flow = 0;
  for (;;) {
    std::vector<int> parent(n, -1);
    parent[s] = s;
    std::queue<int> q;
    q.push(s);
    while (!q.empty() && parent[t] < 0) {
      const int u = q.front();
      q.pop();
      for (int v = 0; v < n; ++v) {
        if (parent[v] < 0 && r[u][v] > 1e-12) {
          parent[v] = u;
          q.push(v);
        }
      }
    }
    if (parent[t] < 0) return flow;
    double f = std::numeric_limits<double>::infinity();
    for (int v = t; v != s; v = parent[v]) f = std::min(f, r[parent[v]][v]);
    for (int v = t; v != s; v = parent[v]) {
      r[parent[v]][v] -= f;
      r[v][parent[v]] += f;
    }
    flow += f;
  }
}

template <typename Capacity>
Capacity SolveWith(const TestGraph& tg, MaxFlowGraph<Capacity>* g, std::vector<bool>* sink_side) {
  for (const TestEdge& e : tg.edges) g->AddEdge(e.i, e.j, static_cast<Capacity>(e.cap_ij), static_cast<Capacity>(e.cap_ji));
  for (int v = 0; v < tg.n; ++v) {
    g->AddTerminalCapacities(v, static_cast<Capacity>(tg.source[v]), static_cast<Capacity>(tg.sink[v]));
  }
  const Capacity flow = g->Solve();
  sink_side->resize(tg.n);
  for (int v = 0; v < tg.n; ++v) (*sink_side)[v] = g->InSinkSegment(v);
  return flow;
}

// The flow of `tg` equals Edmonds-Karp's and the reported cut costs that much.
void ExpectMaximumFlowAndMinimalCut(const TestGraph& tg, uint64_t seed) {
  MaxFlowGraph<double> g(tg.n);
  std::vector<bool> side;
  const double flow = SolveWith(tg, &g, &side);
  const double expected = EdmondsKarp(tg);
  EXPECT_NEAR(flow, expected, 1e-9 * (1 + expected)) << "seed " << seed;
  EXPECT_NEAR(CutCost(tg, side), expected, 1e-9 * (1 + expected)) << "seed " << seed;
}

TEST(MaxFlowGraph, EqualsBruteForceMinCutOnSmallRandomGraphs) {
  int tested = 0;
  for (uint64_t seed = 0; seed < 600; ++seed) {
    const int n = 1 + static_cast<int>(seed % 12);
    const double density = 0.15 + 0.1 * static_cast<double>(seed % 7);
    const TestGraph tg = RandomGraph(n, density, /*integer=*/seed % 2 == 0, seed);
    const double expected = BruteForceMinCut(tg);
    MaxFlowGraph<double> g(n);
    std::vector<bool> side;
    const double flow = SolveWith(tg, &g, &side);
    ASSERT_NEAR(flow, expected, 1e-9 * (1 + expected)) << "seed " << seed;
    // The returned partition is a minimum cut.
    ASSERT_NEAR(CutCost(tg, side), expected, 1e-9 * (1 + expected)) << "seed " << seed;
    ++tested;
  }
  EXPECT_EQ(tested, 600);
}

TEST(MaxFlowGraph, IntegerAndFloatCapacitiesAgree) {
  for (uint64_t seed = 0; seed < 200; ++seed) {
    const TestGraph tg = RandomGraph(10, 0.4, /*integer=*/true, 1000 + seed);
    const double expected = BruteForceMinCut(tg);
    MaxFlowGraph<int64_t> gi(tg.n);
    MaxFlowGraph<float> gf(tg.n);
    std::vector<bool> side_i, side_f;
    EXPECT_EQ(SolveWith(tg, &gi, &side_i), static_cast<int64_t>(expected)) << "seed " << seed;
    EXPECT_FLOAT_EQ(SolveWith(tg, &gf, &side_f), static_cast<float>(expected)) << "seed " << seed;
    EXPECT_EQ(CutCost(tg, side_i), expected);
  }
}

TEST(MaxFlowGraph, EqualsEdmondsKarpOnLargerGraphs) {
  for (uint64_t seed = 0; seed < 40; ++seed) {
    ExpectMaximumFlowAndMinimalCut(RandomGraph(60, 0.08, seed % 2 == 0, 5000 + seed), seed);
  }
}

// Hub nodes with arcs to many others (the auxiliary nodes of large Robust P^n cliques in alpha-expansion), on
// a grid: adoption may stop scanning a hub's arcs at a parent attached to the terminal; the flow is still
// Edmonds-Karp's and the cut minimal.
TEST(MaxFlowGraph, HubNodesGiveTheMaximumFlowAndAMinimalCut) {
  for (uint64_t seed = 0; seed < 20; ++seed) {
    const int w = 14, h = 12, hubs = 4;
    std::mt19937_64 rng(900 + seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    TestGraph tg;
    tg.n = w * h + hubs;
    for (int v = 0; v < tg.n; ++v) {
      const double d = unit(rng) - 0.5;
      tg.source.push_back(d > 0 ? d : 0);
      tg.sink.push_back(d < 0 ? -d : 0);
    }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int v = y * w + x;
        if (x + 1 < w) tg.edges.push_back({v, v + 1, 0.3 * unit(rng), 0.3 * unit(rng)});
        if (y + 1 < h) tg.edges.push_back({v, v + w, 0.3 * unit(rng), 0.3 * unit(rng)});
      }
    for (int k = 0; k < hubs; ++k) {
      const int hub = w * h + k;
      for (int v = 0; v < w * h; ++v)
        if (unit(rng) < 0.6) {
          // Members -> hub (like member -> z) or hub -> members (like y -> member), one direction per hub.
          if (k % 2 == 0)
            tg.edges.push_back({v, hub, 0.2 * unit(rng), 0.0});
          else
            tg.edges.push_back({hub, v, 0.2 * unit(rng), 0.0});
        }
    }
    ExpectMaximumFlowAndMinimalCut(tg, seed);
  }
}

TEST(MaxFlowGraph, GridCutIsMinimalAgainstEdmondsKarp) {
  // A 12 x 12 4-connected grid with random terminals: the shape alpha-expansion produces.
  const int w = 12, h = 12;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  TestGraph tg;
  tg.n = w * h;
  for (int v = 0; v < tg.n; ++v) {
    const double d = unit(rng) - 0.5;
    tg.source.push_back(d > 0 ? d : 0);
    tg.sink.push_back(d < 0 ? -d : 0);
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int v = y * w + x;
      if (x + 1 < w) tg.edges.push_back({v, v + 1, 0.3 * unit(rng), 0.3 * unit(rng)});
      if (y + 1 < h) tg.edges.push_back({v, v + w, 0.3 * unit(rng), 0.3 * unit(rng)});
    }
  }
  MaxFlowGraph<double> g(tg.n);
  std::vector<bool> side;
  const double flow = SolveWith(tg, &g, &side);
  EXPECT_NEAR(flow, EdmondsKarp(tg), 1e-9);
  EXPECT_NEAR(CutCost(tg, side), flow, 1e-9);
}

TEST(MaxFlowGraph, ResetCapacitiesAllowsReuseWithTheSameTopology) {
  const TestGraph a = RandomGraph(10, 0.5, false, 11);
  TestGraph b = a;
  std::mt19937_64 rng(12);
  for (TestEdge& e : b.edges) {
    e.cap_ij = static_cast<double>(rng() % 7);
    e.cap_ji = static_cast<double>(rng() % 3);
  }
  for (int v = 0; v < b.n; ++v) {
    b.source[v] = static_cast<double>(rng() % 5);
    b.sink[v] = static_cast<double>(rng() % 5);
  }
  MaxFlowGraph<double> g(a.n);
  std::vector<bool> side;
  EXPECT_NEAR(SolveWith(a, &g, &side), BruteForceMinCut(a), 1e-9);
  for (int round = 0; round < 2; ++round) {
    // Via ResetCapacities, then via ResetTerminalCapacities + every edge.
    if (round == 0) {
      g.ResetCapacities();
    } else {
      g.ResetTerminalCapacities();
    }
    for (size_t e = 0; e < b.edges.size(); ++e) g.SetEdgeCapacities(static_cast<int>(e), b.edges[e].cap_ij, b.edges[e].cap_ji);
    for (int v = 0; v < b.n; ++v) g.AddTerminalCapacities(v, b.source[v], b.sink[v]);
    const double flow = g.Solve();
    EXPECT_NEAR(flow, BruteForceMinCut(b), 1e-9);
    for (int v = 0; v < b.n; ++v) side[v] = g.InSinkSegment(v);
    EXPECT_NEAR(CutCost(b, side), flow, 1e-9);
  }
}

TEST(MaxFlowGraph, AddingEdgesAndNodesAfterSolveKeepsEarlierEdges) {
  TestGraph tg = RandomGraph(8, 0.4, true, 21);
  MaxFlowGraph<double> g(tg.n);
  std::vector<bool> side;
  SolveWith(tg, &g, &side);
  // Rebuild from scratch on the same object: zero everything, grow the graph, set all capacities again.
  g.ResetCapacities();
  const int extra = g.AddNodes(2);
  EXPECT_EQ(extra, tg.n);
  tg.n += 2;
  tg.source.push_back(4);
  tg.sink.push_back(0);
  tg.source.push_back(0);
  tg.sink.push_back(6);
  tg.edges.push_back({extra, 0, 3, 1});
  tg.edges.push_back({1, extra + 1, 2, 0});
  g.AddEdge(extra, 0, 0, 0);
  g.AddEdge(1, extra + 1, 0, 0);
  for (size_t e = 0; e < tg.edges.size(); ++e) g.SetEdgeCapacities(static_cast<int>(e), tg.edges[e].cap_ij, tg.edges[e].cap_ji);
  for (int v = 0; v < tg.n; ++v) g.AddTerminalCapacities(v, tg.source[v], tg.sink[v]);
  EXPECT_NEAR(g.Solve(), BruteForceMinCut(tg), 1e-9);
}

TEST(MaxFlowGraph, HandWorkedExample) {
  // s -> 0 (3), 0 -> t (1), 0 -> 1 (5), 1 -> t (4): 1 unit goes 0 -> t, 2 go 0 -> 1 -> t; the only
  // minimum cut is {s} | {0, 1, t} (value 3), so both nodes end on the sink side.
  MaxFlowGraph<int64_t> g(2);
  g.AddEdge(0, 1, 5, 0);
  g.AddTerminalCapacities(0, 3, 1);
  g.AddTerminalCapacities(1, 0, 4);
  EXPECT_EQ(g.Solve(), 3);
  EXPECT_TRUE(g.InSinkSegment(0));
  EXPECT_TRUE(g.InSinkSegment(1));
}

TEST(MaxFlowGraph, EmptyGraphHasZeroFlow) {
  MaxFlowGraph<double> g(0);
  EXPECT_EQ(g.Solve(), 0.0);
  MaxFlowGraph<double> h(3);
  h.AddTerminalCapacities(1, 2.5, 1.0);
  EXPECT_DOUBLE_EQ(h.Solve(), 1.0);
  EXPECT_FALSE(h.InSinkSegment(1));
}

}  // namespace
}  // namespace semvox
