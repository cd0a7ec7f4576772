// CRF solver benchmark (not a test): Potts grid CRFs with 21 labels and random-but-seeded unaries,
// minimised by
//   - semvox alpha-expansion with semvox's own Boykov-Kolmogorov max-flow (crf/max_flow.h), with and
//     ("semvox-noprune") without fixing the nodes whose move is decided before the cut,
//   - the same alpha-expansion driver (default options, so with the reduction) on Boost's
//     boykov_kolmogorov_max_flow (same moves, graph topology fixed once and capacities reset per move:
//     only the max-flow differs),
//   - the same driver on OpenCV's GCGraph (rebuilt per move: it has no capacity reset),
//   - ICM,
// reporting energy reached, seconds, sweeps and peak memory side by side. Every solver runs in its own
// forked child that builds the problem itself, so "peak MB" is getrusage(RUSAGE_SELF).ru_maxrss of a
// process holding exactly that problem and that solver. "wall s" is the solver's wall time (as the
// reference figures), "CPU s" its user + system CPU time, which shared, loaded machines distort less.
//
// Problems: grid2d = 640 x 480, 4-connected; grid3d = 100 x 100 x 100, 6-connected. Unaries U(i, l) are
// uniform in [0, 1) (std::mt19937_64 seeded with --seed); every edge has Potts weight --potts (0.05).
//
//   build-crf/bin/crf_bench [--problems grid2d,grid3d] [--solvers semvox,boost,opencv,icm] [--labels 21]
//     (also semvox-noprune, boost-noprune, opencv-noprune: the driver without the decided-node reduction,
//      i.e. plain alpha-expansion as in the reference figures)
//                           [--potts 0.05] [--seed 1] [--init argmin|zero] [--size3d 100]
//                           [--cliques B]   (Robust P^n cliques on B x B (x B) tiles, see MakeGridEnergy)
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc/detail/gcgraph.hpp>

#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/property_map/property_map.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench/boost_bk_graph.h"
#include "crf/alpha_expansion_impl.h"
#include "crf/energy.h"
#include "crf/solvers.h"

using namespace semvox;

namespace {

using semvox::bench::BoostBkGraph;

// OpenCV's GCGraph (BK max-flow, opencv2/imgproc/detail/gcgraph.hpp) behind the same interface. GCGraph
// cannot reset capacities, so every Solve() rebuilds it (create + addEdges + addTermWeights), as an
// OpenCV-based alpha-expansion does; edges with both capacities zero are left out.
class OpenCvGcGraph {
 public:
  int AddNodes(int count) {
    const int first = n_;
    n_ += count;
    terminal_.resize(n_, 0.0);
    return first;
  }
  int AddEdge(int i, int j, double cap_ij, double cap_ji) {
    pairs_.emplace_back(i, j);
    caps_.emplace_back(cap_ij, cap_ji);
    return static_cast<int>(pairs_.size()) - 1;
  }
  void ResetFlow() {}
  void SetTerminalCapacity(int v, double source_minus_sink) { terminal_[v] = source_minus_sink; }
  void SetEdgeCapacities(int e, double cap_ij, double cap_ji) { caps_[e] = {cap_ij, cap_ji}; }
  double Solve() {
    graph_ = cv::detail::GCGraph<double>();  // create() only reserves: start from an empty graph.
    graph_.create(n_, 2 * static_cast<unsigned>(pairs_.size()));
    for (int v = 0; v < n_; ++v) graph_.addVtx();
    for (size_t e = 0; e < pairs_.size(); ++e) {
      if (caps_[e].first > 0 || caps_[e].second > 0) {
        graph_.addEdges(pairs_[e].first, pairs_[e].second, caps_[e].first, caps_[e].second);
      }
    }
    for (int v = 0; v < n_; ++v) {
      const double d = terminal_[v];
      graph_.addTermWeights(v, d > 0 ? d : 0.0, d < 0 ? -d : 0.0);
    }
    return graph_.maxFlow();
  }
  bool InSinkSegment(int v) { return !graph_.inSourceSegment(v); }
  size_t MemoryBytes() const {
    return pairs_.capacity() * sizeof(pairs_[0]) + caps_.capacity() * sizeof(caps_[0]) +
           terminal_.capacity() * sizeof(double);  // GCGraph's own arrays are private.
  }

