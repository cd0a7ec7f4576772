// A real scan end to end: `semvox run` on the ScanNet studio (scene0000_00, a sparse fused
// colour point cloud from ../shared/data) and `semvox eval --boxes` against its 27 furniture boxes
// (docs/metrics.md, "Real scans: box scores"). Skipped when the data is absent, and in the sanitizer build
// (one run takes 3-8 minutes in Release on 2 cores, depending on load). The per-box table goes to the test log.
//
// The floors below are stated with the value measured on the current models (Release); they are raised
// after retraining. Scores are fractions in [0, 1].
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/ply.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

// ---- Floors (measured on the current models in the comment) ----
// Measured 2026-12-03 with the point-cloud Voxel-CRF weights (models/voxel_crf_cloud.txt), the object
// segments, and the voxels holding scan points kept occupied (semantic.keep_scan_points); before that
// setting in brackets.
constexpr double kMinFloorRecall = 0.95;    // Floor band labelled floor; measured 0.971 with furniture's feet (2026-12-07:
                                            // the floor's upper layer under furniture outside every box; 0.959 with the
                                            // segment model of seeds 110-209), 0.991 (2026-12-06), 0.978 (0.985) before.
constexpr double kMaxWallShare = 0.50;      // Occupied voxels labelled wall; measured 0.281 with wooden wall units
                                            // (2026-12-07), 0.291 with tall furniture no wall
                                            // (2026-12-07), 0.317 with the walls' colour
                                            // (2026-12-06), 0.354 with the walls' margin
                                            // (2026-12-06), 0.375 before, 0.431 (0.546).
constexpr double kMinMeanBoxRecall = 0.55;  // Mean over boxes holding voxels; measured 0.602 with hung wall cabinets
                                            // (semantic.hung_wall_cabinets, 2026-12-07; 0.408 with the segment model of
                                            // seeds 110-209: a retrained segment model is measured here first), 0.583
                                            // with furniture's feet
                                            // (semantic.furniture_feet, 2026-12-07; 0.388 with the segment model of seeds
                                            // 110-209), 0.565 with bars as tables (semantic.bar_tables, 2026-12-07),
                                            // 0.535 with wooden wall units
                                            // (semantic.wooden_wall_units, 2026-12-07; 0.365 with the segment model of
                                            // seeds 110-209), 0.511 with tall furniture no
                                            // wall (semantic.tall_object_walls, 2026-12-07; 0.339 with the segment model
                                            // of seeds 110-209), 0.490 with doors in their
                                            // doorways (semantic.doors_in_doorways, 2026-12-07; 0.336 with the segment
                                            // model of seeds 110-209), 0.464 with refrigerators by
                                            // their colour (semantic.refrigerator_wood_chroma, 2026-12-07; 0.318 with the
                                            // segment model of seeds 110-209), 0.402 with the walls' colour
                                            // (semantic.wall_colour, 2026-12-06; 0.286 with the segment model of seeds
                                            // 110-209), 0.376 with classes no higher than
                                            // their objects stand (semantic.high_tops, 2026-12-06), 0.359 with sofa backs beside their
                                            // seats (semantic.sofa_backs, 2026-12-06), 0.338 with counters at counter
                                            // height (semantic.counter_min_top_m), 0.300 with the walls'
                                            // margin (semantic.wall_margin), 0.287 (the segment
                                            // model retrained on varied toilets), 0.258 (on sectional sofas), 0.256 (the floor as a
                                            // surface), 0.249 (fronts seen over
                                            // the top, curtains by their room), 0.233 before, 0.222 with the doors and
                                            // windows found in the walls (2026-12-05; 0.199 before the window pane
                                            // cut from unrecorded glass and the deeper pane voxels), 0.134 without,
                                            // 0.106 before.
