// Room segmentation on the ipa_room_segmentation test maps (Bormann et al., ICRA 2016), scored with
// their recall / precision, per map and mean, for each method, on the plain and the furnished maps.
//
//   rooms_bench [--data DIR] [--method NAME]... [--KEY VALUE]...
//
// DIR defaults to <source>/../shared/data/ipa_room_seg/test_maps. KEY is a RoomSegmentationOptions or
// FloorPlanOptions field (saddle_ratio, min_room_radius_m, max_opening_width_m, min_room_area_m2,
// min_seed_area_m2, clutter_max_area_m2, max_speck_distance_m). Timing covers floor plan + segmentation.
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "rooms/floor_plan.h"
#include "rooms/room_score.h"
#include "rooms/room_segmentation.h"

namespace fs = std::filesystem;
using namespace semvox;

int main(int argc, char** argv) {
  std::string data = std::string(SEMVOX_SOURCE_DIR) + "/../shared/data/ipa_room_seg/test_maps";
  std::vector<std::string> methods;
  RoomSegmentationOptions seg;
  FloorPlanOptions fp;
  bool per_map = true;
  std::string dump_dir;  // --dump DIR: colour images of each segmentation (room colours, black walls).
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) std::fprintf(stderr, "rooms_bench: %s needs a value\n", a.c_str()), std::exit(2);
      return argv[++i];
    };
    if (a == "--data") data = next();
    else if (a == "--method") methods.push_back(next());
    else if (a == "--brief") per_map = false;
    else if (a == "--dump") dump_dir = next();
    else if (a == "--saddle_ratio") seg.saddle_ratio = std::atof(next().c_str());
    else if (a == "--min_room_radius_m") seg.min_room_radius_m = std::atof(next().c_str());
    else if (a == "--max_opening_width_m") seg.max_opening_width_m = std::atof(next().c_str());
    else if (a == "--min_room_area_m2") seg.min_room_area_m2 = std::atof(next().c_str());
    else if (a == "--min_seed_area_m2") seg.min_seed_area_m2 = std::atof(next().c_str());
    else if (a == "--max_speck_distance_m") seg.max_speck_distance_m = std::atof(next().c_str());
    else if (a == "--clutter_max_area_m2") fp.clutter_max_area_m2 = std::atof(next().c_str());
    else if (a == "--clutter_max_length_m") fp.clutter_max_length_m = std::atof(next().c_str());
    else if (a == "--saddle_ratio_larger") seg.saddle_ratio_larger = std::atof(next().c_str());
    else if (a == "--wall_gap_max_m") seg.wall_gap_max_m = std::atof(next().c_str());
    else if (a == "--wall_gap_ratio") seg.wall_gap_ratio = std::atof(next().c_str());
    else if (a == "--no_fill_clutter") seg.fill_clutter = false;
    else {
      std::fprintf(stderr, "rooms_bench: unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  if (methods.empty()) methods = RoomSegmentationMethodNames();
  std::string error;
  if (!seg.Check(&error) || !fp.Check(&error)) {
    std::fprintf(stderr, "rooms_bench: %s\n", error.c_str());
    return 2;
  }
  std::vector<std::string> maps;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(data, ec)) {
    const std::string name = e.path().filename().string();
    const std::string suffix = "_gt_segmentation.png";
    if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      maps.push_back(name.substr(0, name.size() - suffix.size()));
  }
  if (maps.empty()) {
    std::fprintf(stderr, "rooms_bench: no *_gt_segmentation.png in %s (hint: --data DIR)\n", data.c_str());
    return 2;
  }
  std::sort(maps.begin(), maps.end());
  std::printf("# ipa_room_seg test maps: %zu; recall / precision as Bormann et al. 2016; seconds = floor plan + rooms (wall clock; cpu = process time, less sensitive to load)\n",
              maps.size());
  for (const std::string& method_name : methods) {
    RoomSegmentationOptions o = seg;
    if (!ParseRoomSegmentationMethod(method_name, &o.method)) {
      std::fprintf(stderr, "rooms_bench: unknown method %s\n", method_name.c_str());
      return 2;
    }
    for (const char* variant : {"", "_furnitures"}) {
      double sr = 0, sp = 0, ss = 0, sc = 0;
      for (const std::string& m : maps) {
        auto gt_grey = ReadGreyMap(data + "/" + m + "_gt_segmentation.png");
        auto map_grey = ReadGreyMap(data + "/" + m + variant + ".png");
        if (!gt_grey.ok() || !map_grey.ok()) {
          std::fprintf(stderr, "rooms_bench: %s\n", (gt_grey.ok() ? map_grey.status() : gt_grey.status()).message().c_str());
          return 2;
        }
        const ImageU16 gt = GroundTruthRoomsFromImage(gt_grey.value());
        const auto t0 = std::chrono::steady_clock::now();
        const std::clock_t c0 = std::clock();
        const FloorPlan plan = FloorPlanFromImage(map_grey.value(), 0.05, fp);
        const RoomSegmentation rooms = SegmentRooms(plan, o);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
        const RoomScore score = ScoreRooms(rooms.room_ids, gt);
        if (per_map)
          std::printf("%-14s %-28s recall %.3f precision %.3f rooms %3d (gt %3d) %.3f s\n", method_name.c_str(),
                      (m + variant).c_str(), score.recall, score.precision, score.num_predicted_rooms,
                      score.num_ground_truth_rooms, s);
        if (!dump_dir.empty()) {
          cv::Mat3b img(plan.height(), plan.width(), cv::Vec3b(0, 0, 0));
          for (int y = 0; y < plan.height(); ++y)
            for (int x = 0; x < plan.width(); ++x) {
              const int id = rooms.room_ids.at(x, y);
              if (id) img(y, x) = cv::Vec3b(60 + (id * 97) % 190, 60 + (id * 57) % 190, 60 + (id * 31) % 190);
              else if (plan.at(x, y) == FloorCell::kClutter) img(y, x) = cv::Vec3b(128, 128, 128);
              else if (plan.IsFloor(x, y)) img(y, x) = cv::Vec3b(255, 255, 255);
            }
          cv::imwrite(dump_dir + "/" + method_name + "_" + m + variant + ".png", img);
        }
        sr += score.recall, sp += score.precision, ss += s, sc += cpu;
      }
      const double n = double(maps.size());
      std::printf("MEAN %-14s %-11s recall %.3f precision %.3f  %.3f s/map (cpu %.3f s)\n", method_name.c_str(),
                  *variant ? "furnished" : "plain", sr / n, sp / n, ss / n, sc / n);
    }
  }
  return 0;
}