 private:
  int n_ = 0;
  std::vector<std::pair<int, int>> pairs_;
  std::vector<std::pair<double, double>> caps_;
  std::vector<double> terminal_;
  cv::detail::GCGraph<double> graph_;
};

struct Args {
  std::vector<std::string> problems{"grid2d", "grid3d"};
  std::vector<std::string> solvers{"semvox", "boost", "opencv", "icm"};
  int labels = 21;
  float potts = 0.05f;
  uint64_t seed = 1;
  std::string init = "argmin";
  int size3d = 100;
  int clique_block = 0;  // > 0: Robust P^n cliques over block x block (x block) tiles.
};

std::vector<std::string> Split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) out.push_back(item);
  return out;
}

CrfEnergy MakeGridEnergy(const std::string& problem, const Args& args) {
  const bool is3d = problem == "grid3d";
  const int nx = is3d ? args.size3d : 640, ny = is3d ? args.size3d : 480, nz = is3d ? args.size3d : 1;
  const int n = nx * ny * nz;
  CrfEnergy energy(n, args.labels);
  std::mt19937_64 rng(args.seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (float& u : energy.mutable_unaries()) u = unit(rng);
  energy.ReserveEdges(static_cast<size_t>(n) * (is3d ? 3 : 2));
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const int v = (z * ny + y) * nx + x;
        if (x + 1 < nx) energy.AddEdge(v, v + 1, args.potts);
        if (y + 1 < ny) energy.AddEdge(v, v + nx, args.potts);
        if (z + 1 < nz) energy.AddEdge(v, v + nx * ny, args.potts);
      }
  if (args.clique_block > 0) {
    // Robust P^n over tiles (as superpixels / plane segments would be): gamma_l = 0, gamma_max = the
    // Potts weight times the tile size, Q = 20% of the tile.
    const int b = args.clique_block;
    for (int z0 = 0; z0 < nz; z0 += (is3d ? b : 1))
      for (int y0 = 0; y0 < ny; y0 += b)
        for (int x0 = 0; x0 < nx; x0 += b) {
          std::vector<int> nodes;
          for (int z = z0; z < std::min(nz, z0 + (is3d ? b : 1)); ++z)
            for (int y = y0; y < std::min(ny, y0 + b); ++y)
              for (int x = x0; x < std::min(nx, x0 + b); ++x) nodes.push_back((z * ny + y) * nx + x);
          RobustPnParams params;
          params.gamma_max = args.potts * static_cast<float>(nodes.size());
          params.truncation_q = 0.2f * static_cast<float>(nodes.size());
          energy.AddRobustPnClique(std::move(nodes), params);
        }
  }
  return energy;
}

struct RunResult {
  double energy = 0, initial_energy = 0, seconds = 0, max_flow_seconds = 0, build_seconds = 0;
  double build_cpu_seconds = 0;  // CPU time of the problem construction (subtracted in the table).
  int sweeps = 0;
  long expansions = 0;
  long peak_kb = 0;
  double cpu_seconds = 0;  // User + system CPU time of the whole child (problem construction included).
  int ok = 0;
};

RunResult RunSolver(const std::string& problem, const std::string& solver, const Args& args) {
  RunResult r;
  const auto t0 = std::chrono::steady_clock::now();
  const CrfEnergy energy = MakeGridEnergy(problem, args);
  r.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    r.build_cpu_seconds = usage.ru_utime.tv_sec + 1e-6 * usage.ru_utime.tv_usec + usage.ru_stime.tv_sec +
                          1e-6 * usage.ru_stime.tv_usec;
  }
  const InitialLabelling init = args.init == "zero" ? InitialLabelling::kAllZero : InitialLabelling::kUnaryArgmin;
  std::vector<CrfLabel> labels;
  CrfSolverSummary summary;
  Status st;
  if (solver == "semvox" || solver == "semvox-noprune") {
    AlphaExpansionOptions options;
    options.initial_labelling = init;
    options.prune_decided_nodes = solver == "semvox";
    st = MinimizeWithAlphaExpansion(energy, options, &labels, &summary);
  } else if (solver == "boost" || solver == "boost-noprune") {
    AlphaExpansionOptions options;
    options.initial_labelling = init;
    options.prune_decided_nodes = solver == "boost";
    BoostBkGraph graph;
    st = crf_internal::RunAlphaExpansion(energy, options, graph, &labels, &summary);
  } else if (solver == "opencv" || solver == "opencv-noprune") {
    AlphaExpansionOptions options;
    options.initial_labelling = init;
    options.prune_decided_nodes = solver == "opencv";
    OpenCvGcGraph graph;
    st = crf_internal::RunAlphaExpansion(energy, options, graph, &labels, &summary);
  } else if (solver == "icm") {
    IcmOptions options;
    options.initial_labelling = init;
    st = MinimizeWithIcm(energy, options, &labels, &summary);
  } else if (solver == "none") {
    st = Status::Ok();  // Problem construction only: the memory floor.
    summary.final_energy = summary.initial_energy = energy.Evaluate(energy.UnaryArgmin());
  } else {
    std::fprintf(stderr, "unknown solver %s\n", solver.c_str());
    return r;
  }
  if (!st.ok()) {
    std::fprintf(stderr, "%s\n", st.message().c_str());
    return r;
  }
  r.energy = summary.final_energy;
  r.initial_energy = summary.initial_energy;
  r.seconds = summary.seconds;
  r.max_flow_seconds = summary.max_flow_seconds;
  r.sweeps = summary.num_sweeps;
  r.expansions = static_cast<long>(summary.num_expansions);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  r.peak_kb = usage.ru_maxrss;
  r.cpu_seconds = usage.ru_utime.tv_sec + 1e-6 * usage.ru_utime.tv_usec + usage.ru_stime.tv_sec +
                  1e-6 * usage.ru_stime.tv_usec;
  r.ok = 1;
  return r;
}