constexpr int kMinRooms = 3;                // Rooms in rooms.geojson; measured 3: living room 28.2 m², kitchen 10.1 m²,
                                            // bathroom 4.0 m² (2026-12-06, the walls' colour); living room 27.8 m², kitchen 10.5 m²,
                                            // bathroom 4.0 m² (2026-12-06, unfamiliar views discounted); living
                                            // room 33.1 m², kitchen 5.2 m², bathroom 4.0 m² (2026-12-06, counters at counter height); living room
                                            // 28.6 m², kitchen 9.6 m², the bathroom 4.0 m² (2026-12-05) (typed kitchen until 2026-12-06,
                                            // bathroom since thin parts give no neighbour rise); 2 before.
constexpr double kMinUnfamiliarShare = 0.3;  // Object segment voxels unlike every training segment; measured 0.50.
constexpr double kMinUnfamiliarViewShare = 0.35;  // Classified pixels unlike every training view; measured 0.47.
constexpr double kMaxBathroomArea = 6.0;    // The room holding the toilet box's centre, m²; measured 4.0.
// Per-class recall floors (gt.json class names; voxels pooled over the class's boxes).
const std::map<std::string, double> kMinClassRecall = {
    {"bed", 0.60},          // measured 0.794 (0.537)
    {"cabinet", 0.50},      // measured 0.701 with hung wall cabinets (2026-12-07: the bedroom's wall cabinet), 0.669
                            // with wooden wall units (2026-12-07: the wall units over the counter),
                            // 0.605 with tall furniture no wall (2026-12-07: the corner wardrobe's front;
                            // 0.253 with the segment model of seeds 110-209, which calls it otherfurniture), 0.402 with
                            // doors in their doorways (2026-12-07: the tall cabinet called door;
                            // 0.237 with the segment model of seeds 110-209), 0.300 with refrigerators by their colour (2026-12-07: the wooden tall cabinet
                            // and the cabinet over the refrigerator; 0.144 with the segment model of seeds 110-209),
                            // 0.115 with the walls' colour, 0.103 with the segment model retrained on varied toilets (2026-12-06), 0.065 with the
                            // one of earlier that day (the kitchen's base cabinets), 0.002 before
    {"counter", 0.15},      // measured 0.226 with the segment model retrained on varied toilets (2026-12-06; 0.340 with the
                            // same code trained on seeds 110-209), 0.395 with the one before, 0.432 (0.216)
    {"curtain", 0.20},      // measured 0.339 with doors in their doorways (2026-12-07: the drawn curtain's panel
                            // called door; 0.324 with the segment model of seeds 110-209), 0.191 with the walls'
                            // colour, 0.179 since shower curtains outside bathrooms are curtains (2026-12-06), 0.000
                            // before
    {"desk", 0.0},          // measured 0.364 since segments below counter height are no counters (2026-12-06; 0.026 with
                            // the segment model of seeds 110-209, which calls the desk cabinet and sofa), 0.002 before
                            // (table voxels count)
    {"door", 0.50},         // measured 0.634 with the walls' margin, 0.622 with the doors found in the walls
                            // (semantic.wall_openings), 0.163 without
    {"garbagebin", 0.0},    // measured 0.173 with the segment model retrained on varied toilets (2026-12-06; 0 with the same
                            // code trained on seeds 110-209), 0.022 before
    {"refrigerator", 0.10}, // measured 0.610 with refrigerators by their colour (2026-12-07), 0.677 since classes
                            // stand no higher than their objects (2026-12-06: the
                            // refrigerator's front, top surface 1.7 m, was counter; 0.029 with the segment model of
                            // seeds 110-209, which gives it door), 0.165 with the segment model retrained on varied toilets (2026-12-06; 0.083 with the
                            // same code trained on seeds 110-209: the fridge's segments flip between refrigerator,
                            // shower curtain and door with the training draw), 0.462 with the one before,
                            // 0.458 with the segment model retrained on fronts seen over the top (2026-12-06), 0.347
                            // with the one of earlier that day, 0.771 with the one of 2026-12-02 (0.880)
    {"sink", 0.0},          // measured 0.000
    {"sofa", 0.50},         // measured 0.777 since a sofa's back beside its seat is sofa (2026-12-06, semantic.sofa_backs;
                            // 0.77 with the segment model of seeds 110-209, whose back was sofa already), 0.235 with the segment model retrained on varied toilets (2026-12-06), 0.229 on
                            // sectional sofas (0.769 and 0.776 with the same code trained on seeds 110-209), 0.171 (0.297)
    {"table", 0.40},        // measured 0.859 with bars as tables and furniture's feet (2026-12-07: the bar; 0.774 with
                            // the segment model of seeds 110-209), 0.165 since segments below counter height are
                            // no counters (2026-12-06: the low
                            // table by the curtain), 0.090 (0.055; desk voxels count)
    {"toilet", 0.40},       // measured 0.664 with the walls' margin (2026-12-06), 0.551 with the segment model
                            // retrained on varied toilets (2026-12-06; 0.569 with the
                            // same code trained on seeds 110-209), 0.082 since thin parts give no neighbour rise
                            // (2026-12-06), 0.000 before
    {"window", 0.40},       // measured 0.627 with the walls' colour (2026-12-06), 0.477 with the walls' margin (2026-12-06: the reveals beside the panes), 0.393
                            // with the windows found in the walls (0.262 before the pane cut from
                            // unrecorded glass), 0.046 without
};

