// Voxel-CRF benchmark: accuracy of the model variants in the Voxel-CRF paper's form (Tables 1-3)
// and solver performance. Not a test.
//
//   voxelcrf_bench --accuracy [--seeds 100-104] [--models DIR] [--work DIR]
//     per validation apartment (generated exactly as `semvox generate --seed N`): the run's stages up to the
//     evidence once, then the CRF variants U, U+PW, U+PW+G after exactly 1 and 5 iterations, and the full model
//     with `semvox run`'s stopping rule; each is written as
//     voxels.ply + occupancy and scored by `semvox eval`'s Evaluate (top-view geometric and semantic
//     accuracy, visible-voxel accuracy) plus the accuracy on completed wall and floor voxels (ground-truth
//     wall/floor voxels the scan never saw).
//   voxelcrf_bench --solvers [--seed N] [--models DIR]
//     one apartment: the first iteration's energy minimised by alpha-expansion with semvox's max-flow and with
//     Boost's boykov_kolmogorov_max_flow (same driver), and by ICM: energy reached, seconds, peak RSS.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "apps/models_dir.h"
#include "pipeline/pipeline_config.h"
#include "pipeline/semantic_evidence.h"
#include "pipeline/semantic_exports.h"
#include "pipeline/semantic_solve.h"
#include "pipeline/voxel_crf_examples.h"
#include "bench/boost_bk_graph.h"
#include "core/labels.h"
#include "core/log.h"
#include "crf/alpha_expansion_impl.h"
#include "eval/evaluate.h"
#include "io/load_scene.h"
#include "mapping/occupancy_map.h"
#include "perception/training_data.h"
#include "render/views.h"
#include "scenegen/apartment.h"
#include "scenegen/apartment_io.h"
#include "scenegen/scan_artefacts.h"

using namespace semvox;
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }
double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}
double PeakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

struct Prepared {
  Scene scene;
  VoxelMap map;
  std::unique_ptr<ViewRenderer> renderer;
  SemanticModels models;
  SemanticEvidence evidence;
  SemanticLabels labels;
  std::string gt_dir;
  Mesh clean_mesh;
  double seconds_voxelize = 0, seconds_views = 0, seconds_classify = 0;
};

Status Prepare(uint64_t seed, const std::string& models, const std::string& work, Prepared* p) {
  ApartmentOptions ao;
  ao.seed = seed;
  ScanArtefactOptions art;
  art.seed = seed;
  Result<Apartment> apt = GenerateApartment(ao);
  if (!apt.ok()) return apt.status();
  p->gt_dir = work + "/gt_" + std::to_string(seed);
  fs::create_directories(p->gt_dir);
  SEMVOX_RETURN_IF_ERROR(WriteApartment(p->gt_dir, *apt, ao, art, GroundTruthOptions(), false));
  p->clean_mesh = apt->mesh;
  Result<Scene> scene = LoadScene(p->gt_dir + "/mesh.ply", LoadOptions{});
  if (!scene.ok()) return scene.status();
  p->scene = std::move(scene).value();
  const PipelineConfig config;
  auto t0 = Clock::now();
  Result<VoxelMap> map = Voxelize(p->scene, config.voxelize);
  if (!map.ok()) return map.status();
  p->map = std::move(map).value();
  p->seconds_voxelize = Seconds(t0);
  Result<ViewRenderer> r = ViewRenderer::Create(p->scene);
  if (!r.ok()) return r.status();
  p->renderer = std::make_unique<ViewRenderer>(std::move(r).value());
  Result<SemanticModels> loaded = SemanticModels::Load(models, config.semantic.crf_model);
  if (!loaded.ok()) return loaded.status();
  p->models = std::move(loaded).value();
  Result<std::unique_ptr<SemanticEvidenceBuilder>> builder = SemanticEvidenceBuilder::Create(p->map, *p->renderer, config.semantic, p->models);
  if (!builder.ok()) return builder.status();
  t0 = Clock::now();
  Result<ViewSet> views = RenderViews(*p->renderer, p->map, config.render, (*builder)->DepthSink());
  if (!views.ok()) return views.status();
  p->seconds_views = Seconds(t0);
  t0 = Clock::now();
  SEMVOX_RETURN_IF_ERROR((*builder)->ClassifyViews(views->positions));
  p->seconds_classify = Seconds(t0);
  p->evidence = std::move(**builder).Finish();
  return Status::Ok();
}