// Runs one solver in a forked child so that its peak memory is its own.
RunResult RunInChild(const std::string& problem, const std::string& solver, const Args& args) {
  int fd[2];
  if (pipe(fd) != 0) std::abort();
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    const RunResult r = RunSolver(problem, solver, args);
    if (write(fd[1], &r, sizeof(r)) != static_cast<ssize_t>(sizeof(r))) _exit(1);
    _exit(0);
  }
  close(fd[1]);
  RunResult r;
  if (read(fd[0], &r, sizeof(r)) != static_cast<ssize_t>(sizeof(r))) r.ok = 0;
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  Args args;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--problems") args.problems = Split(value);
    else if (key == "--solvers") args.solvers = Split(value);
    else if (key == "--labels") args.labels = std::atoi(value.c_str());
    else if (key == "--potts") args.potts = std::strtof(value.c_str(), nullptr);
    else if (key == "--seed") args.seed = std::strtoull(value.c_str(), nullptr, 10);
    else if (key == "--init") args.init = value;
    else if (key == "--size3d") args.size3d = std::atoi(value.c_str());
    else if (key == "--cliques") args.clique_block = std::atoi(value.c_str());
    else {
      std::fprintf(stderr, "unknown option %s\n", key.c_str());
      return 2;
    }
  }
  std::printf("crf_bench: %d labels, Potts weight %.3g, unaries U[0,1) seed %llu, start %s", args.labels,
              args.potts, static_cast<unsigned long long>(args.seed), args.init.c_str());
  if (args.clique_block > 0) std::printf(", Robust P^n cliques on tiles of side %d", args.clique_block);
  std::printf("\n");
  std::printf("%-8s %-25s %18s %18s %6s %5s %8s %9s %8s %8s\n", "problem", "solver", "initial E", "final E",
              "sweeps", "cuts", "wall s", "maxflow s", "CPU s", "peak MB");
  for (const std::string& problem : args.problems) {
    double reference = 0;
    bool have_reference = false;
    for (const std::string& solver : args.solvers) {
      const RunResult r = RunInChild(problem, solver, args);
      if (!r.ok) {
        std::printf("%-8s %-25s failed\n", problem.c_str(), solver.c_str());
        continue;
      }
      const char* name = solver == "semvox"  ? "alpha-exp semvox BK"
                         : solver == "semvox-noprune" ? "alpha-exp semvox, no prune"
                         : solver == "boost" ? "alpha-exp Boost BK"
                         : solver == "opencv" ? "alpha-exp OpenCV GCGraph"
                         : solver == "boost-noprune" ? "alpha-exp Boost, no prune"
                         : solver == "opencv-noprune" ? "alpha-exp OpenCV, no prune"
                         : solver == "icm"   ? "ICM"
                                             : "(problem only)";
      std::printf("%-8s %-25s %18.6f %18.6f %6d %5ld %8.3f %9.3f %8.3f %8.1f", problem.c_str(), name,
                  r.initial_energy, r.energy, r.sweeps, r.expansions, r.seconds, r.max_flow_seconds,
                  r.cpu_seconds - r.build_cpu_seconds, r.peak_kb / 1024.0);
      if (solver != "icm" && solver != "none") {
        if (!have_reference) {
          reference = r.energy;
          have_reference = true;
        } else {
          std::printf("   dE vs first: %.3g", r.energy - reference);
        }
      }
      std::printf("\n");
      std::fflush(stdout);
    }
  }
  return 0;
}
