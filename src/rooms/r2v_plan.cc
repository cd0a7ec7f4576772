#include "rooms/r2v_plan.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/labels.h"

namespace semvox {

int R2vRoomTypeId(const std::string& name) {
  static const std::map<std::string, int> kTypes = {{"bathroom", 1}, {"restroom", 1}, {"bedroom", 2},  {"corridor", 4},
                                                    {"kitchen", 6},  {"washing_room", 7}, {"living_room", 8}, {"stairs", 10},
                                                    {"closet", 11},  {"PS", 11},       {"balcony", 12}};
  const auto it = kTypes.find(name);
  return it == kTypes.end() ? 0 : it->second;
}

bool IsR2vRoomLabel(const std::string& name) {
  return R2vRoomTypeId(name) > 0 || name == "entrance" || name == "special";
}

namespace {

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

Result<R2vPlan> ReadR2vPlan(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Status::InvalidInput(FileError(path, "cannot be read", "check the path"));
  R2vPlan plan;
  std::string line;
  std::vector<double> door_lengths, swing_doors, toilets;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    R2vItem it;
    if (!(ls >> it.x0 >> it.y0 >> it.x1 >> it.y1 >> it.category)) continue;
    const bool finite = std::isfinite(it.x0) && std::isfinite(it.y0) && std::isfinite(it.x1) && std::isfinite(it.y1);
    if (!finite || std::min({it.x0, it.y0, it.x1, it.y1}) < 0 || std::max({it.x0, it.y0, it.x1, it.y1}) > 1e4) continue;
    if (!(ls >> it.kind)) it.kind = 0;
    if (it.category == "door") {
      const double length = std::hypot(it.x1 - it.x0, it.y1 - it.y0);
      door_lengths.push_back(length);
      if (it.kind == 1 || it.kind == 2) swing_doors.push_back(length);
    }
    if (it.category == "toilet") toilets.push_back(std::max(std::fabs(it.x1 - it.x0), std::fabs(it.y1 - it.y0)));
    plan.items.push_back(it);
  }
  if (plan.items.empty())
    return Status::InvalidInput(FileError(path, "no line of the form `x0 y0 x1 y1 category ...`: not an R2V plan",
                                          "pass a plan_*.txt of ../shared/data/r2v"));
  if (door_lengths.empty() || Median(door_lengths) < 1)
    return Status::InvalidInput(FileError(path, "no door, so no scale (doors and toilets give the plan its size)",
                                          "add the plan's doors as `door` lines"));
  plan.doors = int(door_lengths.size());
  // Scale: swing doors (kind 1 or 2) are 0.7 m wide and toilets 0.72 m long (the geometric mean of the two
  // when a plan has both); a plan with neither takes its median opening as 0.8 m. All openings together are a
  // poor ruler: kind 3 are double and sliding doors of 1.3-1.8 m, and where they are the majority the median
  // shrinks a flat to a third of its area.
  std::vector<double> log_scales;
  if (Median(swing_doors) >= 1) log_scales.push_back(std::log(kR2vSwingDoorWidthM / Median(swing_doors)));
  if (Median(toilets) >= 1) log_scales.push_back(std::log(kR2vToiletLengthM / Median(toilets)));
  double mean = 0;
  for (double l : log_scales) mean += l / double(log_scales.size());
  plan.metres_per_unit = log_scales.empty() ? 0.8 / Median(door_lengths) : std::exp(mean);
  return plan;
}

R2vRooms RasteriseR2vRooms(const R2vPlan& plan, double resolution_m) {
  R2vRooms out;
  out.resolution_m = resolution_m;
  out.type_id.assign(1, 0);
  out.connections.assign(1, {});
  double max_x = 0, max_y = 0;
  for (const R2vItem& it : plan.items) max_x = std::max({max_x, it.x0, it.x1}), max_y = std::max({max_y, it.y0, it.y1});
  const double s = plan.metres_per_unit / resolution_m;  // Raster pixels per plan unit.
  const int W = int(max_x * s) + 12, H = int(max_y * s) + 12;
  if (!(s > 0) || W > 20000 || H > 20000) return out;
  constexpr int kMargin = 5;
  out.origin_m = -(kMargin + 0.5) * resolution_m;  // Plan point x lands in pixel round(x s) + kMargin.
  auto P = [&](double x, double y) { return cv::Point(int(std::lround(x * s)) + kMargin, int(std::lround(y * s)) + kMargin); };
  cv::Mat1b barriers(H, W, uchar(0));
  for (const R2vItem& it : plan.items)
    if (it.category == "wall" || it.category == "door") cv::line(barriers, P(it.x0, it.y0), P(it.x1, it.y1), 255, 2);
  cv::Mat1i region(H, W, 0);
  for (const R2vItem& it : plan.items) {
    if (!IsR2vRoomLabel(it.category)) continue;
    const int type = R2vRoomTypeId(it.category);
    const cv::Point c = P(0.5 * (it.x0 + it.x1), 0.5 * (it.y0 + it.y1));
    if (c.x < 0 || c.y < 0 || c.x >= W || c.y >= H || barriers(c)) continue;
    if (const int r = region(c)) {  // A second label in the same region: untyped when they disagree.
      if (out.type_id[size_t(r)] != type) out.type_id[size_t(r)] = 0;
      continue;
    }
    cv::Mat1b mask(H + 2, W + 2, uchar(0));
    barriers.copyTo(mask(cv::Rect(1, 1, W, H)));
    cv::Mat1b scratch = barriers.clone();
    cv::floodFill(scratch, mask, c, 128, nullptr, 0, 0, 4 | (255 << 8) | cv::FLOODFILL_MASK_ONLY);
    const cv::Mat1b filled = (mask(cv::Rect(1, 1, W, H)) == 255) & ~barriers;
    bool border = false;
    for (int x = 0; x < W && !border; ++x) border = filled(0, x) || filled(H - 1, x);
    for (int y = 0; y < H && !border; ++y) border = filled(y, 0) || filled(y, W - 1);
    if (border || out.type_id.size() >= 65535) continue;
    out.type_id.push_back(type);
    region.setTo(int(out.type_id.size() - 1), filled);
  }
  const size_t n = out.type_id.size();
  std::vector<std::set<int>> joined(n);
  for (const R2vItem& it : plan.items) {
    if (it.category != "door") continue;
    // The door line and 2-3 px either side, drawn in its own bounding box (with a margin wider than the line).
    const cv::Point a = P(it.x0, it.y0), b = P(it.x1, it.y1);
    const cv::Rect box = cv::Rect(cv::Point(std::min(a.x, b.x) - 6, std::min(a.y, b.y) - 6),
                                  cv::Point(std::max(a.x, b.x) + 7, std::max(a.y, b.y) + 7)) &
                         cv::Rect(0, 0, W, H);
    if (box.empty()) continue;
    cv::Mat1b door(box.size(), uchar(0));
    cv::line(door, a - box.tl(), b - box.tl(), 255, 6);
    std::set<int> ids;
    for (int y = 0; y < box.height; ++y) {
      const uchar* d = door.ptr<uchar>(y);
      const int* r = region.ptr<int>(y + box.y) + box.x;
      for (int x = 0; x < box.width; ++x)
        if (d[x] && r[x]) ids.insert(r[x]);
    }
    for (int a : ids)
      for (int b : ids)
        if (a != b) joined[size_t(a)].insert(b);
  }
  out.connections.assign(n, {});
  for (size_t r = 1; r < n; ++r) out.connections[r].assign(joined[r].begin(), joined[r].end());
  out.ids = ImageU16(W, H, 1, 0);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) out.ids.at(x, y) = uint16_t(region(y, x));
  return out;
}