struct Variant {
  const char* name;
  bool pairwise, higher_order;
  int iterations;
};

int Accuracy(const std::vector<uint64_t>& seeds, const std::string& models, const std::string& work) {
  // iterations 0: the default stopping rule of `semvox run` (visibility settled or no longer settling);
  // otherwise exactly that many iterations.
  const Variant variants[] = {{"U, it 1", false, false, 1},  {"U+PW, it 1", true, false, 1},  {"U+PW+G, it 1", true, true, 1},
                              {"U, it 5", false, false, 5},  {"U+PW, it 5", true, false, 5},  {"U+PW+G, it 5", true, true, 5},
                              {"U+PW+G, run", true, true, 0}};
  const size_t nv = std::size(variants);
  std::vector<std::map<std::string, double>> sums(nv);
  std::vector<std::map<std::string, int>> counts(nv);
  const PipelineConfig config;
  const LabelLevel level = SecondLevel();
  for (uint64_t seed : seeds) {
    Prepared p;
    const Status st = Prepare(seed, models, work, &p);
    if (!st.ok()) {
      std::fprintf(stderr, "seed %llu: %s\n", (unsigned long long)seed, st.message().c_str());
      return 1;
    }
    const VoxelLabels gt_voxels = VoxelizeLabeledMesh(p.clean_mesh, config.voxelize.voxel_size_m);
    for (size_t v = 0; v < nv; ++v) {
      VoxelCrfOptions crf = config.semantic.crf;
      crf.use_pairwise = variants[v].pairwise;
      crf.use_higher_order = variants[v].higher_order;
      if (variants[v].iterations > 0) {
        crf.max_iterations = variants[v].iterations;
        crf.visibility_tolerance = 0;
        crf.visibility_min_progress = 0;
      }
      const auto t0 = Clock::now();
      if (!SolveSemantic(p.map, p.evidence, p.models.crf, crf, &p.labels).ok()) return 1;
      const double solve_s = Seconds(t0);
      const std::string dir = work + "/pred_" + std::to_string(seed) + "_" + std::to_string(v);
      fs::create_directories(dir);
      const OccupancyMap occ = ComputeOccupancy(p.labels.refined, p.map.floor_z, config.occupancy);
      if (!WriteOccupancyMap(occ, dir, "occupancy").ok()) return 1;
      if (!WriteSemanticExports(dir, p.map, p.labels, config.occupancy.band_min_above_floor_m, config.occupancy.band_max_above_floor_m, occ.image).ok()) return 1;
      Result<EvalReport> rep = Evaluate(dir, p.gt_dir);
      if (!rep.ok()) {
        std::fprintf(stderr, "eval: %s\n", rep.status().message().c_str());
        return 1;
      }
      // Completed wall / floor: ground-truth wall and floor voxels the scan never saw.
      const VoxelCrfNodes& nodes = p.evidence.nodes;
      const auto& labels = p.labels.crf.labels;
      size_t hidden = 0, right = 0;
      for (size_t i = 0; i < nodes.size(); ++i) {
        if (nodes.initial_state[i] != uint8_t(VoxelState::kUnknown)) continue;
        const auto c = p.map.grid.Cell(nodes.voxel[i]);
        const auto it = gt_voxels.find(p.map.grid.KeyOf(c[0], c[1], c[2]).Pack());
        if (it == gt_voxels.end() || (it->second != nyu40::kWall && it->second != nyu40::kFloor)) continue;
        ++hidden;
        right += labels[i] == level.class_of_nyu40[size_t(it->second)] + 1;
      }
      auto add = [&](const std::string& k, double x) { sums[v][k] += x, counts[v][k] += 1; };
      if (rep->top_view.geometric_accuracy.present) add("geo", rep->top_view.geometric_accuracy.value);
      if (rep->top_view.semantic_accuracy.present) add("top_sem", rep->top_view.semantic_accuracy.value);
      if (rep->voxels.accuracy.present) add("vis_acc", rep->voxels.accuracy.value);
      if (rep->voxels.mean_recall.present) add("vis_recall", rep->voxels.mean_recall.value);
      if (hidden) add("completed", double(right) / double(hidden));
      add("seconds", solve_s);
      std::printf("seed %llu %-13s geo %.3f top-sem %.3f visible acc %.3f recall %.3f completed wall/floor %.3f (%zu) %.1f s\n",
                  (unsigned long long)seed, variants[v].name, rep->top_view.geometric_accuracy.value, rep->top_view.semantic_accuracy.value,
                  rep->voxels.accuracy.value, rep->voxels.mean_recall.value, hidden ? double(right) / double(hidden) : 0.0, hidden, solve_s);
      std::fflush(stdout);
    }
  }
  std::printf("\nmean over %zu validation apartments (5 cm voxels)\n", seeds.size());
  std::printf("%-14s %8s %8s %8s %8s %10s %8s\n", "variant", "Geo", "top S", "vis S", "vis rec", "completed", "solve s");
  for (size_t v = 0; v < nv; ++v) {
    auto m = [&](const char* k) { return counts[v][k] ? sums[v][k] / counts[v][k] : 0.0; };
    std::printf("%-14s %8.3f %8.3f %8.3f %8.3f %10.3f %8.1f\n", variants[v].name, m("geo"), m("top_sem"), m("vis_acc"),
                m("vis_recall"), m("completed"), m("seconds"));
  }
  return 0;
}

