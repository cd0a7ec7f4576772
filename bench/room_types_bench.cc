// Room-type accuracy on the generated validation apartments (the room-labelling paper, Table II form):
// per-pixel accuracy, global (pooled pixels) and average (mean recall over types), and the mean over
// apartments of the per-apartment global accuracy, for the raw scene evidence, majority voting, the dense
// Gaussian CRF and the Gibbs CRF variants; and the CRF stage's time per apartment.
//
//   room_types_bench [--seeds 100-109] [--models DIR] [--sweeps N] [--seed S]
//                    [--protocol split|loao] [--train-seeds 0-39] [--ssvm-epochs 30] [--fold-models DIR]
//                    [--pred-topview PATTERN] [--shape-weight W]
//
// Per apartment: the plan is rasterised from the generator's ground truth and segmented (SegmentRooms,
// default options); the views are the training views (room middles, 4 headings, 320x240, 60 degrees)
// rendered and classified as `semvox train` does (second level, tree CRF, then the room-type k-NN), with
// the models of DIR (default: the source tree's models/). Truth: each pixel's room type.
//
// Top view: the generator's ground-truth top view (topview_gt). With --pred-topview, also the pipeline's own:
// PATTERN is a `semvox run` OUTDIR with {seed} for the seed (e.g. /tmp/runs/{seed}); its
// semantic_topview_labels.png (on the occupancy grid of occupancy.yaml) is resampled onto the plan's grid
// (pixel centres) and every method is scored a second time with it, on the apartments that have a run. The
// frame is checked: agreement with the ground-truth top view at the resampled position and at shifts of up
// to 2 pixels (the best shift must be 0).
//
// Protocols (split is always scored; loao in addition with --protocol loao):
//  split  the committed model (trained on training apartments 35-39, statistics from 0-39) and room-type
//         k-NN (rows of apartments 0-39), evaluated on the validation apartments.
//  loao   leave one apartment out over the validation apartments: for each held-out apartment h, the
//         confusion (Eq. 3), the SSVM weights (and their scale calibration) of the evaluated variants and the
//         dense-CRF grid search are learned on the other validation apartments (as `semvox train` does on
//         its CRF apartments: each one's views from a room-type k-NN without its own rows), and h is
//         evaluated with a room-type k-NN whose rows are those of the training apartments (--train-seeds,
//         ground-truth classes, as `semvox train`) and the other validation apartments, never h's. The
//         object and homogeneity statistics stay the committed model's (40 training apartments + R2V); the
//         per-view classifier (second level) stays the committed one. The SSVM runs --ssvm-epochs epochs
//         (default 30, as `semvox train`; fewer keep ten folds short). Training scenes use their
//         ground-truth top views (as `semvox train`). With --fold-models DIR, each fold's learned model is
//         saved as DIR/fold_<h>.json, and loaded instead of learned when it exists (a second run with
//         --pred-topview then costs only the classification and the inference; delete DIR after changing
//         the data or the code).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "io/image_io.h"
#include "mapping/occupancy_map.h"
#include "perception/knn_unary.h"
#include "perception/room_evidence.h"
#include "perception/training_data.h"
#include "perception/view_classifier.h"
#include "rooms/room_type_crf.h"
#include "rooms/room_type_training.h"

using namespace semvox;

