// End to end: `semvox run` on a generated apartment writes the semantic outputs, and `semvox eval`
// scores them against the generator's ground truth above stated floors.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/ply.h"
#include "io/image_io.h"
#include "mapping/octomap_io.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

int RunSemvox(const std::string& args, const std::string& log) {
  const int rc = std::system((std::string(SEMVOX_BINARY) + " " + args + " > " + log + " 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

TEST(SemanticCli, GeneratedApartmentIsLabelledAboveTheStatedFloors) {
  testing::ScratchDir dir("semantic_cli");
  const std::string gt = dir.File("gt"), out = dir.File("out"), log = dir.File("log.txt");
  ASSERT_EQ(RunSemvox("generate --seed 104 --set apartment.max_rooms=3 -o " + gt, log), 0) << testing::ReadText(log);
  ASSERT_EQ(RunSemvox("run " + gt + "/mesh.ply -o " + out + " --config " + std::string(SEMVOX_SOURCE_DIR) + "/tests/data/semantic.yaml", log), 0)
      << testing::ReadText(log);
  for (const char* f : {"voxels.ply", "map.ot", "semantic_topview.png", "semantic_topview_labels.png", "rooms.geojson",
                        "support_clutter.ply", "object_proposals.json", "report.html"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + f)) << f;
  // voxels.ply: the fields of the issue, one vertex per occupied voxel, rooms assigned.
  Result<PlyData> ply = ReadPly(out + "/voxels.ply");
  ASSERT_TRUE(ply.ok()) << ply.status().message();
  const PlyElement* v = ply->Find("vertex");
  ASSERT_NE(v, nullptr);
  ASSERT_GT(v->count, 1000u);
  size_t in_room = 0, completed = 0;
  for (size_t i = 0; i < v->count; ++i) {
    in_room += v->Find("room")->values[i] > 0;
    completed += v->Find("completed")->values[i] > 0;
    ASSERT_GT(v->Find("label")->values[i], 0);
    ASSERT_GE(v->Find("confidence")->values[i], 0.0);
    ASSERT_LE(v->Find("confidence")->values[i], 1.0);
  }
  // Floor, furniture and ceiling voxels above room cells carry their room; walls lie outside every room (-1).
  EXPECT_GT(in_room, v->count / 10);
  // map.ot reads back with the same occupied voxels.
  double res = 0;
  Result<std::vector<SemanticVoxel>> ot = ReadSemanticOctree(out + "/map.ot", &res);
  ASSERT_TRUE(ot.ok()) << ot.status().message();
  EXPECT_DOUBLE_EQ(res, 0.05);
  size_t occupied = 0;
  for (const SemanticVoxel& s : *ot) occupied += s.occupied;
  EXPECT_EQ(occupied, v->count);
  // The semantic top view is on the occupancy grid.
  Result<ImageU16> top = ReadImageU16(out + "/semantic_topview_labels.png");
  Result<ImageRgb8> pgm = ReadImageGrey8(out + "/occupancy.pgm");
  ASSERT_TRUE(top.ok() && pgm.ok());
  EXPECT_EQ(top->width, pgm->width);
  EXPECT_EQ(top->height, pgm->height);
  // Scores against the ground truth (docs/metrics.md). Floors stated here, measured well above them.
  ASSERT_EQ(RunSemvox("eval --pred " + out + " --gt " + gt + " -o " + dir.File("eval.json"), log), 0) << testing::ReadText(log);
  std::ifstream in(dir.File("eval.json"));
  const nlohmann::json e = nlohmann::json::parse(in);
  const double geo = e["a_top_view"]["geometric_accuracy"]["value"].get<double>();
  const double visible = e["b_visible_voxels"]["accuracy"]["value"].get<double>();
  const double nyu4 = e["c_nyu4"]["global"]["value"].get<double>();
  std::printf("seed 104: top-view geometric %.3f, visible-voxel accuracy %.3f, NYU-4 global %.3f, %zu voxels (%zu completed)\n", geo,
              visible, nyu4, size_t(v->count), completed);
  EXPECT_GE(geo, 0.85) << "top-view geometric accuracy";
  EXPECT_GE(visible, 0.60) << "visible-voxel accuracy (NYU40 ids)";
  EXPECT_GE(nyu4, 0.70) << "visible-voxel NYU-4 global accuracy";
  // The confidence of the visible voxels is scored (eval/confidence_eval.h): its reliability bins hold them all.
  const nlohmann::json& conf = e["f_confidence"];
  size_t binned = 0;
  for (const auto& b : conf["reliability"]) binned += b["count"].get<size_t>();
  EXPECT_EQ(binned, conf["scored"].get<size_t>());
  EXPECT_GT(conf["scored"].get<size_t>(), 1000u);
  EXPECT_TRUE(conf["ece"]["present"].get<bool>());
  // Deterministic: a second run gives the same semantic outputs, byte for byte.
  const std::string out2 = dir.File("out2");
  ASSERT_EQ(RunSemvox("run " + gt + "/mesh.ply -o " + out2 + " --config " + std::string(SEMVOX_SOURCE_DIR) + "/tests/data/semantic.yaml", log), 0)
      << testing::ReadText(log);
  for (const char* f : {"voxels.ply", "map.ot", "semantic_topview_labels.png", "rooms.geojson", "rooms.png", "support_clutter.ply",
                        "object_proposals.json", "occupancy.pgm"})
    EXPECT_TRUE(testing::ReadText(out + "/" + f) == testing::ReadText(out2 + "/" + f)) << f << " differs between two runs";
  // Summary: Voxel-CRF energies per iteration.
  std::ifstream sj(out + "/summary.json");
  const nlohmann::json s = nlohmann::json::parse(sj);
  ASSERT_TRUE(s.contains("semantic"));
  EXPECT_GE(s["semantic"]["iterations"].size(), 1u);
  // A generated apartment's object segments are shaped like the training segments (the ScanNet studio's are
  // not: tests/apps/real_scan_test.cc), and no warning says otherwise.
  const nlohmann::json& shapes = s["semantic"]["object_segment_shapes"];
  std::printf("object segment voxels unlike every training segment: %.3f of %d\n", shapes["unfamiliar_share"].get<double>(),
              shapes["segment_voxels"].get<int>());
  EXPECT_GT(shapes["segment_voxels"].get<int>(), 1000);
  EXPECT_LT(shapes["unfamiliar_share"].get<double>(), 0.15);
  // Its views look like the training views (flat colours, as the shipped per-view models were trained on).
  const double unfamiliar_view = s["semantic"]["view_appearance"]["unfamiliar_share"].get<double>();
  std::printf("classified pixels unlike every training view: %.3f\n", unfamiliar_view);
  EXPECT_LT(unfamiliar_view, 0.15);
  for (const auto& w : s["warnings"]) {
    EXPECT_EQ(w.get<std::string>().find("unlike every training segment"), std::string::npos) << w;
    EXPECT_EQ(w.get<std::string>().find("unlike every training view"), std::string::npos) << w;
  }
}

// semantic.view_selection: all_objects_on_cover classifies every view, as `all` does, so the labels and rooms
// are the same byte for byte; only the cover's views go to the support / clutter stage.
TEST(SemanticCli, ObjectsOnTheCoverKeepTheLabelsOfEveryView) {
  testing::ScratchDir dir("semantic_cli_cover");
  const std::string gt = dir.File("gt"), log = dir.File("log.txt");
  ASSERT_EQ(RunSemvox("generate --seed 104 --set apartment.max_rooms=2 -o " + gt, log), 0) << testing::ReadText(log);
  nlohmann::json summary[2];
  const char* modes[2] = {"all", "all_objects_on_cover"};
  for (int m = 0; m < 2; ++m) {
    const std::string config = dir.File(std::string(modes[m]) + ".yaml"), out = dir.File(modes[m]);
    {
      std::ofstream c(config);
      c << testing::ReadText(std::string(SEMVOX_SOURCE_DIR) + "/tests/data/semantic.yaml") << "  view_selection: " << modes[m] << "\n";
    }
    ASSERT_EQ(RunSemvox("run " + gt + "/mesh.ply -o " + out + " --config " + config, log), 0) << testing::ReadText(log);
    std::ifstream sj(out + "/summary.json");
    summary[m] = nlohmann::json::parse(sj);
  }
  for (const char* f : {"voxels.ply", "semantic_topview_labels.png", "rooms.geojson", "rooms.png"})
    EXPECT_TRUE(testing::ReadText(dir.File("all") + "/" + f) == testing::ReadText(dir.File("all_objects_on_cover") + "/" + f))
        << f << " differs";
  const nlohmann::json& all = summary[0];
  const nlohmann::json& cover = summary[1];
  EXPECT_EQ(cover["semantic"]["view_selection"]["method"], "all_objects_on_cover");
  const int classified = cover["semantic"]["classification_views"].get<int>();
  EXPECT_EQ(classified, all["semantic"]["classification_views"].get<int>());
  EXPECT_EQ(all["objects"]["views"].get<int>(), classified);
  const int hooked = cover["semantic"]["view_selection"]["hooked_views"].get<int>();
  EXPECT_EQ(cover["objects"]["views"].get<int>(), hooked);
  EXPECT_GT(hooked, 0);
  EXPECT_LT(hooked, classified);
}

// objects.enabled: false (docs/configuration.md) keeps the semantic outputs and drops the support / clutter
// stage: none of its files, no "objects" in summary.json.
TEST(SemanticCli, ObjectsSectionSwitchesTheSupportStageOff) {
  testing::ScratchDir dir("semantic_cli_objects");
  const std::string gt = dir.File("gt"), out = dir.File("out"), log = dir.File("log.txt"), config = dir.File("config.yaml");
  ASSERT_EQ(RunSemvox("generate --seed 104 --set apartment.max_rooms=2 -o " + gt, log), 0) << testing::ReadText(log);
  {
    std::ofstream c(config);
    c << testing::ReadText(std::string(SEMVOX_SOURCE_DIR) + "/tests/data/semantic.yaml") << "objects:\n  enabled: false\n";
  }
  ASSERT_EQ(RunSemvox("run " + gt + "/mesh.ply -o " + out + " --config " + config, log), 0) << testing::ReadText(log);
  for (const char* f : {"voxels.ply", "map.ot", "semantic_topview_labels.png", "config_used.yaml"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + f)) << f;
  for (const char* f : {"support_clutter.ply", "support_clutter_topview.png", "object_proposals.json"})
    EXPECT_FALSE(std::filesystem::exists(out + "/" + f)) << f;
  std::ifstream sj(out + "/summary.json");
  const nlohmann::json s = nlohmann::json::parse(sj);
  EXPECT_TRUE(s.contains("semantic"));
  EXPECT_FALSE(s.contains("objects"));
  EXPECT_NE(testing::ReadText(out + "/config_used.yaml").find("enabled: false"), std::string::npos);
  // An out-of-range value is one error line naming the key, and nothing is run.
  {
    std::ofstream c(config);
    c << "objects:\n  merge_iou: 0\n";
  }
  const std::string bad = dir.File("bad");
  EXPECT_NE(RunSemvox("run " + gt + "/mesh.ply -o " + bad + " --config " + config, log), 0);
  EXPECT_NE(testing::ReadText(log).find("objects.merge_iou"), std::string::npos) << testing::ReadText(log);
  EXPECT_FALSE(std::filesystem::exists(bad + "/summary.json"));
}

// --min-confidence: labels under the floor (0.8 here) are 0 in map.ot and the top views, voxels.ply keeps every label
// and summary.json counts them; out of [0, 1] is one error line.
TEST(SemanticCli, MinConfidenceUnlabelsUnsureVoxelsInTheExportsOnly) {
  testing::ScratchDir dir("semantic_cli_min_conf");
  const std::string gt = dir.File("gt"), log = dir.File("log.txt"), config = std::string(SEMVOX_SOURCE_DIR) + "/tests/data/semantic.yaml";
  ASSERT_EQ(RunSemvox("generate --seed 104 --set apartment.max_rooms=2 -o " + gt, log), 0) << testing::ReadText(log);
  const std::string all = dir.File("all"), sure = dir.File("sure");
  ASSERT_EQ(RunSemvox("run " + gt + "/mesh.ply -o " + all + " --config " + config, log), 0) << testing::ReadText(log);
  ASSERT_EQ(RunSemvox("run " + gt + "/mesh.ply -o " + sure + " --config " + config + " --min-confidence 0.8", log), 0)
      << testing::ReadText(log);
  // voxels.ply is the same; the summary counts the voxels under the floor.
  EXPECT_TRUE(testing::ReadText(all + "/voxels.ply") == testing::ReadText(sure + "/voxels.ply"));
  Result<PlyData> ply = ReadPly(all + "/voxels.ply");
  ASSERT_TRUE(ply.ok());
  const PlyElement* v = ply->Find("vertex");
  size_t below = 0;
  for (double c : v->Find("confidence")->values) below += c < 0.8;
  std::ifstream sj(sure + "/summary.json");
  const nlohmann::json s = nlohmann::json::parse(sj);
  EXPECT_EQ(s["semantic"]["min_confidence"]["voxels_below"].get<size_t>(), below);
  ASSERT_GT(below, 0u);
  // The top view: every labelled cell of the floored view is labelled alike without the floor, and fewer are.
  Result<ImageU16> a = ReadImageU16(all + "/semantic_topview_labels.png"), b = ReadImageU16(sure + "/semantic_topview_labels.png");
  ASSERT_TRUE(a.ok() && b.ok());
  size_t labelled_a = 0, labelled_b = 0, disagree = 0;
  for (int y = 0; y < a->height; ++y)
    for (int x = 0; x < a->width; ++x) {
      labelled_a += a->at(x, y) != 0, labelled_b += b->at(x, y) != 0;
      disagree += b->at(x, y) != 0 && b->at(x, y) != a->at(x, y);
    }
  EXPECT_LT(labelled_b, labelled_a);
  EXPECT_EQ(disagree, 0u);
  // map.ot: no label under the floor.
  double resolution = 0;
  Result<std::vector<SemanticVoxel>> ot = ReadSemanticOctree(sure + "/map.ot", &resolution);
  ASSERT_TRUE(ot.ok());
  for (const SemanticVoxel& sv : *ot) {
    if (sv.occupied && sv.label != 0) {
      ASSERT_GE(sv.confidence, 0.8f);
    }
  }
  EXPECT_NE(RunSemvox("run " + gt + "/mesh.ply -o " + dir.File("bad") + " --min-confidence 1.5", log), 0);
  EXPECT_NE(testing::ReadText(log).find("--min-confidence"), std::string::npos) << testing::ReadText(log);
}

}  // namespace
}  // namespace semvox
