// Room-type accuracy on the generated validation apartments (the room-labelling paper, Table II form):
// per-pixel accuracy, global (pooled pixels) and average (mean recall over types), and the mean over
// apartments of the per-apartment global accuracy, for the raw scene evidence, majority voting, the dense
// Gaussian CRF and the Gibbs CRF variants; and the CRF stage's time per apartment.
//
//   room_types_bench [--seeds 100-109] [--models DIR] [--sweeps N] [--seed S]
//
// Per apartment: the plan is rasterised from the generator's ground truth and segmented (SegmentRooms,
// default options); the top view is the generator's ground-truth top view (topview_gt; the Voxel-CRF top
// view is not used here); the views are the training views (room middles, 4 headings, 320x240, 60 degrees)
// rendered and classified as `semvox train` does (second level, tree CRF, then the room-type k-NN), with
// the models of DIR (default: the source tree's models/). Truth: each pixel's room type.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "perception/knn_unary.h"
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
  RoomTypeAccuracy acc;
  double sum_apartment_global = 0, seconds = 0;
};

}  // namespace

int main(int argc, char** argv) {
  uint64_t first = 100, last = 109, seed = 1;
  std::string models = std::string(SEMVOX_SOURCE_DIR) + "/models";
  int sweeps = 100;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return std::fprintf(stderr, "room_types_bench: %s needs a value\n", a.c_str()), 2;
    const std::string v = argv[++i];
    if (a == "--seeds") {
      const size_t dash = v.find('-');
      first = std::stoull(v.substr(0, dash));
      last = dash == std::string::npos ? first : std::stoull(v.substr(dash + 1));
    } else if (a == "--models") {
      models = v;
    } else if (a == "--sweeps") {
      sweeps = std::stoi(v);
    } else if (a == "--seed") {
      seed = std::stoull(v);
    } else {
      return std::fprintf(stderr, "room_types_bench: unknown argument %s (hint: --seeds A-B --models DIR --sweeps N --seed S)\n", a.c_str()), 2;
    }
  }
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
  RoomTypeCrfOptions options;
  options.sample_sweeps = sweeps;
  options.seed = seed;
  int apartments = 0, total_views = 0, total_splits = 0;
  double stage_seconds = 0, area_m2 = 0;
  for (uint64_t s = first; s <= last; ++s) {
    Result<RoomTypeTrainingScene> scene = RoomTypeSceneFromApartment(s);
    if (!scene.ok()) return std::fprintf(stderr, "room_types_bench: seed %llu: %s\n", (unsigned long long)s, scene.status().message().c_str()), 1;
    Result<std::vector<ViewRoomEvidence>> views = ClassifiedApartmentViews(s, TrainingViewsOptions{}, *clf, *knn, 8.0);
    if (!views.ok()) return std::fprintf(stderr, "room_types_bench: seed %llu: %s\n", (unsigned long long)s, views.status().message().c_str()), 1;
    ++apartments;
    total_views += int(views->size());
    for (uint16_t t : scene->truth.data) area_m2 += t ? scene->plan.resolution_m * scene->plan.resolution_m : 0;
    for (Method& m : methods) {
      options.variant = m.variant;
      const auto t0 = std::chrono::steady_clock::now();
      ImageU16 predicted;
      if (m.raw_scene) {  // Each pixel: argmax of its node's mean view distribution (no type where no view looks).
        Result<RoomTypeGraph> g = BuildRoomTypeGraph(scene->plan, scene->rooms, *views, scene->topview, *model, options);
        if (!g.ok()) return 1;
        predicted = ImageU16(g->width, g->height, 1, 0);
        for (size_t i = 0; i < g->node_of_pixel.size(); ++i)
          if (const int n = g->node_of_pixel[i]; n >= 0 && g->covered[size_t(n)])
            predicted.data[i] = uint16_t(std::max_element(g->scene[size_t(n)].begin(), g->scene[size_t(n)].end()) - g->scene[size_t(n)].begin() + 1);
      } else {
        Result<RoomTypeResult> r = InferRoomTypes(scene->plan, scene->rooms, *views, scene->topview, *model, options, m.method);
        if (!r.ok()) return std::fprintf(stderr, "room_types_bench: %s\n", r.status().message().c_str()), 1;
        predicted = r->pixel_types;
        if (m.variant.Name() == RoomTypeVariant{}.Name() && m.method == RoomTypeMethod::kGibbsCrf) {
          stage_seconds += r->seconds;
          total_splits += r->splits;
        }
      }
      m.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      RoomTypeAccuracy one;
      one.Add(predicted, scene->truth);
      m.acc.Add(predicted, scene->truth);
      m.sum_apartment_global += one.Global();
    }
    std::fprintf(stderr, "seed %llu: %zu views\n", (unsigned long long)s, views->size());
  }
  std::printf("room types, validation apartments %llu-%llu (%d apartments, %d views, %.0f m2 scored), Gibbs %d+%d sweeps, seed %llu\n",
              (unsigned long long)first, (unsigned long long)last, apartments, total_views, area_m2, options.burn_in_sweeps, sweeps,
              (unsigned long long)seed);
  std::printf("%-36s %8s %8s %10s %9s\n", "method", "global", "average", "mean/apt", "s/apt");
  for (const Method& m : methods)
    std::printf("%-36s %8.4f %8.4f %10.4f %9.3f\n", m.name.c_str(), m.acc.Global(), m.acc.Average(),
                m.sum_apartment_global / std::max(1, apartments), m.seconds / std::max(1, apartments));
  std::printf("default variant (%s): %.3f s per apartment for graph + Gibbs + rooms, %d rooms split\n", RoomTypeVariant{}.Name().c_str(),
              stage_seconds / std::max(1, apartments), total_splits);
  return 0;
}