namespace {

struct Method {
  std::string name;
  RoomTypeMethod method = RoomTypeMethod::kGibbsCrf;
  RoomTypeVariant variant;
  bool raw_scene = false;
};

// Per method, per apartment: the accuracy accumulator and the seconds.
struct Scores {
  std::vector<std::map<uint64_t, RoomTypeAccuracy>> per_apartment;
  std::vector<double> seconds;
  explicit Scores(size_t methods) : per_apartment(methods), seconds(methods, 0) {}
};

bool ParseRange(const std::string& v, uint64_t* first, uint64_t* last) {
  const size_t dash = v.find('-');
  try {
    *first = std::stoull(v.substr(0, dash));
    *last = dash == std::string::npos ? *first : std::stoull(v.substr(dash + 1));
  } catch (...) {
    return false;
  }
  return *first <= *last;
}

std::string WithSeed(std::string pattern, uint64_t seed) {
  const size_t at = pattern.find("{seed}");
  if (at != std::string::npos) pattern.replace(at, 6, std::to_string(seed));
  return pattern;
}

// The run's semantic top view on the plan's grid (pixel centres looked up in the occupancy grid), with the
// agreement with `gt_topview` (labelled cells: label equal; empty cells: empty) at shifts -2..2 px; returns
// nullopt when the run has no top view.
std::optional<ImageU16> PredictedTopView(const std::string& outdir, const FloorPlan& plan, const ImageU16& gt_topview,
                                         std::string* note) {
  namespace fs = std::filesystem;
  const std::string labels = (fs::path(outdir) / "semantic_topview_labels.png").string();
  const std::string yaml = (fs::path(outdir) / "occupancy.yaml").string();
  if (!fs::exists(labels) || !fs::exists(yaml)) return std::nullopt;
  Result<ImageU16> top = ReadImageU16(labels);
  Result<OccupancyMap> occ = ReadOccupancyMap(yaml);
  if (!top.ok() || !occ.ok() || top->width != occ->image.width || top->height != occ->image.height) {
    *note = "unreadable or mismatched top view in " + outdir;
    return std::nullopt;
  }
  const int W = plan.cells.width, H = plan.cells.height;
  auto sample = [&](int dc, int dr) {
    ImageU16 out(W, H, 1, 0);
    for (int r = 0; r < H; ++r)
      for (int c = 0; c < W; ++c) {
        const double x = plan.origin_x + (c + dc + 0.5) * plan.resolution_m;
        const double y = plan.origin_y + (H - (r + dr) - 0.5) * plan.resolution_m;
        const int oc = int(std::floor((x - occ->origin_x) / occ->resolution));
        const int orow = occ->image.height - 1 - int(std::floor((y - occ->origin_y) / occ->resolution));
        if (oc < 0 || orow < 0 || oc >= occ->image.width || orow >= occ->image.height) continue;
        out.at(c, r) = top->at(oc, orow);
      }
    return out;
  };
  auto agreement = [&](const ImageU16& p, double* labelled) {
    size_t n = 0, ok = 0, nl = 0, okl = 0;
    for (size_t i = 0; i < p.data.size(); ++i) {
      const int g = gt_topview.data[i];
      ++n;
      ok += (g != 0) == (p.data[i] != 0);
      if (g != 0) ++nl, okl += p.data[i] == g;
    }
    *labelled = nl ? double(okl) / nl : 0;
    return n ? double(ok) / n : 0;
  };
  double best = -1, at0 = 0, lab0 = 0;
  int best_dc = 0, best_dr = 0;
  for (int dr = -2; dr <= 2; ++dr)
    for (int dc = -2; dc <= 2; ++dc) {
      double lab = 0;
      const double a = agreement(sample(dc, dr), &lab);
      if (dc == 0 && dr == 0) at0 = a, lab0 = lab;
      if (a > best + 1e-12) best = a, best_dc = dc, best_dr = dr;
    }
  // What the object term sees: per object group (Eq. 4), cells in the ground truth, cells predicted, and the
  // fraction of the predicted ones whose ground-truth cell is of the same group.
  const ImageU16 out = sample(0, 0);
  std::array<size_t, kNumObjectGroups> n_gt{}, n_pred{}, n_both{};
  for (size_t i = 0; i < out.data.size(); ++i) {
    const int g = ObjectGroupOf(gt_topview.data[i]), p = ObjectGroupOf(out.data[i]);
    if (g >= 0) ++n_gt[size_t(g)];
    if (p >= 0) ++n_pred[size_t(p)], n_both[size_t(p)] += g == p;
  }
  char buf[512];
  std::snprintf(buf, sizeof(buf), "occupied/empty agreement %.3f (best shift %+d,%+d px: %.3f), labels equal on %.3f of labelled cells, res %.3f; "
                "object groups gt/pred cells (pred in gt group):",
                at0, best_dc, best_dr, best, lab0, occ->resolution);
  *note = buf;
  for (int g = 0; g < kNumObjectGroups; ++g) {
    std::snprintf(buf, sizeof(buf), " g%d %zu/%zu (%.2f)", g + 1, n_gt[size_t(g)], n_pred[size_t(g)],
                  n_pred[size_t(g)] ? double(n_both[size_t(g)]) / double(n_pred[size_t(g)]) : 0.0);
    *note += buf;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  uint64_t first = 100, last = 109, seed = 1, train_first = 0, train_last = 39;
  std::string models = std::string(SEMVOX_SOURCE_DIR) + "/models", protocol = "split", pred_pattern, fold_dir;
  int sweeps = 100, ssvm_epochs = SsvmOptions{}.epochs;
  double shape_weight = RoomTypeCrfOptions{}.shape_weight;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return std::fprintf(stderr, "room_types_bench: %s needs a value\n", a.c_str()), 2;
    const std::string v = argv[++i];
    bool ok = true;
    if (a == "--seeds") {
      ok = ParseRange(v, &first, &last);
    } else if (a == "--train-seeds") {
      ok = ParseRange(v, &train_first, &train_last);
    } else if (a == "--models") {
      models = v;
    } else if (a == "--sweeps") {
      sweeps = std::stoi(v);
    } else if (a == "--seed") {
      seed = std::stoull(v);
    } else if (a == "--protocol") {
      protocol = v;
      ok = v == "split" || v == "loao";
    } else if (a == "--ssvm-epochs") {
      ssvm_epochs = std::stoi(v);
      ok = ssvm_epochs >= 1;
    } else if (a == "--fold-models") {
      fold_dir = v;
    } else if (a == "--pred-topview") {
      pred_pattern = v;
    } else if (a == "--shape-weight") {
      shape_weight = std::stod(v);
      ok = shape_weight >= 0;
    } else {
      return std::fprintf(stderr,
                          "room_types_bench: unknown argument %s (hint: --seeds A-B --models DIR --sweeps N --seed S --protocol split|loao "
                          "--train-seeds A-B --ssvm-epochs N --fold-models DIR --pred-topview OUTDIR_WITH_{seed} --shape-weight W)\n",
                          a.c_str()),
             2;
    }
    if (!ok) return std::fprintf(stderr, "room_types_bench: bad value %s for %s\n", v.c_str(), a.c_str()), 2;
  }
  const bool loao = protocol == "loao";
  if (loao && last - first < 1) return std::fprintf(stderr, "room_types_bench: loao needs at least two apartments\n"), 2;
  Result<ViewClassifier> clf = ViewClassifier::Load(models + "/second", ViewClassifierOptions{});
  Result<KnnClassifier> knn = KnnClassifier::Load(models + "/room_type_knn.bin");
  Result<RoomTypeModel> model = LoadRoomTypeModel(models + "/room_type_crf.json");
  if (!clf.ok() || !knn.ok() || !model.ok()) {
    std::fprintf(stderr, "room_types_bench: %s (hint: run `semvox train -o %s`)\n",
                 (!clf.ok() ? clf.status() : !knn.ok() ? knn.status() : model.status()).message().c_str(), models.c_str());
    return 1;
  }
  std::vector<Method> methods;
  auto add = [&](const std::string& name, RoomTypeMethod method, RoomTypeVariant variant, bool raw) {
    Method m;
    m.name = name, m.method = method, m.variant = variant, m.raw_scene = raw;
    methods.push_back(m);
  };
  add("scene evidence (argmax)", RoomTypeMethod::kMajorityVoting, {}, true);
  add("majority voting", RoomTypeMethod::kMajorityVoting, {}, false);
  add("dense G-CRF (mean field)", RoomTypeMethod::kDenseCrf, {}, false);
  const std::vector<RoomTypeVariant> gibbs = {
      {ScenePotential::kCnn, HomogeneityPotential::kNone, false},        // CRF 1
      {ScenePotential::kConfusion, HomogeneityPotential::kNone, false},  // CRF 2
      {ScenePotential::kConfusion, HomogeneityPotential::kGaussian, false},  // CRF 3
      {ScenePotential::kConfusion, HomogeneityPotential::kGaussian, true},   // CRF 4
      {ScenePotential::kConfusion, HomogeneityPotential::kStatistics, true},  // CRF 5
      {ScenePotential::kCnn, HomogeneityPotential::kGaussian, true},
      {ScenePotential::kCnn, HomogeneityPotential::kStatistics, true},
  };
  for (const RoomTypeVariant& v : gibbs) add("Gibbs CRF " + v.Name(), RoomTypeMethod::kGibbsCrf, v, false);
  size_t default_index = 0;  // The pipeline's variant (conf+gauss+obj).
  for (size_t mi = 0; mi < methods.size(); ++mi)
    if (methods[mi].method == RoomTypeMethod::kGibbsCrf && methods[mi].variant.Name() == RoomTypeVariant{}.Name()) default_index = mi;
  RoomTypeCrfOptions options;
  options.sample_sweeps = sweeps;
  options.seed = seed;
  options.shape_weight = shape_weight;
  std::optional<RoomShapeModel> shape_model;
  if (shape_weight > 0) {
    Result<RoomShapeModel> sm = LoadRoomShapeModel(models + "/room_shape.json");
    if (!sm.ok()) return std::fprintf(stderr, "room_types_bench: %s\n", sm.status().message().c_str()), 1;
    shape_model = *sm;
  }
  const auto t_start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count(); };

