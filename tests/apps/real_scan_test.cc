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

// ---- Floors (measured on the current models in the comment; history in docs/experiments.md) ----
// Measured 2026-12-08 with the shipped models, after the steps chosen on the studio alone were removed (they
// failed the real-scan rule of docs/metrics.md, "The real-scan bench"; 0.602 with them).
constexpr double kMinFloorRecall = 0.95;    // Floor band labelled floor; measured 0.972.
constexpr double kMaxWallShare = 0.50;      // Occupied voxels labelled wall; measured 0.373.
constexpr double kMinMeanBoxRecall = 0.33;  // Mean over boxes holding voxels; measured 0.358.
constexpr int kMinRooms = 3;                // Rooms in rooms.geojson; measured 3: living room 29.4 m², kitchen 8.9 m²,
                                            // bathroom 4.0 m².
constexpr double kMinUnfamiliarShare = 0.3;  // Object segment voxels unlike every training segment; measured 0.50.
constexpr double kMinUnfamiliarViewShare = 0.35;  // Classified pixels unlike every training view; measured 0.47.
constexpr double kMaxBathroomArea = 6.0;    // The room holding the toilet box's centre, m²; measured 4.0.
// Per-class recall floors (gt.json class names; voxels pooled over the class's boxes), a few points under the
// value measured.
const std::map<std::string, double> kMinClassRecall = {
    {"bed", 0.80},          // measured 0.867
    {"cabinet", 0.05},      // measured 0.103: the wardrobe's front and the wall units lie in the wall columns
    {"counter", 0.15},      // measured 0.226
    {"curtain", 0.0},       // measured 0.000: the drawn curtain comes out shower curtain
    {"desk", 0.25},         // measured 0.352 (segments below counter height are no counters)
    {"door", 0.50},         // measured 0.623 (doors found in the walls)
    {"garbagebin", 0.0},    // measured 0.221
    {"refrigerator", 0.10}, // measured 0.167
    {"sink", 0.0},          // measured 0.000
    {"sofa", 0.15},         // measured 0.237
    {"table", 0.70},        // measured 0.816 (the bar and the low table)
    {"toilet", 0.50},       // measured 0.604
    {"window", 0.30},       // measured 0.390 (windows found in the walls)
};

const std::string kDataDir = std::string(SEMVOX_SOURCE_DIR) + "/../shared/data/scannet_scene0000_00";
const std::string kSunDir = std::string(SEMVOX_SOURCE_DIR) + "/../shared/data/sunrgbd_000017";
// One real RGB-D view of a bedroom (SUN RGB-D 000017, 50,000 points, two yawed boxes in gt_boxes.tsv).
// Measured 2026-12-08: bed 0.434 (its pillows, inside its box, are labelled pillow), night stand 0.000, floor 0.955.
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
  // The kitchen's bar (top 1.1 m, 1.0 m from every wall), called counter, is a table by name once the rooms have read
  // it as kitchen furniture (semantic.bar_tables; measured 2 segments, 4,015 voxels).
  EXPECT_GE(summary["semantic"]["bar_tables"]["segments"].get<int>(), 1);
  EXPECT_GE(summary["semantic"]["bar_tables"]["relabelled_voxels"].get<int>(), 2000);
  // The floor's upper layer under the bed, the sofa, the tables and the cabinets holds their feet
  // (semantic.furniture_feet; measured 1,065 voxels).
  EXPECT_GE(summary["semantic"]["furniture_feet"]["relabelled_voxels"].get<int>(), 500);
  // The room-type descriptors of nearly all its views lie beyond the training views' familiar distance, and their
  // room evidence is discounted (semantic.room_view_familiarity; measured 45 of 45 views, mean weight 0.09;
  // generated randomised scans: see docs/rooms.md).
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

