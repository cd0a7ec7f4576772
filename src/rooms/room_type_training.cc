#include "rooms/room_type_training.h"

#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>

#include "core/file_util.h"
#include "core/labels.h"
#include "perception/room_evidence.h"
#include "rooms/r2v_layout.h"
#include "rooms/r2v_plan.h"
#include "scenegen/apartment_io.h"

namespace semvox {
namespace {

using Dist = std::array<double, kRoomTypeLabels>;

bool InsideBox(const OrientedBox& b, double x, double y, double margin = 0) {
  const double c = std::cos(b.yaw_rad), s = std::sin(b.yaw_rad);
  const double dx = x - b.center.x(), dy = y - b.center.y();
  const double u = c * dx + s * dy, v = -s * dx + c * dy;
  return std::fabs(u) <= b.size.x() / 2 + margin && std::fabs(v) <= b.size.y() / 2 + margin;
}

int R2vFixtureLabel(const std::string& name) {
  if (name == "cooking_counter") return 12;
  if (name == "washing_basin") return 34;
  if (name == "toilet") return 33;
  if (name == "bathtub") return 36;
  return 0;
}

}  // namespace

std::vector<RoomTypeVariant> AllRoomTypeVariants() {
  std::vector<RoomTypeVariant> out;
  for (ScenePotential s : {ScenePotential::kCnn, ScenePotential::kConfusion})
    for (HomogeneityPotential h : {HomogeneityPotential::kNone, HomogeneityPotential::kStatistics, HomogeneityPotential::kGaussian})
      for (bool obj : {false, true}) out.push_back({s, h, obj});
  return out;
}

FloorPlan FloorPlanFromApartment(const Apartment& a, double resolution_m) {
  GroundTruthOptions gto;
  gto.resolution_m = resolution_m;
  const FloorGrid grid = MakeFloorGrid(a, gto);
  const ImageU16 rooms = RasterizeRooms(a, grid);
  FloorPlan plan;
  plan.resolution_m = grid.resolution;
  plan.origin_x = grid.origin_x, plan.origin_y = grid.origin_y, plan.floor_z = a.floor_z_m;
  plan.cells = Image<uint8_t>(grid.width, grid.height, 1, uint8_t(FloorCell::kWall));
  plan.ceiling_height_m = ImageF32(grid.width, grid.height, 1, 0.f);
  for (int r = 0; r < grid.height; ++r)
    for (int c = 0; c < grid.width; ++c) {
      if (!rooms.at(c, r)) continue;
      plan.cells.at(c, r) = uint8_t(FloorCell::kFree);
      plan.ceiling_height_m.at(c, r) = float(a.ceiling_z_m - a.floor_z_m);
      const double x = grid.CenterX(c), y = grid.CenterY(r);
      for (const ObjectGt& o : a.objects)
        if (o.support_of < 0 && o.box.center.z() - o.box.size.z() / 2 < a.floor_z_m + 0.2 && InsideBox(o.box, x, y)) {
          plan.cells.at(c, r) = uint8_t(FloorCell::kClutter);
          break;
        }
    }
  for (const DoorGt& d : a.doors) {
    const double half_w = d.width_m / 2, half_t = d.wall_thickness_m / 2 + grid.resolution;
    for (int r = 0; r < grid.height; ++r)
      for (int c = 0; c < grid.width; ++c) {
        const double dx = grid.CenterX(c) - d.center.x(), dy = grid.CenterY(r) - d.center.y();
        const bool in = d.along_x ? std::fabs(dx) <= half_w && std::fabs(dy) <= half_t : std::fabs(dy) <= half_w && std::fabs(dx) <= half_t;
        if (in && plan.at(c, r) == FloorCell::kWall) plan.cells.at(c, r) = uint8_t(FloorCell::kDoor);
      }
  }
  return plan;
}

Result<RoomTypeTrainingScene> RoomTypeSceneFromApartment(uint64_t seed, const RoomSegmentationOptions& segmentation) {
  ApartmentOptions ao;
  ao.seed = seed;
  Result<Apartment> a = GenerateApartment(ao);
  if (!a.ok()) return a.status();
  return RoomTypeSceneOf(*a, segmentation);
}

RoomTypeTrainingScene RoomTypeSceneOf(const Apartment& apartment, const RoomSegmentationOptions& segmentation) {
  const Apartment* a = &apartment;
  RoomTypeTrainingScene s;
  s.plan = FloorPlanFromApartment(*a);
  s.rooms = SegmentRooms(s.plan, segmentation);
  const GroundTruthOptions gto;
  const FloorGrid grid = MakeFloorGrid(*a, gto);
  s.topview = RasterizeTopView(*a, grid, gto);
  for (uint16_t& v : s.topview.data)
    if (v == kTopViewHidden) v = 0;
  const ImageU16 rooms = RasterizeRooms(*a, grid);
  s.truth = ImageU16(rooms.width, rooms.height, 1, 0);
  std::map<int, int> type_of;
  for (const RoomGt& r : a->rooms) type_of[r.id] = r.type_id;
  for (size_t i = 0; i < rooms.data.size(); ++i)
    if (rooms.data[i]) s.truth.data[i] = uint16_t(type_of[rooms.data[i]]);
  return s;
}

Result<std::vector<RoomTypeTrainingScene>> GeneratedEvidenceScenes(const std::vector<uint64_t>& seeds, const ViewClassifier& second_level,
                                                                   const KnnClassifier& room_knn, double max_range_m,
                                                                   double min_object_fraction) {
  const LabelLevel level = SecondLevel();
  const std::vector<bool> object_classes = RoomObjectClasses(level.class_names);
  const TrainingViewsOptions views;
  std::vector<Result<RoomTypeTrainingScene>> out(seeds.size(), Result<RoomTypeTrainingScene>(Status::Internal("not built")));
  tbb::parallel_for(size_t(0), seeds.size(), [&](size_t k) {
    Result<RoomTypeTrainingScene> s = RoomTypeSceneFromApartment(seeds[k]);
    if (!s.ok()) {
      out[k] = s.status();
      return;
    }
    const Status st = ForEachApartmentView(seeds[k], views, [&](const LabelledView& v) {
      Result<ViewClassification> c = second_level.Classify(*v.view);
      if (!c.ok()) return c.status();
      const RoomViewRecord r = MakeRoomViewRecord(v, PixelLabels(c->superpixels, c->tree_labels), level.num_classes(), object_classes, max_range_m);
      s->views.push_back(RoomViewEvidence(room_knn, r, min_object_fraction));
      return Status::Ok();
    });
    out[k] = st.ok() ? std::move(s) : Result<RoomTypeTrainingScene>(st);
  });
  std::vector<RoomTypeTrainingScene> scenes;
  for (auto& r : out) {
    if (!r.ok()) return r.status();
    scenes.push_back(std::move(r).value());
  }
  return scenes;
}

Result<std::vector<RoomTypeTrainingScene>> PlanEvidenceScenes(const std::vector<std::string>& plans, const ViewClassifier& second_level,
                                                              const KnnClassifier& room_knn, double max_range_m,
                                                              double min_object_fraction, int* skipped) {
  const LabelLevel level = SecondLevel();
  const std::vector<bool> object_classes = RoomObjectClasses(level.class_names);
  const TrainingViewsOptions views;
  struct Unit {
    std::optional<RoomTypeTrainingScene> scene;
    Status status = Status::Ok();
  };
  std::vector<Unit> units(plans.size());
  tbb::parallel_for(size_t(0), plans.size(), [&](size_t k) {
    Unit& u = units[k];
    Result<Apartment> apartment = TrainingPlanApartment(plans[k], k);
    if (!apartment.ok()) return;
    RoomTypeTrainingScene s = RoomTypeSceneOf(*apartment);
    u.status = ForEachViewOfApartment(*apartment, kPlanViewSeedBase + k, views, [&](const LabelledView& v) {
      Result<ViewClassification> c = second_level.Classify(*v.view);
      if (!c.ok()) return c.status();
      const RoomViewRecord r = MakeRoomViewRecord(v, PixelLabels(c->superpixels, c->tree_labels), level.num_classes(), object_classes, max_range_m);
      s.views.push_back(RoomViewEvidence(room_knn, r, min_object_fraction));
      return Status::Ok();
    });
    if (u.status.ok()) u.scene = std::move(s);
  });
  std::vector<RoomTypeTrainingScene> scenes;
  int missing = 0;
  for (Unit& u : units) {
    SEMVOX_RETURN_IF_ERROR(u.status);
    if (u.scene) scenes.push_back(std::move(*u.scene));
    else ++missing;
  }
  if (skipped) *skipped = missing;
  return scenes;
}

ObjectRoomCounts CountApartmentObjects(const Apartment& a) {
  ObjectRoomCounts c;
  for (const RoomGt& r : a.rooms) {
    if (r.type_id < 1 || r.type_id > kRoomTypeLabels) continue;
    c.rooms[size_t(r.type_id - 1)] += 1;
    std::vector<bool> seen(kNumNyu40, false);
    for (const ObjectGt& o : a.objects)
      if (o.room == r.id && o.label > 0 && o.label < kNumNyu40) seen[size_t(o.label)] = true;
    for (int k = 1; k < kNumNyu40; ++k)
      if (seen[size_t(k)]) c.with_object[size_t(k)][size_t(r.type_id - 1)] += 1;
    const std::vector<int>& fixtures = R2vFixtureLabels();
    if (std::none_of(fixtures.begin(), fixtures.end(), [&](int k) { return seen[size_t(k)]; }))
      c.without_fixture[size_t(r.type_id - 1)] += 1;
  }
  return c;
}

bool AddRoomKnnRow(const LabelledView& view, const Image<int32_t>& classes, int num_classes, std::vector<float>* x,
                   std::vector<int>* y) {
  if (view.room_type < 1 || view.room_type > kNumRoomTypeClasses) return false;
  const std::vector<float> d = RoomViewDescriptor(*view.view, classes, num_classes);
  x->insert(x->end(), d.begin(), d.end());
  y->push_back(view.room_type - 1);
  return true;
}

Result<Apartment> TrainingPlanApartment(const std::string& plan, size_t k) {
  int unclosed = 0;
  Result<PlanLayout> layout = LayoutOfR2vPlan(plan, &unclosed);
  if (!layout.ok()) return layout.status();
  PlanApartmentOptions options;
  options.seed = kPlanViewSeedBase + k;
  return ApartmentFromLayout(*layout, options);
}

Result<RoomKnnRows> RoomTypeKnnRows(const std::vector<uint64_t>& seeds, const std::vector<std::string>& plans,
                                    const ViewClassifier* classifier) {
  const LabelLevel level = SecondLevel();
  const TrainingViewsOptions views;
  struct Unit {
    std::vector<float> x;
    std::vector<int> y;
    Status status = Status::Ok();
    bool skipped = false;
  };
  std::vector<Unit> units(seeds.size() + plans.size());
  auto add = [&](Unit* u) {
    return [&level, classifier, u](const LabelledView& v) {
      if (v.room_type < 1 || v.room_type > kNumRoomTypeClasses) return Status::Ok();  // Before classifying.
      Image<int32_t> classes;
      if (classifier) {
        Result<ViewClassification> c = classifier->Classify(*v.view);
        if (!c.ok()) return c.status();
        classes = PixelLabels(c->superpixels, c->union_labels);
      } else {
        classes = level.Map(*v.nyu40);
      }
      AddRoomKnnRow(v, classes, level.num_classes(), &u->x, &u->y);
      return Status::Ok();
    };
  };
  tbb::parallel_for(size_t(0), units.size(), [&](size_t i) {
    Unit& u = units[i];
    if (i < seeds.size()) {
      u.status = ForEachApartmentView(seeds[i], views, add(&u));
      return;
    }
    const size_t k = i - seeds.size();
    Result<Apartment> apartment = TrainingPlanApartment(plans[k], k);
    if (!apartment.ok()) {
      u.skipped = true;
      return;
    }
    u.status = ForEachViewOfApartment(*apartment, kPlanViewSeedBase + k, views, add(&u));
  });
  RoomKnnRows rows;
  for (size_t i = 0; i < units.size(); ++i) {
    SEMVOX_RETURN_IF_ERROR(units[i].status);
    rows.x.insert(rows.x.end(), units[i].x.begin(), units[i].x.end());
    rows.y.insert(rows.y.end(), units[i].y.begin(), units[i].y.end());
    (i < seeds.size() ? rows.generated_rows : rows.plan_rows) += int(units[i].y.size());
    if (i >= seeds.size()) ++(units[i].skipped ? rows.plans_skipped : rows.plans_used);
  }
  return rows;
}

Result<ObjectRoomCounts> CountR2vFixtures(const std::string& dir, int max_plans, int* plans_used) {
  std::vector<std::string> files = ListR2vPlans(dir);
  if (files.empty())
    return Status::InvalidInput(FileError(dir, "no plan_*.txt (R2V plans) found", "pass the r2v folder of ../shared/data"));
  if (max_plans >= 0 && files.size() > size_t(max_plans)) files.resize(size_t(max_plans));
  ObjectRoomCounts counts;
  int used = 0;
  for (const std::string& f : files) {
    struct Item {
      double x0, y0, x1, y1;
      std::string category;
    };
    std::vector<Item> items;
    std::ifstream in(f);
    std::string line;
    double max_x = 0, max_y = 0;
    while (std::getline(in, line)) {
      std::istringstream ls(line);
      Item it;
      if (!(ls >> it.x0 >> it.y0 >> it.x1 >> it.y1 >> it.category)) continue;
      if (!std::isfinite(it.x0) || !std::isfinite(it.y0) || !std::isfinite(it.x1) || !std::isfinite(it.y1) || it.x0 < 0 ||
          it.y0 < 0 || it.x1 < 0 || it.y1 < 0 || it.x0 > 1e4 || it.y0 > 1e4 || it.x1 > 1e4 || it.y1 > 1e4)
        continue;
      max_x = std::max({max_x, it.x0, it.x1}), max_y = std::max({max_y, it.y0, it.y1});
      items.push_back(it);
    }
    if (items.empty()) continue;
    // Plan pixels as they are; walls and doors drawn 3 px thick as barriers.
    const int W = int(max_x) + 8, H = int(max_y) + 8;
    auto P = [](double x, double y) { return cv::Point(int(std::lround(x)) + 3, int(std::lround(y)) + 3); };
    cv::Mat1b barriers(H, W, uchar(0));
    for (const Item& it : items)
      if (it.category == "wall" || it.category == "door") cv::line(barriers, P(it.x0, it.y0), P(it.x1, it.y1), 255, 3);
    cv::Mat1i region(H, W, 0);
    std::vector<int> region_type(1, 0);
    for (const Item& it : items) {
      const int type = R2vRoomTypeId(it.category);
      if (!type) continue;
      const cv::Point c = P(0.5 * (it.x0 + it.x1), 0.5 * (it.y0 + it.y1));
      if (c.x < 0 || c.y < 0 || c.x >= W || c.y >= H || barriers(c)) continue;
      if (const int r = region(c)) {  // A second label in the same region: keep the first unless it disagrees.
        if (region_type[size_t(r)] != type) region_type[size_t(r)] = -1;
        continue;
      }
      cv::Mat1b mask(H + 2, W + 2, uchar(0));
      barriers.copyTo(mask(cv::Rect(1, 1, W, H)));
      cv::Mat1b scratch = barriers.clone();
      cv::floodFill(scratch, mask, c, 128, nullptr, 0, 0, 4 | (255 << 8) | cv::FLOODFILL_MASK_ONLY);
      const cv::Mat1b filled = (mask(cv::Rect(1, 1, W, H)) == 255) & ~barriers;
      bool border = false;  // The outside of a plan that is not closed.
      for (int x = 0; x < W && !border; ++x) border = filled(0, x) || filled(H - 1, x);
      for (int y = 0; y < H && !border; ++y) border = filled(y, 0) || filled(y, W - 1);
      if (border) continue;
      region_type.push_back(type);
      region.setTo(int(region_type.size() - 1), filled);
    }
    if (region_type.size() <= 1) continue;
    ++used;
    std::vector<std::vector<bool>> has(region_type.size(), std::vector<bool>(kNumNyu40, false));
    for (const Item& it : items) {
      const int k = R2vFixtureLabel(it.category);
      if (!k) continue;
      const cv::Point c = P(0.5 * (it.x0 + it.x1), 0.5 * (it.y0 + it.y1));
      if (c.x < 0 || c.y < 0 || c.x >= W || c.y >= H) continue;
      if (const int r = region(c)) has[size_t(r)][size_t(k)] = true;
    }
    for (size_t r = 1; r < region_type.size(); ++r) {
      const int t = region_type[r];
      if (t < 1) continue;  // Conflicting labels: skipped.
      counts.rooms[size_t(t - 1)] += 1;
      bool any = false;
      for (int k : R2vFixtureLabels())
        if (has[r][size_t(k)]) counts.with_object[size_t(k)][size_t(t - 1)] += 1, any = true;
      if (!any) counts.without_fixture[size_t(t - 1)] += 1;
    }
  }
  if (plans_used) *plans_used = used;
  return counts;
}

std::vector<Dist> CombinedObjectStatistics(const ObjectRoomCounts& generator, const ObjectRoomCounts* r2v) {
  std::vector<Dist> table = ObjectTypeStatistics(generator);
  if (!r2v) return table;
  ObjectRoomCounts pooled = generator;
  pooled.Add(*r2v);
  const std::vector<Dist> fixtures = ObjectTypeStatistics(pooled);
  for (int k : R2vFixtureLabels()) table[size_t(k)] = fixtures[size_t(k)];
  return table;
}

namespace {

// Adds the object counts of generated apartment `seed` (default options) to `counts`.
Status AddGeneratedApartmentObjects(uint64_t seed, ObjectRoomCounts* counts) {
  ApartmentOptions ao;
  ao.seed = seed;
  Result<Apartment> a = GenerateApartment(ao);
  if (!a.ok()) return a.status();
  counts->Add(CountApartmentObjects(*a));
  return Status::Ok();
}

}  // namespace

Status RefreshR2vFixtureStatistics(const std::vector<uint64_t>& statistics_seeds, const std::string& r2v_dir, int r2v_plans,
                                   RoomTypeModel* model, int* plans_used) {
  ObjectRoomCounts gen;
  for (uint64_t seed : statistics_seeds) SEMVOX_RETURN_IF_ERROR(AddGeneratedApartmentObjects(seed, &gen));
  Result<ObjectRoomCounts> r2v = CountR2vFixtures(r2v_dir, r2v_plans, plans_used);
  if (!r2v.ok()) return r2v.status();
  const std::vector<Dist> table = CombinedObjectStatistics(gen, &*r2v);
  if (model->object_type.size() != table.size())
    return Status::InvalidInput("room-type model: " + std::to_string(model->object_type.size()) + " object rows, expected " +
                                std::to_string(table.size()));
  for (int k : R2vFixtureLabels()) model->object_type[size_t(k)] = table[size_t(k)];
  ObjectRoomCounts pooled = gen;
  pooled.Add(*r2v);
  model->no_fixture_log_prob = NoFixtureLogProb(pooled);
  return Status::Ok();
}

RoomViewRecord MakeRoomViewRecord(const LabelledView& v, const Image<int32_t>& predicted, int num_classes,
                                  const std::vector<bool>& object_classes, double max_range_m) {
  RoomViewRecord r;
  r.seed = v.seed;
  r.geometry.position = v.view->world_from_camera.translation();
  const Eigen::Vector3d axis = v.view->world_from_camera.linear() * Eigen::Vector3d::UnitZ();
  r.geometry.yaw_rad = std::atan2(axis.y(), axis.x());
  r.geometry.hfov_rad = 2 * std::atan(0.5 * v.view->camera.width / v.view->camera.fx);
  r.geometry.max_range_m = max_range_m;
  r.descriptor = RoomViewDescriptor(*v.view, predicted, num_classes);
  r.object_fraction = ObjectPixelFraction(*v.view, predicted, object_classes);
  return r;
}

namespace {

std::vector<bool> ObjectClassesOf(const LabelLevel& level) {
  std::vector<bool> out;
  for (const std::string& name : level.class_names)
    out.push_back(name != "wall" && name != "floor" && name != "ceiling" && name != "window" && name != "door");
  return out;
}

}  // namespace

ViewRoomEvidence RoomViewEvidence(const KnnClassifier& knn, const RoomViewRecord& r, double min_object_fraction) {
  ViewRoomEvidence e = r.geometry;
  const std::vector<double> p = RoomTypeProbabilities(knn, r.descriptor, r.object_fraction, min_object_fraction);
  for (int y = 0; y < kRoomTypeLabels && y < int(p.size()); ++y) e.p[size_t(y)] = p[size_t(y)];
  return e;
}

Result<KnnClassifier> RoomKnnWithout(const std::vector<float>& room_rows, const std::vector<int>& room_labels,
                                     const std::vector<uint64_t>& room_row_seeds, int descriptor_dims,
                                     const std::vector<uint64_t>& exclude_seeds) {
  if (room_labels.size() != room_row_seeds.size() || room_rows.size() != room_labels.size() * size_t(descriptor_dims))
    return Status::InvalidInput("room-type k-NN: room rows, labels and seeds differ in count");
  std::vector<float> rows;
  std::vector<int> labels;
  for (size_t i = 0; i < room_labels.size(); ++i) {
    if (std::find(exclude_seeds.begin(), exclude_seeds.end(), room_row_seeds[i]) != exclude_seeds.end()) continue;
    rows.insert(rows.end(), room_rows.begin() + long(i * size_t(descriptor_dims)), room_rows.begin() + long((i + 1) * size_t(descriptor_dims)));
    labels.push_back(room_labels[i]);
  }
  return KnnClassifier::Train(rows, descriptor_dims, labels, kRoomTypeLabels, KnnOptions{});
}

Status ClassifiedApartmentRecords(uint64_t seed, const TrainingViewsOptions& views, const ViewClassifier& second_level,
                                  double max_range_m, std::vector<RoomViewRecord>* records, std::vector<float>* truth_rows,
                                  std::vector<int>* truth_labels) {
  const LabelLevel level = SecondLevel();
  const std::vector<bool> object_classes = ObjectClassesOf(level);
  return ForEachApartmentView(seed, views, [&](const LabelledView& v) {
    if (records) {
      Result<ViewClassification> c = second_level.Classify(*v.view);
      if (!c.ok()) return c.status();
      const Image<int32_t> predicted = PixelLabels(c->superpixels, c->tree_labels);
      records->push_back(MakeRoomViewRecord(v, predicted, level.num_classes(), object_classes, max_range_m));
    }
    if (truth_rows && truth_labels && v.room_type >= 1 && v.room_type <= kRoomTypeLabels) {
      const std::vector<float> d = RoomViewDescriptor(*v.view, level.Map(*v.nyu40), level.num_classes());
      truth_rows->insert(truth_rows->end(), d.begin(), d.end());
      truth_labels->push_back(v.room_type - 1);
    }
    return Status::Ok();
  });
}

Result<std::vector<ViewRoomEvidence>> ClassifiedApartmentViews(uint64_t seed, const TrainingViewsOptions& views,
                                                               const ViewClassifier& second_level,
                                                               const KnnClassifier& room_knn, double max_range_m) {
  std::vector<RoomViewRecord> records;
  SEMVOX_RETURN_IF_ERROR(ClassifiedApartmentRecords(seed, views, second_level, max_range_m, &records, nullptr, nullptr));
  std::vector<ViewRoomEvidence> out;
  for (const RoomViewRecord& r : records) out.push_back(RoomViewEvidence(room_knn, r, 0.02));
  return out;
}

Result<std::vector<RoomTypeTrainingScene>> LeaveOneOutEvidenceScenes(const std::vector<RoomViewRecord>& records,
                                                                     const std::vector<float>& room_rows,
                                                                     const std::vector<int>& room_labels,
                                                                     const std::vector<uint64_t>& room_row_seeds,
                                                                     int descriptor_dims, double min_object_fraction,
                                                                     const std::map<uint64_t, RoomTypeTrainingScene>* prepared) {
  std::vector<uint64_t> evidence_seeds;
  for (const RoomViewRecord& r : records)
    if (std::find(evidence_seeds.begin(), evidence_seeds.end(), r.seed) == evidence_seeds.end()) evidence_seeds.push_back(r.seed);
  std::vector<RoomTypeTrainingScene> scenes;
  for (uint64_t seed : evidence_seeds) {
    Result<KnnClassifier> knn = RoomKnnWithout(room_rows, room_labels, room_row_seeds, descriptor_dims, {seed});
    if (!knn.ok()) return knn.status();
    RoomTypeTrainingScene s;
    if (prepared && prepared->count(seed)) {
      s = prepared->at(seed);
      s.views.clear();
    } else {
      Result<RoomTypeTrainingScene> made = RoomTypeSceneFromApartment(seed);
      if (!made.ok()) return made.status();
      s = std::move(made).value();
    }
    for (const RoomViewRecord& r : records)
      if (r.seed == seed) s.views.push_back(RoomViewEvidence(*knn, r, min_object_fraction));
    scenes.push_back(std::move(s));
  }
  return scenes;
}

namespace {

// The mean of options.ssvm_runs SSVM directions (seeds ssvm.seed, ssvm.seed + 1, ...), each scaled so that its
// largest weight is 1: one stochastic run's direction moves with its seed's visiting order.
RoomTypeWeights MeanSsvmDirection(const std::vector<RoomTypeTrainingScene>& scenes, const RoomTypeModel& model,
                                  const RoomTypeVariant& variant, const RoomTypeTrainingOptions& options) {
  const int runs = std::max(1, options.ssvm_runs);
  if (runs == 1) return LearnWeightsSsvm(scenes, model, variant, options.crf, options.ssvm);
  std::array<double, 2 + kNumObjectGroups> sum{};
  for (int r = 0; r < runs; ++r) {
    SsvmOptions ssvm = options.ssvm;
    ssvm.seed = options.ssvm.seed + uint64_t(r);
    const RoomTypeWeights w = LearnWeightsSsvm(scenes, model, variant, options.crf, ssvm);
    std::array<double, 2 + kNumObjectGroups> f{w.scene, w.objects[0], w.objects[1], w.objects[2], w.objects[3], w.homogeneity};
    const double largest = *std::max_element(f.begin(), f.end());
    if (largest <= 0) continue;  // No direction (CalibrateWeightScale falls back to the scene term).
    for (size_t k = 0; k < f.size(); ++k) sum[k] += f[k] / largest / runs;
  }
  RoomTypeWeights mean;
  mean.scene = sum[0];
  for (int g = 0; g < kNumObjectGroups; ++g) mean.objects[size_t(g)] = sum[size_t(1 + g)];
  mean.homogeneity = sum[1 + kNumObjectGroups];
  return mean;
}

}  // namespace

std::string LearnRoomTypeEvidenceTerms(const std::vector<RoomTypeTrainingScene>& scenes, const std::vector<RoomTypeVariant>& variants,
                                       const RoomTypeTrainingOptions& options, RoomTypeModel* model,
                                       const std::vector<RoomTypeTrainingScene>* calibration) {
  LearnConfusion(scenes, model);
  const std::vector<RoomTypeTrainingScene>& calibration_scenes = calibration && !calibration->empty() ? *calibration : scenes;
  std::ostringstream rep;
  for (const RoomTypeVariant& v : variants) {
    const RoomTypeWeights direction = MeanSsvmDirection(scenes, *model, v, options);
    RoomTypeCrfOptions calib = options.crf;  // Shorter chains for the scale search.
    calib.burn_in_sweeps = 10, calib.sample_sweeps = 30;
    double scale = 1;
    const RoomTypeWeights w =
        CalibrateWeightScale(calibration_scenes, *model, v, direction, calib, {1, 3, 10, 30, 100}, &scale, options.shapes);
    model->SetWeights(v, w);
    rep << v.Name() << " (SSVM direction";
    if (options.ssvm_runs > 1) rep << ", mean of " << options.ssvm_runs << " runs";
    rep << " x " << scale << (&calibration_scenes != &scenes ? ", scale on held-out apartments" : "") << "): w_c " << w.scene << " w_obj " << w.objects[0] << " " << w.objects[1] << " " << w.objects[2] << " "
        << w.objects[3] << " w_hom " << w.homogeneity << "\n";
  }
  model->dense = LearnDenseCrfParams(scenes, *model, options.crf);
  rep << "dense CRF: w1 " << model->dense.w_appearance << " theta_alpha " << model->dense.theta_alpha_m << " w2 "
      << model->dense.w_smooth << " theta_gamma " << model->dense.theta_gamma_m << "\n";
  return rep.str();
}

Result<RoomTypeModel> TrainRoomTypeModel(const std::vector<RoomViewRecord>& records, const std::vector<float>& room_rows,
                                         const std::vector<int>& room_labels, const std::vector<uint64_t>& room_row_seeds,
                                         int descriptor_dims, const std::vector<uint64_t>& statistics_seeds,
                                         const RoomTypeTrainingOptions& options, RoomTypeTrainingSummary* summary) {
  RoomTypeTrainingSummary local;
  RoomTypeTrainingSummary& sum = summary ? *summary : local;
  if (room_labels.size() != room_row_seeds.size() || room_rows.size() != room_labels.size() * size_t(descriptor_dims))
    return Status::InvalidInput("room-type CRF training: room rows, labels and seeds differ in count");
  RoomTypeModel model = RoomTypeModel::Uninformative();
  // Object statistics (Eq. 5) and homogeneity statistics (Fig. 6) from the generator's ground truth.
  ObjectRoomCounts gen;
  std::vector<RoomTypeTrainingScene> truth_scenes;
  for (uint64_t seed : statistics_seeds) {
    SEMVOX_RETURN_IF_ERROR(AddGeneratedApartmentObjects(seed, &gen));
    Result<RoomTypeTrainingScene> s = RoomTypeSceneFromApartment(seed);
    if (!s.ok()) return s.status();
    truth_scenes.push_back(std::move(s).value());
  }
  sum.statistics_apartments = int(statistics_seeds.size());
  ObjectRoomCounts r2v;
  bool have_r2v = false;
  if (!options.r2v_dir.empty()) {
    Result<ObjectRoomCounts> c = CountR2vFixtures(options.r2v_dir, options.r2v_plans, &sum.r2v_plans);
    if (c.ok()) r2v = *c, have_r2v = true;
  }
  model.object_type = CombinedObjectStatistics(gen, have_r2v ? &r2v : nullptr);
  ObjectRoomCounts pooled = gen;
  if (have_r2v) pooled.Add(r2v);
  model.no_fixture_log_prob = NoFixtureLogProb(pooled);
  LearnHomogeneityStatistics(truth_scenes, options.crf, &model);
  // Evidence apartments: per-view distributions from a k-NN without the apartment's own rows.
  Result<std::vector<RoomTypeTrainingScene>> scenes =
      LeaveOneOutEvidenceScenes(records, room_rows, room_labels, room_row_seeds, descriptor_dims, options.min_object_fraction, nullptr);
  if (!scenes.ok()) return scenes.status();
  sum.evidence_scenes = int(scenes->size());
  sum.report = LearnRoomTypeEvidenceTerms(*scenes, AllRoomTypeVariants(), options, &model);
  std::ostringstream prov;
  prov << "semvox train: object and homogeneity statistics from " << statistics_seeds.size() << " generated apartments"
       << (have_r2v ? " + " + std::to_string(sum.r2v_plans) + " R2V plans (fixtures)" : std::string()) << "; confusion, SSVM weights and "
       << "dense-CRF parameters from " << scenes->size() << " apartments' classified views (leave-one-apartment-out room k-NN)";
  model.provenance = prov.str();
  return model;
}

}  // namespace semvox