  // Per validation apartment: scene (ground-truth top view), predicted top view, classified view records
  // and ground-truth k-NN rows.
  const LabelLevel level = SecondLevel();
  const int dims = RoomDescriptorDims(level.num_classes());
  std::vector<uint64_t> val;
  std::map<uint64_t, RoomTypeTrainingScene> scenes;
  std::map<uint64_t, ImageU16> pred_top;
  std::vector<RoomViewRecord> records;
  std::vector<float> rows;
  std::vector<int> labels;
  std::vector<uint64_t> row_seeds;
  double area_m2 = 0;
  for (uint64_t s = first; s <= last; ++s) {
    Result<RoomTypeTrainingScene> scene = RoomTypeSceneFromApartment(s);
    if (!scene.ok()) return std::fprintf(stderr, "room_types_bench: seed %llu: %s\n", (unsigned long long)s, scene.status().message().c_str()), 1;
    const size_t before = labels.size();
    const Status st = ClassifiedApartmentRecords(s, TrainingViewsOptions{}, *clf, kRoomViewRangeM, &records, &rows, &labels);
    if (!st.ok()) return std::fprintf(stderr, "room_types_bench: seed %llu: %s\n", (unsigned long long)s, st.message().c_str()), 1;
    row_seeds.resize(labels.size(), s);
    for (uint16_t t : scene->truth.data) area_m2 += t ? scene->plan.resolution_m * scene->plan.resolution_m : 0;
    std::string note = "no run";
    if (!pred_pattern.empty()) {
      std::optional<ImageU16> p = PredictedTopView(WithSeed(pred_pattern, s), scene->plan, scene->topview, &note);
      if (p) pred_top[s] = std::move(*p);
    }
    std::fprintf(stderr, "seed %llu: %zu truth rows, %.0f s%s%s\n", (unsigned long long)s, labels.size() - before, elapsed(),
                 pred_pattern.empty() ? "" : "; predicted top view: ", pred_pattern.empty() ? "" : note.c_str());
    scenes[s] = std::move(scene).value();
    val.push_back(s);
  }
  // Training apartments' k-NN rows (loao): ground-truth classes of their views, as `semvox train`.
  std::vector<float> train_rows;
  std::vector<int> train_labels;
  if (loao) {
    for (uint64_t s = train_first; s <= train_last; ++s) {
      const Status st = ClassifiedApartmentRecords(s, TrainingViewsOptions{}, *clf, kRoomViewRangeM, nullptr, &train_rows, &train_labels);
      if (!st.ok()) return std::fprintf(stderr, "room_types_bench: training seed %llu: %s\n", (unsigned long long)s, st.message().c_str()), 1;
    }
    std::fprintf(stderr, "training rows: %zu from apartments %llu-%llu (the committed k-NN holds %zu), %.0f s\n", train_labels.size(),
                 (unsigned long long)train_first, (unsigned long long)train_last, knn->size(), elapsed());
  }