std::vector<std::string> ListR2vPlans(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind("plan_", 0) == 0 && it->path().extension() == ".txt") files.push_back(it->path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<R2vRoomSample> R2vRoomShapes(const std::vector<std::string>& files, int* skipped) {
  std::vector<R2vRoomSample> out;
  int bad = 0;
  for (size_t f = 0; f < files.size(); ++f) {
    Result<R2vPlan> plan = ReadR2vPlan(files[f]);
    if (!plan.ok()) {
      ++bad;
      continue;
    }
    const R2vRooms rooms = RasteriseR2vRooms(*plan);
    const int n = int(rooms.type_id.size()) - 1;
    const std::vector<RoomShape> shapes = MeasureRoomShapes(rooms.ids, n, rooms.resolution_m, &rooms.connections);
    std::vector<int> index(size_t(n) + 1, -1);  // Room id -> sample index.
    for (int r = 1; r <= n; ++r)
      if (rooms.type_id[size_t(r)] > 0 && shapes[size_t(r - 1)].area_m2 > 0) {
        index[size_t(r)] = int(out.size());
        out.push_back({{rooms.type_id[size_t(r)], shapes[size_t(r - 1)], {}}, int(f)});
      }
    for (int r = 1; r <= n; ++r)
      if (index[size_t(r)] >= 0)
        for (const int o : rooms.connections[size_t(r)])
          if (o >= 1 && o <= n && index[size_t(o)] >= 0) out[size_t(index[size_t(r)])].sample.neighbours.push_back(index[size_t(o)]);
  }
  if (skipped) *skipped = bad;
  return out;
}

Result<RoomShapeModel> TrainRoomShapesFromR2v(const std::string& dir, int train_plans, RoomShapeTrainingReport* report,
                                              const std::vector<int>& features) {
  const std::vector<std::string> files = ListR2vPlans(dir);
  if (files.empty())
    return Status::InvalidInput(FileError(dir, "no plan_*.txt (R2V plans) found", "pass the r2v folder of ../shared/data"));
  const size_t split = std::min(files.size(), size_t(std::max(train_plans, 1)));
  const std::vector<std::string> train(files.begin(), files.begin() + long(split)), val(files.begin() + long(split), files.end());
  RoomShapeTrainingReport r;
  int skipped_train = 0, skipped_val = 0;
  const std::vector<R2vRoomSample> train_rooms = R2vRoomShapes(train, &skipped_train);
  const std::vector<R2vRoomSample> val_rooms = R2vRoomShapes(val, &skipped_val);
  std::vector<RoomShapeSample> samples;
  for (const R2vRoomSample& s : train_rooms) samples.push_back(s.sample);
  RoomShapeModel model = TrainRoomShapeModel(samples, 15, 0.01, features);
  model.adjacency = TrainRoomAdjacency(samples);
  r.train_plans = int(train.size()), r.val_plans = int(val.size()), r.skipped_plans = skipped_train + skipped_val;
  r.train_rooms = int(train_rooms.size()), r.val_rooms = int(val_rooms.size());
  std::ostringstream prov;
  prov << "R2V plans 0-" << split - 1 << " of " << dir.substr(dir.find_last_of('/') + 1) << " (" << r.train_rooms
       << " typed rooms, median door = 0.8 m)";
  model.provenance = prov.str();
  // Validation: the shape alone (argmax of its ratios, a uniform type prior), then with the adjacency term's
  // messages at each weight of RoomShapeTrainingReport::adjacency_weights (rooms of one plan together).
  using Dist = std::array<double, kRoomShapeTypes>;
  std::vector<Dist> ratio(val_rooms.size());
  for (size_t i = 0; i < val_rooms.size(); ++i) ratio[i] = LogLikelihoodRatios(model, val_rooms[i].sample.shape, /*open_plan=*/false);
  auto score = [&](double weight, std::array<std::array<double, kRoomShapeTypes>, kRoomShapeTypes>* confusion, double* room_acc,
                   double* area_acc, double* class_avg) {
    std::vector<Dist> message(val_rooms.size(), Dist{});
    for (size_t a = 0; a < val_rooms.size();) {  // One plan's rooms are consecutive.
      size_t b = a;
      while (b < val_rooms.size() && val_rooms[b].plan == val_rooms[a].plan) ++b;
      std::vector<Dist> evidence(ratio.begin() + long(a), ratio.begin() + long(b));
      std::vector<std::vector<int>> nb(b - a);
      for (size_t i = a; i < b; ++i)
        for (const int j : val_rooms[i].sample.neighbours) nb[i - a].push_back(j - int(a));
      const std::vector<Dist> m = AdjacencyMessages(model, evidence, nb, weight);
      std::copy(m.begin(), m.end(), message.begin() + long(a));
      a = b;
    }
    std::array<std::array<double, kRoomShapeTypes>, kRoomShapeTypes> conf{};
    int right = 0;
    double area = 0, area_right = 0;
    for (size_t i = 0; i < val_rooms.size(); ++i) {
      const R2vRoomSample& s = val_rooms[i];
      int best = -1;
      for (int t = 0; t < kRoomShapeTypes; ++t)
        if (model.types[size_t(t)].rooms > 0 &&
            (best < 0 || ratio[i][size_t(t)] + message[i][size_t(t)] > ratio[i][size_t(best)] + message[i][size_t(best)]))
          best = t;
      if (best < 0) continue;
      const int truth = s.sample.type_id - 1;
      const double a = s.sample.shape.area_m2;
      conf[size_t(truth)][size_t(best)] += a;
      right += best == truth, area += a, area_right += best == truth ? a : 0;
    }
    *room_acc = val_rooms.empty() ? 0 : double(right) / double(val_rooms.size());
    *area_acc = area > 0 ? area_right / area : 0;
    double sum = 0;
    int present = 0;
    for (int t = 0; t < kRoomShapeTypes; ++t) {
      double row = 0;
      for (double v : conf[size_t(t)]) row += v;
      if (row > 0) sum += conf[size_t(t)][size_t(t)] / row, ++present;
    }
    *class_avg = present ? sum / present : 0;
    if (confusion) *confusion = conf;
  };
  score(0.0, &r.confusion_m2, &r.val_room_accuracy, &r.val_area_accuracy, &r.val_class_average);
  for (const double w : r.adjacency_weights) {
    double room_acc = 0, area_acc = 0, class_avg = 0;
    score(w, nullptr, &room_acc, &area_acc, &class_avg);
    r.adjacency_area_accuracy.push_back(area_acc);
    r.adjacency_class_average.push_back(class_avg);
  }
  if (report) *report = r;
  return model;
}

std::string RoomShapeTrainingReport::ToText() const {
  auto name = [](int t) { return std::string(RoomTypes()[size_t(t + 1)].name); };
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(3);
  o << "room shapes: " << train_rooms << " rooms of " << train_plans << " training plans, " << val_rooms << " rooms of "
    << val_plans << " validation plans (" << skipped_plans << " plans skipped)\n";
  o << "validation, shape alone: rooms " << val_room_accuracy << ", area (pixel) accuracy " << val_area_accuracy
    << ", class average " << val_class_average << "\n";
  for (size_t i = 0; i < adjacency_weights.size() && i < adjacency_area_accuracy.size(); ++i)
    o << "validation, shape + adjacency at weight " << adjacency_weights[i] << ": area accuracy " << adjacency_area_accuracy[i]
      << ", class average " << adjacency_class_average[i] << "\n";
  o << "confusion of the shape alone (rows true, columns predicted, share of the row's area):\n             ";
  for (int p = 0; p < kRoomShapeTypes; ++p) o << ' ' << name(p).substr(0, 5);
  o << "\n";
  for (int t = 0; t < kRoomShapeTypes; ++t) {
    double row = 0;
    for (double v : confusion_m2[size_t(t)]) row += v;
    if (row <= 0) continue;
    o << "  " << name(t);
    for (int u = int(name(t).size()); u < 12; ++u) o << ' ';
    for (int p = 0; p < kRoomShapeTypes; ++p) {
      char cell[16];
      const double v = confusion_m2[size_t(t)][size_t(p)] / row;
      if (v > 0)
        std::snprintf(cell, sizeof cell, " %5.2f", v);
      else
        std::snprintf(cell, sizeof cell, "     .");
      o << cell;
    }
    o << "\n";
  }
  return o.str();
}

}  // namespace semvox