const std::string kDataDir = std::string(SEMVOX_SOURCE_DIR) + "/../shared/data/scannet_scene0000_00";
const std::string kSunDir = std::string(SEMVOX_SOURCE_DIR) + "/../shared/data/sunrgbd_000017";
// One real RGB-D view of a bedroom (SUN RGB-D 000017, 50,000 points, two yawed boxes in gt_boxes.tsv).
// Measured 2026-12-06: bed 0.436 (0.000 before the frame fix: the view was taken for upside down and left
// 2 degrees tilted, and the bed came out sofa and chair), night stand 0.000, floor 0.998, wall share 0.348;
// 0.402 with the segment model retrained on upholstered sofas the same day (wall share 0.322); 0.423 since the
// floor is a surface (floor recall 0.976: the noisy floor's top layer beside the bed takes the bed's label);
// 0.660 with the segment model retrained on sectional sofas (2026-12-06), 0.425 with the one retrained on varied
// toilets the same day (0.422 with the same code trained on seeds 110-209); 0.435 since furniture stands on the floor
// (2026-12-07; floor recall 0.976 -> 0.954: the floor's upper layer under the bed's edge takes the bed's label).
constexpr double kMinSunBedRecall = 0.30;
constexpr double kMinSunFloorRecall = 0.95;