  // Scores per protocol ("split" always: the committed model; "loao" with --protocol loao) and top view.
  std::map<std::string, Scores> scores;
  auto scores_of = [&](const std::string& key) -> Scores& {
    if (!scores.count(key)) scores.emplace(key, Scores(methods.size()));
    return scores.at(key);
  };
  int total_views = 0, total_splits = 0;
  double stage_seconds = 0, learn_seconds = 0;
  for (uint64_t h : val) {
    struct Protocol {
      std::string name;
      RoomTypeModel model;
      std::vector<ViewRoomEvidence> views;
    };
    std::vector<Protocol> protocols(1);
    protocols[0].name = "split", protocols[0].model = *model;
    for (const RoomViewRecord& r : records)
      if (r.seed == h) protocols[0].views.push_back(RoomViewEvidence(*knn, r, kRoomMinObjectFraction));
    if (loao) {
      const auto t0 = std::chrono::steady_clock::now();
      Protocol p;
      p.name = "loao", p.model = *model;
      // Rows of the fold: training apartments + the other validation apartments (tagged with their seed; the
      // training rows with an id no validation seed has).
      std::vector<float> fold_rows = train_rows;
      std::vector<int> fold_labels = train_labels;
      std::vector<uint64_t> fold_seeds(train_labels.size(), ~uint64_t(0));
      for (size_t i = 0; i < labels.size(); ++i) {
        if (row_seeds[i] == h) continue;
        fold_rows.insert(fold_rows.end(), rows.begin() + long(i * size_t(dims)), rows.begin() + long((i + 1) * size_t(dims)));
        fold_labels.push_back(labels[i]);
        fold_seeds.push_back(row_seeds[i]);
      }
      std::vector<RoomViewRecord> fold_records;
      for (const RoomViewRecord& r : records)
        if (r.seed != h) fold_records.push_back(r);
      const std::string cached = fold_dir.empty() ? "" : fold_dir + "/fold_" + std::to_string(h) + ".json";
      std::string report;
      size_t fold_scenes = 0;
      if (!cached.empty() && std::filesystem::exists(cached)) {  // Learned by an earlier run with the same data.
        Result<RoomTypeModel> m = LoadRoomTypeModel(cached);
        if (!m.ok()) return std::fprintf(stderr, "room_types_bench: %s\n", m.status().message().c_str()), 1;
        p.model = std::move(m).value();
        report = "(loaded " + cached + ")\n";
      } else {
        Result<std::vector<RoomTypeTrainingScene>> train_scenes =
            LeaveOneOutEvidenceScenes(fold_records, fold_rows, fold_labels, fold_seeds, dims, kRoomMinObjectFraction, &scenes);
        if (!train_scenes.ok()) return std::fprintf(stderr, "room_types_bench: %s\n", train_scenes.status().message().c_str()), 1;
        RoomTypeTrainingOptions to;
        to.ssvm.epochs = ssvm_epochs;
        report = LearnRoomTypeEvidenceTerms(*train_scenes, gibbs, to, &p.model);
        fold_scenes = train_scenes->size();
        p.model.provenance = "room_types_bench leave-one-apartment-out fold " + std::to_string(h);
        if (!cached.empty()) {
          std::filesystem::create_directories(fold_dir);
          const Status st = SaveRoomTypeModel(p.model, cached);
          if (!st.ok()) return std::fprintf(stderr, "room_types_bench: %s\n", st.message().c_str()), 1;
        }
      }
      Result<KnnClassifier> fold_knn = RoomKnnWithout(fold_rows, fold_labels, fold_seeds, dims, {});
      if (!fold_knn.ok()) return std::fprintf(stderr, "room_types_bench: %s\n", fold_knn.status().message().c_str()), 1;
      for (const RoomViewRecord& r : records)
        if (r.seed == h) p.views.push_back(RoomViewEvidence(*fold_knn, r, kRoomMinObjectFraction));
      const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      learn_seconds += dt;
      std::fprintf(stderr, "fold %llu: learned on %zu apartments (%zu k-NN rows) in %.0f s:\n%s", (unsigned long long)h,
                   fold_scenes, fold_labels.size(), dt, report.c_str());
      protocols.push_back(std::move(p));
    }
    total_views += int(protocols[0].views.size());
    const RoomTypeTrainingScene& scene = scenes[h];
    std::vector<std::pair<std::string, const ImageU16*>> tops = {{"gt", &scene.topview}};
    if (pred_top.count(h)) tops.push_back({"pred", &pred_top[h]});
    for (const Protocol& proto : protocols)
      for (const auto& [top_name, topview] : tops) {
        Scores& sc = scores_of(proto.name + "/" + top_name);
        for (size_t mi = 0; mi < methods.size(); ++mi) {
          const Method& m = methods[mi];
          options.variant = m.variant;
          const auto t0 = std::chrono::steady_clock::now();
          ImageU16 predicted;
          if (m.raw_scene) {  // Each pixel: argmax of its node's mean view distribution (no type where no view looks).
            Result<RoomTypeGraph> g = BuildRoomTypeGraph(scene.plan, scene.rooms, proto.views, *topview, proto.model, options);
            if (!g.ok()) return 1;
            predicted = ImageU16(g->width, g->height, 1, 0);
            for (size_t i = 0; i < g->node_of_pixel.size(); ++i)
              if (const int n = g->node_of_pixel[i]; n >= 0 && g->covered[size_t(n)])
                predicted.data[i] = uint16_t(std::max_element(g->scene[size_t(n)].begin(), g->scene[size_t(n)].end()) - g->scene[size_t(n)].begin() + 1);
          } else {
            Result<RoomTypeResult> r = InferRoomTypes(scene.plan, scene.rooms, proto.views, *topview, proto.model, options, m.method,
                                                      shape_model ? &*shape_model : nullptr);
            if (!r.ok()) return std::fprintf(stderr, "room_types_bench: %s\n", r.status().message().c_str()), 1;
            predicted = r->pixel_types;
            if (proto.name == "split" && top_name == "gt" && mi == default_index) {
              stage_seconds += r->seconds;
              total_splits += r->splits;
            }
          }
          sc.seconds[mi] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          sc.per_apartment[mi][h].Add(predicted, scene.truth);
        }
      }
    std::fprintf(stderr, "seed %llu: %zu views, default CRF (gt top view) split %.3f%s, %.0f s\n", (unsigned long long)h,
                 protocols[0].views.size(), scores_of("split/gt").per_apartment[default_index][h].Global(),
                 loao ? (" loao " + std::to_string(scores_of("loao/gt").per_apartment[default_index][h].Global())).c_str() : "", elapsed());
  }
  const int apartments = int(val.size());
  std::printf("room types, validation apartments %llu-%llu (%d apartments, %d views, %.0f m2 scored), Gibbs %d+%d sweeps, seed %llu\n",
              (unsigned long long)first, (unsigned long long)last, apartments, total_views, area_m2, options.burn_in_sweeps, sweeps,
              (unsigned long long)seed);
  if (loao)
    std::printf("protocol: leave one validation apartment out (confusion, SSVM weights, dense-CRF grid, room-type k-NN rows without the held-out "
                "apartment; k-NN rows also from training apartments %llu-%llu; object/homogeneity statistics from the committed model); "
                "SSVM %d epochs; learning %.0f s in all\n",
                (unsigned long long)train_first, (unsigned long long)train_last, ssvm_epochs, learn_seconds);
  else
    std::printf("protocol: train/validation split (committed models)\n");
  auto table = [&](const char* title, const Scores& sc, const std::vector<uint64_t>& subset) {
    if (subset.empty()) return;
    std::printf("%s (%zu apartments:", title, subset.size());
    for (uint64_t s : subset) std::printf(" %llu", (unsigned long long)s);
    std::printf(")\n%-36s %8s %8s %10s %9s\n", "method", "global", "average", "mean/apt", "s/apt");
    for (size_t mi = 0; mi < methods.size(); ++mi) {
      RoomTypeAccuracy pooled;
      double sum = 0;
      for (uint64_t s : subset) {
        const RoomTypeAccuracy& a = sc.per_apartment[mi].at(s);
        for (size_t t = 0; t < pooled.total.size(); ++t) pooled.total[t] += a.total[t], pooled.correct[t] += a.correct[t];
        sum += a.Global();
      }
      std::printf("%-36s %8.4f %8.4f %10.4f %9.3f\n", methods[mi].name.c_str(), pooled.Global(), pooled.Average(), sum / double(subset.size()),
                  sc.seconds[mi] / double(subset.size()));
    }
  };
  std::vector<uint64_t> with_pred;
  for (uint64_t s : val)
    if (pred_top.count(s)) with_pred.push_back(s);
  for (const std::string proto : {"split", "loao"}) {
    if (!scores.count(proto + "/gt")) continue;
    const std::string what = proto == "split" ? "train/validation split (committed model)" : "leave one apartment out";
    table((what + ", ground-truth top view").c_str(), scores.at(proto + "/gt"), val);
    if (with_pred.empty()) continue;
    if (with_pred.size() < val.size()) table((what + ", ground-truth top view, apartments with a run").c_str(), scores.at(proto + "/gt"), with_pred);
    table((what + ", predicted top view (semvox run's semantic_topview_labels.png)").c_str(), scores.at(proto + "/pred"), with_pred);
  }
  for (const auto& [key, sc] : scores) {
    std::printf("per apartment, %s, default variant %s:", key.c_str(), RoomTypeVariant{}.Name().c_str());
    for (const auto& [s, acc] : sc.per_apartment[default_index]) std::printf(" %llu:%.3f", (unsigned long long)s, acc.Global());
    std::printf("\n");
  }
  std::printf("default variant (%s): %.3f s per apartment for graph + Gibbs + rooms, %d rooms split\n", RoomTypeVariant{}.Name().c_str(),
              stage_seconds / std::max(1, apartments), total_splits);
  return 0;
}