int Solvers(uint64_t seed, const std::string& models, const std::string& work) {
  Prepared p;
  const auto t0 = Clock::now();
  const Status st = Prepare(seed, models, work, &p);
  if (!st.ok()) {
    std::fprintf(stderr, "%s\n", st.message().c_str());
    return 1;
  }
  const Aabb box = p.scene.Bounds();
  std::printf("apartment seed %llu: %.1f x %.1f m, %zu CRF nodes; voxelise %.1f s, views %.1f s, classify %.1f s (total %.1f s), peak RSS %.0f MB\n",
              (unsigned long long)seed, box.extent().x(), box.extent().y(), p.evidence.nodes.size(), p.seconds_voxelize, p.seconds_views,
              p.seconds_classify, Seconds(t0), PeakRssMb());
  // Alg. 1 as `semvox run` does it.
  const auto t1 = Clock::now();
  const double cpu1 = CpuSeconds();
  if (!SolveSemantic(p.map, p.evidence, p.models.crf, PipelineConfig{}.semantic.crf, &p.labels).ok()) return 1;
  const double alg1_cpu = CpuSeconds() - cpu1;
  const VoxelCrfResult& r = p.labels.crf;
  std::printf("Voxel-CRF (Alg. 1, %zu iterations): %.1f s wall, %.1f CPU s (both threads), peak RSS %.0f MB; planes %.2f s, ray starts + V_0 %.2f s, "
              "confidence %.2f s\n",
              r.iterations.size(), Seconds(t1), alg1_cpu, PeakRssMb(), r.seconds_planes, r.seconds_ray_starts, r.seconds_confidence);
  for (size_t k = 0; k < r.iterations.size(); ++k) {
    const VoxelCrfIteration& it = r.iterations[k];
    std::printf("  iteration %zu: %.2f s = build %.2f + energy %.2f + alpha-expansion %.2f (max-flow %.2f, %d sweeps) + visibility %.2f; "
                "E %.2f -> %.2f, %lld rays changed\n",
                k + 1, it.seconds, it.seconds_build, it.seconds_energy, it.seconds_expansion, it.seconds_max_flow, it.sweeps, it.seconds_visibility,
                it.energy_initial, it.energy_final, (long long)it.changed_visibility);
  }
  // The first iteration's energy (visibility V_0 from the map) with three minimisers.
  std::vector<int> v0(p.evidence.nodes.size(), 0);
  for (size_t i = 0; i < v0.size(); ++i) v0[i] = p.evidence.nodes.initial_state[i] == uint8_t(VoxelState::kOccupied);
  const VoxelCrfTrainingExample ex = TrainingExample(p.map, p.evidence, PipelineConfig{}.semantic.crf, v0, p.models.crf);
  const CrfEnergy energy = ex.problem.Energy(p.models.crf.w);
  std::printf("first-iteration energy: %d nodes, %d labels, %zu edges, %d cliques, %.0f MB\n", energy.num_nodes(), energy.num_labels(),
              energy.edges().size(), energy.num_cliques(), double(energy.MemoryBytes()) / 1e6);
  std::printf("%-34s %14s %8s %8s\n", "solver", "energy", "sweeps", "seconds");
  {
    std::vector<CrfLabel> labels;
    CrfSolverSummary s;
    const auto t = Clock::now();
    if (!MinimizeWithAlphaExpansion(energy, AlphaExpansionOptions{}, &labels, &s).ok()) return 1;
    std::printf("%-34s %14.2f %8d %8.2f\n", "alpha-expansion, semvox BK", s.final_energy, s.num_sweeps, Seconds(t));
  }
  {
    std::vector<CrfLabel> labels;
    CrfSolverSummary s;
    bench::BoostBkGraph graph;
    const auto t = Clock::now();
    if (!crf_internal::RunAlphaExpansion(energy, AlphaExpansionOptions{}, graph, &labels, &s).ok()) return 1;
    std::printf("%-34s %14.2f %8d %8.2f\n", "alpha-expansion, Boost BK", s.final_energy, s.num_sweeps, Seconds(t));
  }
  {
    std::vector<CrfLabel> labels;
    CrfSolverSummary s;
    const auto t = Clock::now();
    if (!MinimizeWithIcm(energy, IcmOptions{}, &labels, &s).ok()) return 1;
    std::printf("%-34s %14.2f %8d %8.2f\n", "ICM", s.final_energy, s.num_sweeps, Seconds(t));
  }
  std::printf("peak RSS %.0f MB\n", PeakRssMb());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string mode, models, work = "/tmp/semvox_voxelcrf_bench", seeds_text = "100-104";
  uint64_t seed = 100;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--accuracy" || a == "--solvers") mode = a;
    else if (a == "--models") models = next();
    else if (a == "--work") work = next();
    else if (a == "--seeds") seeds_text = next();
    else if (a == "--seed") seed = std::stoull(next());
    else {
      std::fprintf(stderr, "usage: voxelcrf_bench --accuracy|--solvers [--seeds A-B] [--seed N] [--models DIR] [--work DIR]\n");
      return 2;
    }
  }
  // As `semvox run`: --models, $SEMVOX_MODELS, else the build tree's share/semvox/models.
  Result<std::string> models_dir = ResolveModelsDir(models, argv[0]);
  if (!models_dir.ok()) return std::fprintf(stderr, "voxelcrf_bench: %s\n", models_dir.status().message().c_str()), 2;
  models = std::move(models_dir).value();
  SetLogLevel(LogLevel::kWarning);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  fs::create_directories(work);
  if (mode == "--solvers") return Solvers(seed, models, work);
  std::vector<uint64_t> seeds;
  if (!ParseSeedList(seeds_text, "--seeds", &seeds).ok()) return 2;
  return Accuracy(seeds, models, work);
}
