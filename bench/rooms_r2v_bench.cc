// Room segmentation on R2V floor plans (Liu et al., "Raster-to-Vector", ICCV 2017) rasterised as 2D maps,
// scored with the recall / precision of Bormann et al. 2016, mean over the plans, for each method.
//
//   rooms_r2v_bench [--data DIR] [--method NAME]... [--limit N] [--fixtures] [--dump DIR]
//
// Rasterisation: a plan has no metric scale, so pixels are scaled to make its median door 0.8 m, at
// 0.05 m per map pixel. Walls are drawn 0.1 m thick. A ground-truth room is the region flood-filled from
// a room label box with walls and doors as barriers (several labels in one region are one room). The
// map's free space is the union of the rooms plus the door openings cut through the walls; the rest is
// occupied. With --fixtures, toilets, bathtubs, sinks and counters become obstacles (a furnished map).
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "rooms/floor_plan.h"
#include "rooms/room_score.h"
#include "rooms/room_segmentation.h"

namespace fs = std::filesystem;
using namespace semvox;

namespace {

struct Item {
  double x0, y0, x1, y1;
  std::string category;
};

bool IsRoomLabel(const std::string& c) {
  static const char* kRooms[] = {"bedroom", "living_room", "kitchen", "bathroom", "washing_room", "restroom",
                                 "corridor", "closet",      "balcony", "PS",       "stairs"};
  return std::find_if(std::begin(kRooms), std::end(kRooms), [&](const char* r) { return c == r; }) != std::end(kRooms);
}

bool IsFixture(const std::string& c) {
  return c == "cooking_counter" || c == "washing_basin" || c == "toilet" || c == "bathtub";
}

struct Rasterised {
  Image<uint8_t> map;  // 0 occupied, 255 free.
  ImageU16 truth;      // Ground-truth rooms.
};

bool Rasterise(const std::vector<Item>& items, bool fixtures, Rasterised* out) {
  std::vector<double> doors;
  double max_x = 0, max_y = 0;
  for (const Item& it : items) {
    if (it.category == "door") doors.push_back(std::hypot(it.x1 - it.x0, it.y1 - it.y0));
    max_x = std::max({max_x, it.x0, it.x1}), max_y = std::max({max_y, it.y0, it.y1});
  }
  if (doors.empty()) return false;
  std::nth_element(doors.begin(), doors.begin() + doors.size() / 2, doors.end());
  const double median_door = doors[doors.size() / 2];
  if (median_door < 5) return false;
  const double s = (0.8 / median_door) / 0.05;  // Map pixels per plan pixel.
  const int W = int(max_x * s) + 12, H = int(max_y * s) + 12;
  auto P = [&](double x, double y) { return cv::Point(int(std::lround(x * s)) + 5, int(std::lround(y * s)) + 5); };
  cv::Mat1b walls(H, W, uchar(0)), barriers(H, W, uchar(0));
  for (const Item& it : items) {
    if (it.category == "wall") cv::line(walls, P(it.x0, it.y0), P(it.x1, it.y1), 255, 2);
    if (it.category == "wall" || it.category == "door")
      cv::line(barriers, P(it.x0, it.y0), P(it.x1, it.y1), 255, 2);
  }
  // Rooms: flood fill from each label box centre inside the barriers.
  cv::Mat1i rooms(H, W, 0);
  int next = 0;
  for (const Item& it : items) {
    if (!IsRoomLabel(it.category)) continue;
    const cv::Point c = P(0.5 * (it.x0 + it.x1), 0.5 * (it.y0 + it.y1));
    if (c.x < 0 || c.y < 0 || c.x >= W || c.y >= H || barriers(c) || rooms(c)) continue;
    cv::Mat1b mask(H + 2, W + 2, uchar(0));
    barriers.copyTo(mask(cv::Rect(1, 1, W, H)));
    cv::Mat1b scratch = barriers.clone();
    cv::floodFill(scratch, mask, c, 128, nullptr, 0, 0, 4 | (255 << 8) | cv::FLOODFILL_MASK_ONLY);
    const cv::Mat1b filled = (mask(cv::Rect(1, 1, W, H)) == 255) & ~barriers;
    // A region touching the image border is the outside (a plan that is not closed): skip it.
    bool border = false;
    for (int x = 0; x < W && !border; ++x) border = filled(0, x) || filled(H - 1, x);
    for (int y = 0; y < H && !border; ++y) border = filled(y, 0) || filled(y, W - 1);
    if (border) continue;
    ++next;
    rooms.setTo(next, filled);
  }
  if (next == 0) return false;
  out->map = Image<uint8_t>(W, H, 1, 0);
  out->truth = ImageU16(W, H, 1, 0);
  cv::Mat1b free_mask = rooms > 0;
  // Door openings between two rooms (or a room and itself) are free in the map.
  for (const Item& it : items) {
    if (it.category != "door") continue;
    cv::Mat1b door(H, W, uchar(0));
    cv::line(door, P(it.x0, it.y0), P(it.x1, it.y1), 255, 2);
    cv::Mat1b grown;
    cv::dilate(free_mask, grown, cv::Mat());
    free_mask |= door & grown;  // R2V walls run on through their doors: the door cuts the opening.
  }
  if (fixtures)
    for (const Item& it : items)
      if (IsFixture(it.category)) cv::rectangle(free_mask, P(it.x0, it.y0), P(it.x1, it.y1), 0, cv::FILLED);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      out->map.at(x, y) = free_mask(y, x) ? 255 : 0;
      out->truth.at(x, y) = uint16_t(rooms(y, x));
    }
  return true;
}