int RunSemvox(const std::string& args, const std::string& log) {
  const int rc = std::system((std::string(SEMVOX_BINARY) + " " + args + " > " + log + " 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// Rooms of rooms.geojson (input frame) holding the point (x, y): their ids and areas.
std::vector<std::pair<int, double>> RoomsAt(const nlohmann::json& geojson, double x, double y) {
  auto inside = [&](const nlohmann::json& ring) {  // Even-odd rule.
    bool in = false;
    for (size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
      const double xi = ring[i][0], yi = ring[i][1], xj = ring[j][0], yj = ring[j][1];
      if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) in = !in;
    }
    return in;
  };
  std::vector<std::pair<int, double>> out;
  for (const auto& f : geojson["features"]) {
    const auto& g = f["geometry"];
    nlohmann::json polygons = g["type"] == "Polygon" ? nlohmann::json::array({g["coordinates"]}) : g["coordinates"];
    for (const auto& poly : polygons) {
      bool in = !poly.empty() && inside(poly[0]);
      for (size_t h = 1; in && h < poly.size(); ++h) in = !inside(poly[h]);
      if (in) {
        out.push_back({f["properties"]["id"].get<int>(), f["properties"]["area_m2"].get<double>()});
        break;
      }
    }
  }
  return out;
}

TEST(RealScan, StudioBoxScoresAboveTheStatedFloors) {
#ifdef SEMVOX_SANITIZE_BUILD
  GTEST_SKIP() << "too slow under sanitizers (one run of the studio takes about 3 minutes in Release)";
#endif
  const std::string scan = kDataDir + "/scene0000_00.ply", gt = kDataDir + "/gt.json";
  if (!std::filesystem::exists(scan) || !std::filesystem::exists(gt)) GTEST_SKIP() << kDataDir << " not found";
  testing::ScratchDir dir("real_scan");
  const std::string out = dir.File("out"), log = dir.File("log.txt"), report = dir.File("eval_boxes.json");
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(RunSemvox("run " + scan + " -o " + out, log), 0) << testing::ReadText(log);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(RunSemvox("eval --pred " + out + " --boxes " + gt + " -o " + report + " -q", log), 0) << testing::ReadText(log);
  std::printf("semvox run on the studio: %.1f s wall clock\n%s", seconds, testing::ReadText(log).c_str());

  // A point cloud gets the Voxel-CRF weights learned on clouds.
  std::ifstream summary_in(out + "/summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_in);
  EXPECT_EQ(summary["semantic"]["model"].get<std::string>(), "models/voxel_crf_cloud.txt");
  // Segments below counter height are no counters (semantic.counter_min_top_m): the desk and the low table are
  // among them (measured 7 segments, 15,518 voxels).
  EXPECT_GE(summary["semantic"]["low_counters"]["segments"].get<int>(), 2);
  // The sectional's back-and-arms band, called bed by its shape, stands above the sofa seat beside it
  // (semantic.sofa_backs; measured 1 segment, 5,679 voxels).
  EXPECT_GE(summary["semantic"]["sofa_backs"]["segments"].get<int>(), 1);
  // A corner wardrobe (top 2.3 m) called table, and fronts at 1.7-1.9 m called counter, stand higher than any
  // table or counter (semantic.high_tops; measured 3 segments, 5,414 voxels).
  EXPECT_GE(summary["semantic"]["high_tops"]["segments"].get<int>(), 2);
  // The room-type descriptors of nearly all its views lie beyond the training views' familiar distance, and their
  // room evidence is discounted (semantic.room_view_familiarity; measured 45 of 45 views, mean weight 0.09;
  // generated randomised scans: see docs/rooms.md).
  // Window frames, door leaves, the toilet's back and the wall units' fronts in the wall band take their objects'
  // labels by colour (semantic.wall_colour; measured 2,594 voxels, walls' colour (138, 126, 102)).
  EXPECT_GE(summary["semantic"]["wall_colour"]["relabelled_voxels"].get<int>(), 500);
  // A wooden tall cabinet, shaped like a refrigerator and called one, and the wooden cabinet over the refrigerator
  // are cabinets by their colour (semantic.refrigerator_wood_chroma; measured 1,815 voxels).
  EXPECT_GE(summary["semantic"]["refrigerator_colour"]["relabelled_voxels"].get<int>(), 500);
  // The tall cabinet in the bedroom corner and a panel of the drawn curtain, called door by their shape, stand far
  // from both doors found in the walls (semantic.doors_in_doorways; measured 6 segments, 2,915 voxels).
  EXPECT_GE(summary["semantic"]["doors_in_doorways"]["relabelled_voxels"].get<int>(), 1000);
  // The corner wardrobe's front (top 2.3 m), in object segments the shape classifier calls cabinet, came out wall
  // from the Voxel-CRF (semantic.tall_object_walls; measured 4 segments, 1,924 voxels).
  EXPECT_GE(summary["semantic"]["tall_object_walls"]["relabelled_voxels"].get<int>(), 1000);
  // The oak wall units over the kitchen counter hang in the wall columns, in another colour than the beige wall
  // around them (semantic.wooden_wall_units; measured 2 parts, 685 voxels).
  EXPECT_GE(summary["semantic"]["wooden_wall_units"]["relabelled_voxels"].get<int>(), 300);
  // The bedroom's dark wall cabinet, the colour of the shaded wall beside it, hangs over free space
  // (semantic.hung_wall_cabinets; measured 1 part, 380 voxels).
  EXPECT_EQ(summary["semantic"]["hung_wall_cabinets"]["components"].get<int>(), 1);
  EXPECT_GE(summary["semantic"]["hung_wall_cabinets"]["relabelled_voxels"].get<int>(), 200);
  // The kitchen's bar (top 1.1 m, 1.0 m from every wall), called counter, is a table by name once the rooms have read
  // it as kitchen furniture (semantic.bar_tables; measured 1 segment, 3,628 voxels).
  EXPECT_EQ(summary["semantic"]["bar_tables"]["segments"].get<int>(), 1);
  EXPECT_GE(summary["semantic"]["bar_tables"]["relabelled_voxels"].get<int>(), 2000);
  // The floor's upper layer under the bed, the sofa, the tables and the cabinets holds their feet
  // (semantic.furniture_feet; measured 1,065 voxels).
  EXPECT_GE(summary["semantic"]["furniture_feet"]["relabelled_voxels"].get<int>(), 500);
  const auto& room_views = summary["semantic"]["room_view_appearance"];
  EXPECT_GE(room_views["unfamiliar_views"].get<int>(), int(0.8 * room_views["views"].get<int>()));
  EXPECT_LE(room_views["mean_weight"].get<double>(), 0.3);
  // Most of the studio's object segments are shaped unlike every training segment (measured 0.52; generated
  // scans 0.02-0.05), and the run says so in a warning.
  const double unfamiliar = summary["semantic"]["object_segment_shapes"]["unfamiliar_share"].get<double>();
  std::printf("object segment voxels shaped unlike every training segment: %.3f (>= %.2f)\n", unfamiliar, kMinUnfamiliarShare);
  EXPECT_GE(unfamiliar, kMinUnfamiliarShare);
  // So do its views look unlike the training views (measured 0.47; generated 0.02-0.04 flat, 0.22-0.25 randomised).
  const double unfamiliar_view = summary["semantic"]["view_appearance"]["unfamiliar_share"].get<double>();
  std::printf("classified pixels unlike every training view: %.3f (>= %.2f)\n", unfamiliar_view, kMinUnfamiliarViewShare);
  EXPECT_GE(unfamiliar_view, kMinUnfamiliarViewShare);
  bool warned_segments = false, warned_views = false;
  for (const auto& w : summary["warnings"]) {
    warned_segments |= w.get<std::string>().find("shaped unlike every training segment") != std::string::npos;
    warned_views |= w.get<std::string>().find("look unlike every training view") != std::string::npos;
  }
  EXPECT_TRUE(warned_segments) << "no warning about unfamiliar object segments";
  EXPECT_TRUE(warned_views) << "no warning about unfamiliar views";

  std::ifstream in(report);
  const nlohmann::json e = nlohmann::json::parse(in);
  ASSERT_TRUE(e["floor_recall"]["present"].get<bool>());
  ASSERT_TRUE(e["wall_share"]["present"].get<bool>());
  ASSERT_TRUE(e["mean_box_recall"]["present"].get<bool>()) << "no box holds a voxel: is axis_align_matrix applied?";
  const double floor = e["floor_recall"]["value"].get<double>(), wall = e["wall_share"]["value"].get<double>(),
               mean_box = e["mean_box_recall"]["value"].get<double>();
  std::printf("floor recall %.3f (floor >= %.2f), wall share %.3f (<= %.2f), mean box recall %.3f (>= %.2f) over %d boxes\n", floor,
              kMinFloorRecall, wall, kMaxWallShare, mean_box, kMinMeanBoxRecall, e["boxes_scored"].get<int>());
  EXPECT_GE(floor, kMinFloorRecall) << "floor recall";
  EXPECT_LE(wall, kMaxWallShare) << "wall share";
  EXPECT_GE(mean_box, kMinMeanBoxRecall) << "mean box recall";
  EXPECT_GE(int(e["rooms"].size()), kMinRooms) << "rooms found";
  for (const auto& [name, c] : e["per_class"].items()) {
    const double recall = c["recall"].value("value", 0.0);
    std::printf("  class %-14s recall %.3f (%d boxes, %zu voxels)\n", name.c_str(), recall, c["boxes"].get<int>(),
                c["voxels"].get<size_t>());
    const auto floor_it = kMinClassRecall.find(name);
    if (floor_it != kMinClassRecall.end()) {
      EXPECT_GE(recall, floor_it->second) << name;
    }
  }

  // The bathroom (toilet and sink behind a 1 m door whose lintel the scan sees over a mostly unseen wall) is
  // a room of its own, not a part of the room with the bed.
  std::ifstream gt_in(gt), rooms_in(out + "/rooms.geojson");
  const nlohmann::json g = nlohmann::json::parse(gt_in), rooms = nlohmann::json::parse(rooms_in);
  // Box centres are in the aligned frame: p_aligned = M p_input, so p_input = R^T (p_aligned - t).
  const auto& m = g["axis_align_matrix"];
  auto room_of = [&](const std::string& cls) {
    for (const auto& b : g["boxes_in_aligned_frame"]) {
      if (b["class"] != cls) continue;
      const double ax = b["centre_size"][0].get<double>() - m[0][3].get<double>(),
                   ay = b["centre_size"][1].get<double>() - m[1][3].get<double>();
      const double x = m[0][0].get<double>() * ax + m[1][0].get<double>() * ay, y = m[0][1].get<double>() * ax + m[1][1].get<double>() * ay;
      return RoomsAt(rooms, x, y);
    }
    return std::vector<std::pair<int, double>>{};
  };
  const auto toilet = room_of("toilet"), bed = room_of("bed");
  ASSERT_EQ(toilet.size(), 1u) << "the toilet's centre lies in one room";
  ASSERT_EQ(bed.size(), 1u) << "the bed's centre lies in one room";
  EXPECT_NE(toilet[0].first, bed[0].first) << "the bathroom merged with the main room";
  EXPECT_LT(toilet[0].second, kMaxBathroomArea) << "the toilet's room";
  std::printf("toilet in room %d (%.1f m2), bed in room %d (%.1f m2)\n", toilet[0].first, toilet[0].second, bed[0].first, bed[0].second);
  // The studio holds a bathroom and a kitchen (issue 16): the toilet's room is typed bathroom, the
  // refrigerator's kitchen (measured 1.00 and 0.83; the kitchen corner is 10.1-10.5 of the 38.3 m² open room since the
  // views' room evidence is discounted where they look unlike the training views (2026-12-06: their room
  // classifier called 43 of the 45 views living room, and the corner was no kitchen once the refrigerator's front
  // was no longer read as counter); 5.2 m² since segments below counter height are no counters (9.5 m² before,
  // with two bins read as counters), split off since room_types.min_split_fraction is 0.1).
  auto type_of = [&](int id) {
    for (const auto& f : rooms["features"])
      if (f["properties"]["id"].get<int>() == id) return f["properties"]["type"].get<std::string>();
    return std::string();
  };
  const auto fridge = room_of("refrigerator");
  ASSERT_EQ(fridge.size(), 1u) << "the refrigerator's centre lies in one room";
  EXPECT_EQ(type_of(toilet[0].first), "bathroom") << "the toilet's room";
  EXPECT_EQ(type_of(fridge[0].first), "kitchen") << "the refrigerator's room";
}

// The SUN RGB-D bedroom view end to end, scored against its yawed boxes (gt_boxes.tsv); skipped when absent.
TEST(RealScan, SunRgbdBedroomViewBedIsBed) {
#ifdef SEMVOX_SANITIZE_BUILD
  GTEST_SKIP() << "too slow under sanitizers";
#endif
  const std::string scan = kSunDir + "/000017_points.ply", gt = kSunDir + "/gt_boxes.tsv";
  if (!std::filesystem::exists(scan) || !std::filesystem::exists(gt)) GTEST_SKIP() << kSunDir << " not found";
  testing::ScratchDir dir("real_sun");
  const std::string out = dir.File("out"), log = dir.File("log.txt"), report = dir.File("eval_boxes.json");
  ASSERT_EQ(RunSemvox("run " + scan + " -o " + out, log), 0) << testing::ReadText(log);
  ASSERT_EQ(RunSemvox("eval --pred " + out + " --boxes " + gt + " -o " + report + " -q", log), 0) << testing::ReadText(log);
  std::printf("%s", testing::ReadText(log).c_str());
  std::ifstream summary_in(out + "/summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_in);
  EXPECT_FALSE(summary["frame"]["upside_down"].get<bool>());
  EXPECT_TRUE(summary["frame"]["levelled"].get<bool>());
  std::ifstream in(report);
  const nlohmann::json e = nlohmann::json::parse(in);
  ASSERT_EQ(e["boxes"].size(), 2u);
  const double bed = e["per_class"]["bed"]["recall"].value("value", 0.0), floor = e["floor_recall"].value("value", 0.0);
  std::printf("SUN RGB-D 000017: bed recall %.3f (>= %.2f), floor recall %.3f (>= %.2f)\n", bed, kMinSunBedRecall, floor,
              kMinSunFloorRecall);
  EXPECT_GE(bed, kMinSunBedRecall);
  EXPECT_GE(floor, kMinSunFloorRecall);
}

// Bad input to `semvox eval --boxes`: one error line on stderr and exit code 2. Needs no data.
TEST(RealScan, BoxEvalBadInputGivesOneErrorLineAndExitCode2) {
  testing::ScratchDir dir("real_scan_bad");
  const std::string log = dir.File("log.txt");
  const std::string run = dir.File("run");
  std::filesystem::create_directories(run);
  testing::WriteText(dir.File("gt.json"), R"({"axis_align_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]],
    "boxes_in_aligned_frame": [{"class": "bed", "nyu40": 4, "centre_size": [0, 0, 0, 1, 1, 1]}]})");
  testing::WriteText(dir.File("bad.json"), R"({"axis_align_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]})");
  const auto expect_error = [&](const std::string& args, const std::string& what) {
    EXPECT_EQ(RunSemvox(args, log), 2) << args;
    const std::string text = testing::ReadText(log);
    EXPECT_EQ(text.rfind("semvox: error: ", 0), 0u) << text;
    EXPECT_NE(text.find(what), std::string::npos) << text;
    EXPECT_EQ(text.find('\n'), text.size() - 1) << "one line: " << text;
  };
  // A run directory without voxels.ply, then a missing directory.
  expect_error("eval --pred " + run + " --boxes " + dir.File("gt.json"), "voxels.ply");
  expect_error("eval --pred " + dir.File("absent") + " --boxes " + dir.File("gt.json"), "not a directory");
  // Missing and malformed ground truth.
  expect_error("eval --pred " + run + " --boxes " + dir.File("absent.json"), "absent.json");
  expect_error("eval --pred " + run + " --boxes " + dir.File("bad.json"), "missing field boxes_in_aligned_frame");
  // voxels.ply without a label property.
  PlyWriter w;
  w.AddElement("vertex", 2);
  for (const char* axis : {"x", "y", "z"}) w.AddProperty(axis, PlyType::kFloat32, {0.0, 0.05});
  ASSERT_TRUE(w.Write(run + "/voxels.ply").ok());
  expect_error("eval --pred " + run + " --boxes " + dir.File("gt.json"), "no label property");
  // Neither --gt nor --boxes; both.
  expect_error("eval --pred " + run, "--boxes");
  expect_error("eval --pred " + run + " --gt " + run + " --boxes " + dir.File("gt.json"), "excludes");
  // With a label the same call succeeds and --json prints the report.
  PlyWriter ok;
  ok.AddElement("vertex", 2);
  for (const char* axis : {"x", "y", "z"}) ok.AddProperty(axis, PlyType::kFloat32, {0.0, 0.05});
  ok.AddProperty("label", PlyType::kUInt16, {4.0, 1.0});
  ASSERT_TRUE(ok.Write(run + "/voxels.ply").ok());
  ASSERT_EQ(RunSemvox("eval --pred " + run + " --boxes " + dir.File("gt.json") + " --json -q", log), 0) << testing::ReadText(log);
  const nlohmann::json e = nlohmann::json::parse(testing::ReadText(log));
  EXPECT_DOUBLE_EQ(e["mean_box_recall"]["value"].get<double>(), 0.5);
  EXPECT_FALSE(e["rooms_present"]["present"].get<bool>());
}

}  // namespace
}  // namespace semvox