// The SUN RGB-D view at 2.5 cm voxels: its object segments are found and described on the 5 cm lattice, so they
// look like the training segments as at 5 cm. Measured 2026-12-08: bed 0.595, unfamiliar segment voxels 0.25
// (before the lattice: bed 0.000, no wall column found, every segment unfamiliar).
TEST(RealScan, SunRgbdBedroomViewAtFineVoxelsKeepsItsBed) {
#ifdef SEMVOX_SANITIZE_BUILD
  GTEST_SKIP() << "too slow under sanitizers";
#endif
  const std::string scan = kSunDir + "/000017_points.ply", gt = kSunDir + "/gt_boxes.tsv";
  if (!std::filesystem::exists(scan) || !std::filesystem::exists(gt)) GTEST_SKIP() << kSunDir << " not found";
  testing::ScratchDir dir("real_sun_fine");
  const std::string out = dir.File("out"), log = dir.File("log.txt"), report = dir.File("eval_boxes.json");
  testing::WriteText(dir.File("fine.yaml"), "mapping:\n  voxel_size_m: 0.025\n");
  ASSERT_EQ(RunSemvox("run " + scan + " -o " + out + " --config " + dir.File("fine.yaml"), log), 0) << testing::ReadText(log);
  ASSERT_EQ(RunSemvox("eval --pred " + out + " --boxes " + gt + " -o " + report + " -q", log), 0) << testing::ReadText(log);
  std::ifstream in(report), summary_in(out + "/summary.json");
  const nlohmann::json e = nlohmann::json::parse(in), summary = nlohmann::json::parse(summary_in);
  const double bed = e["per_class"]["bed"]["recall"].value("value", 0.0);
  const double unfamiliar = summary["semantic"]["object_segment_shapes"]["unfamiliar_share"].get<double>();
  std::printf("SUN RGB-D 000017 at 2.5 cm: bed recall %.3f (>= 0.45), unfamiliar segment voxels %.3f (<= 0.6)\n", bed, unfamiliar);
  EXPECT_GE(bed, 0.45);
  EXPECT_LE(unfamiliar, 0.6);
}

// The S3DIS office room (320,917 points, no colour, a NYU40 label per point) end to end, scored per point:
// each labelled point takes the label of the nearest voxel within 7.5 cm (`semvox eval --points`). Skipped when
// absent. Measured 2026-12-08: point accuracy 0.254, mean class recall 0.386, floor recall 0.981, every point matched;
// the chairs, tables and bookcases of an office are mostly wrong (no office furniture in the generator).
const std::string kS3disDir = std::string(SEMVOX_SOURCE_DIR) + "/../shared/data/s3dis_office_room";
constexpr double kMinS3disAccuracy = 0.22;
constexpr double kMinS3disFloorRecall = 0.95;
constexpr double kMinS3disMatched = 0.95;  // Points with a voxel within 7.5 cm: the map covers the scan.

TEST(RealScan, S3disOfficeRoomPointScoresAboveTheStatedFloors) {
#ifdef SEMVOX_SANITIZE_BUILD
  GTEST_SKIP() << "too slow under sanitizers";
#endif
  const std::string scan = kS3disDir + "/office_room.ply";
  if (!std::filesystem::exists(scan)) GTEST_SKIP() << kS3disDir << " not found";
  testing::ScratchDir dir("real_s3dis");
  const std::string out = dir.File("out"), log = dir.File("log.txt"), report = dir.File("eval_points.json");
  ASSERT_EQ(RunSemvox("run " + scan + " -o " + out, log), 0) << testing::ReadText(log);
  ASSERT_EQ(RunSemvox("eval --pred " + out + " --points " + scan + " -o " + report + " -q", log), 0) << testing::ReadText(log);
  std::printf("%s", testing::ReadText(log).c_str());
  std::ifstream in(report);
  const nlohmann::json e = nlohmann::json::parse(in);
  const double accuracy = e["accuracy"]["value"].get<double>(), floor = e["floor_recall"]["value"].get<double>(),
               matched = e["matched"]["value"].get<double>();
  std::printf("S3DIS office room: point accuracy %.3f (>= %.2f), floor recall %.3f (>= %.2f), matched %.3f (>= %.2f)\n", accuracy,
              kMinS3disAccuracy, floor, kMinS3disFloorRecall, matched, kMinS3disMatched);
  EXPECT_GE(accuracy, kMinS3disAccuracy);
  EXPECT_GE(floor, kMinS3disFloorRecall);
  EXPECT_GE(matched, kMinS3disMatched);
  // A run never fails because a class is absent: the room has no colour and no clutter class, and every class of
  // its ground truth is scored.
  EXPECT_EQ(e["per_class"].size(), 11u);
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
  expect_error("eval --pred " + run + " --boxes " + dir.File("gt.json") + " --points " + dir.File("gt.json"), "excludes");
  // Labelled points without a label property (voxels.ply itself, still unlabelled here).
  expect_error("eval --pred " + run + " --points " + run + "/voxels.ply", "no label property");
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
  // The run's own voxels as labelled points: every point finds itself.
  ASSERT_EQ(RunSemvox("eval --pred " + run + " --points " + run + "/voxels.ply --json -q", log), 0) << testing::ReadText(log);
  const nlohmann::json p = nlohmann::json::parse(testing::ReadText(log));
  EXPECT_DOUBLE_EQ(p["accuracy"]["value"].get<double>(), 1.0);
}

}  // namespace
}  // namespace semvox