std::vector<Item> ReadPlan(const std::string& path) {
  std::vector<Item> items;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    Item it;
    if (ls >> it.x0 >> it.y0 >> it.x1 >> it.y1 >> it.category) items.push_back(it);
  }
  return items;
}

}  // namespace

int main(int argc, char** argv) {
  std::string data = std::string(SEMVOX_SOURCE_DIR) + "/../shared/data/r2v";
  std::vector<std::string> methods;
  int limit = 1 << 30;
  bool fixtures = false;
  std::string dump_dir;  // Map | ground truth | prediction images of the first 20 plans.
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) std::fprintf(stderr, "rooms_r2v_bench: %s needs a value\n", a.c_str()), std::exit(2);
      return argv[++i];
    };
    if (a == "--data") data = next();
    else if (a == "--method") methods.push_back(next());
    else if (a == "--limit") limit = std::atoi(next().c_str());
    else if (a == "--fixtures") fixtures = true;
    else if (a == "--dump") dump_dir = next();
    else {
      std::fprintf(stderr, "rooms_r2v_bench: unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  if (methods.empty()) methods = RoomSegmentationMethodNames();
  std::vector<std::string> plans;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(data, ec))
    if (e.path().extension() == ".txt" && e.path().filename().string().rfind("plan_", 0) == 0)
      plans.push_back(e.path().string());
  if (plans.empty()) {
    std::fprintf(stderr, "rooms_r2v_bench: no plan_*.txt in %s (hint: --data DIR)\n", data.c_str());
    return 2;
  }
  std::sort(plans.begin(), plans.end());
  if (int(plans.size()) > limit) plans.resize(limit);
  std::vector<Rasterised> maps;
  for (const std::string& p : plans) {
    Rasterised r;
    if (Rasterise(ReadPlan(p), fixtures, &r)) maps.push_back(std::move(r));
  }
  std::printf("# R2V plans: %zu of %zu rasterised at 0.05 m/px (median door = 0.8 m)%s\n", maps.size(), plans.size(),
              fixtures ? ", fixtures as obstacles" : "");
  for (const std::string& name : methods) {
    RoomSegmentationOptions o;
    if (!ParseRoomSegmentationMethod(name, &o.method)) {
      std::fprintf(stderr, "rooms_r2v_bench: unknown method %s\n", name.c_str());
      return 2;
    }
    double sr = 0, sp = 0, ss = 0;
    for (const Rasterised& r : maps) {
      const auto t0 = std::chrono::steady_clock::now();
      const FloorPlan plan = FloorPlanFromImage(r.map, 0.05, FloorPlanOptions());
      const RoomSegmentation rooms = SegmentRooms(plan, o);
      ss += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const RoomScore score = ScoreRooms(rooms.room_ids, r.truth);
      const size_t index = &r - maps.data();
      if (!dump_dir.empty() && index < 20) {
        auto colour = [](int id) { return id ? cv::Vec3b(60 + (id * 97) % 190, 60 + (id * 57) % 190, 60 + (id * 31) % 190) : cv::Vec3b(0, 0, 0); };
        const int W = r.map.width, H = r.map.height;
        cv::Mat3b img(H, 3 * W + 8, cv::Vec3b(0, 0, 255));
        for (int y = 0; y < H; ++y)
          for (int x = 0; x < W; ++x) {
            img(y, x) = cv::Vec3b::all(r.map.at(x, y));
            img(y, W + 4 + x) = colour(r.truth.at(x, y));
            img(y, 2 * W + 8 + x) = colour(rooms.room_ids.at(x, y));
          }
        cv::imwrite(dump_dir + "/r2v_" + name + "_" + std::to_string(index) + ".png", img);
      }
      sr += score.recall, sp += score.precision;
    }
    const double n = double(std::max<size_t>(1, maps.size()));
    std::printf("MEAN %-14s r2v%-10s recall %.3f precision %.3f  %.4f s/plan\n", name.c_str(),
                fixtures ? "+fixtures" : "", sr / n, sp / n, ss / n);
  }
  return 0;
}
