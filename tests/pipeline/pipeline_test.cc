// The pipeline through its library API (pipeline/pipeline.h) on a small generated apartment, as a mesh and as a
// simulated point cloud: RunPipeline + WritePipelineOutputs write the same files, byte for byte, as `semvox run`
// on the same input with the same configuration, and the labels score above stated floors against the
// generator's ground truth (eval/evaluate.h, docs/metrics.md).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/log.h"
#include "eval/evaluate.h"
#include "pipeline/pipeline.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

int RunSemvox(const std::string& args, const std::string& log) {
  const int rc = std::system((std::string(SEMVOX_BINARY) + " " + args + " > " + log + " 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// tests/data/semantic.yaml, which the binary reads: fewer views than the defaults so the test stays short.
PipelineOptions ShortRunOptions() {
  PipelineOptions options;
  options.config.render.width = 320;
  options.config.render.height = 240;
  options.config.render.grid_spacing_m = 2.5;
  options.config.render.yaw_step_deg = 30;
  options.config.semantic.classify_yaw_step_deg = 45;
  options.config.semantic.crf.max_iterations = 3;
  options.models_dir = std::string(SEMVOX_SOURCE_DIR) + "/models";
  return options;
}

struct Floors {
  double geometric, visible, nyu4;
};

// Runs `input` through the library and through the binary; compares the outputs and scores the library's.
void ExpectLibraryEqualsBinaryAndScores(const std::string& input, const std::string& gt, const testing::ScratchDir& dir,
                                        const std::string& name, const Floors& floors) {
  const std::string lib = dir.File(name + "_lib"), cli = dir.File(name + "_cli"), log = dir.File(name + "_log.txt");
  std::filesystem::create_directories(lib);
  Result<PipelineResult> run = RunPipeline(input, ShortRunOptions());
  ASSERT_TRUE(run.ok()) << run.status().message();
  ASSERT_TRUE(run->labels.has_value() && run->evidence.has_value() && run->room_types.has_value() && run->objects);
  PipelineSummary summary;
  const Status written = WritePipelineOutputs(*run, lib, &summary);
  ASSERT_TRUE(written.ok()) << written.message();
  // The in-memory results are what the files hold.
  EXPECT_EQ(summary.json["semantic"]["occupied_voxels"].get<size_t>(), run->labels->map.occupied.size());
  EXPECT_EQ(summary.json["rooms"]["rooms"].get<int>(), run->rooms.num_rooms);
  EXPECT_EQ(summary.json["views"]["kept"].get<size_t>(), run->views.summary.kept);
  // The shipped models include the "other" and item labellers, and the summary counts what they relabelled.
  ASSERT_TRUE(run->models->other && run->models->items);
  EXPECT_EQ(summary.json["semantic"]["other_labels"]["voxels"].get<size_t>(), run->labels->other_voxels);
  EXPECT_EQ(summary.json["semantic"]["item_labels"]["voxels"].get<size_t>(), run->labels->item_voxels);

  ASSERT_EQ(RunSemvox("run " + input + " -o " + cli + " --models " + std::string(SEMVOX_SOURCE_DIR) + "/models --config " +
                          std::string(SEMVOX_SOURCE_DIR) + "/tests/data/semantic.yaml",
                      log),
            0)
      << testing::ReadText(log);
  for (const char* f : {"voxels.ply", "map.ot", "map.bt", "rooms.geojson", "rooms.png", "rooms.svg", "rooms_types.png",
                        "semantic_topview.png", "semantic_topview_labels.png", "occupancy.pgm", "occupancy.yaml", "views.json",
                        "support_clutter.ply", "object_proposals.json"})
  {
    ASSERT_TRUE(std::filesystem::exists(lib + "/" + f) && std::filesystem::exists(cli + "/" + f)) << name << ": " << f;
    EXPECT_TRUE(testing::ReadText(lib + "/" + f) == testing::ReadText(cli + "/" + f)) << name << ": " << f << " differs";
  }
  // summary.json: the same document apart from the seconds.
  auto without_seconds = [](nlohmann::json j) {
    for (const char* k : {"seconds", "cpu_seconds"}) j.erase(k);
    j["semantic"].erase("seconds");
    for (auto& it : j["semantic"]["iterations"]) it.erase("seconds"), it.erase("phase_seconds");
    j["rooms"]["room_types"].erase("seconds");
    j["objects"].erase("thread_seconds");
    return j;
  };
  EXPECT_EQ(without_seconds(nlohmann::json::parse(testing::ReadText(lib + "/summary.json"))),
            without_seconds(nlohmann::json::parse(testing::ReadText(cli + "/summary.json"))))
      << name;

  Result<EvalReport> e = Evaluate(lib, gt);
  ASSERT_TRUE(e.ok()) << e.status().message();
  const double geo = e->top_view.geometric_accuracy.value, visible = e->voxels.accuracy.value, nyu4 = e->voxels.nyu4_global.value;
  std::printf("%s: top-view geometric %.3f, visible-voxel accuracy %.3f, NYU-4 global %.3f, %zu labelled voxels\n", name.c_str(), geo,
              visible, nyu4, run->labels->map.occupied.size());
  EXPECT_GE(geo, floors.geometric) << name << ": top-view geometric accuracy";
  EXPECT_GE(visible, floors.visible) << name << ": visible-voxel accuracy (NYU40 ids)";
  EXPECT_GE(nyu4, floors.nyu4) << name << ": visible-voxel NYU-4 global accuracy";
}

TEST(Pipeline, LibraryWritesWhatTheBinaryWritesAndLabelsAboveTheStatedFloors) {
  SetLogLevel(LogLevel::kWarning);
  testing::ScratchDir dir("pipeline");
  const std::string gt = dir.File("gt"), log = dir.File("generate_log.txt");
  ASSERT_EQ(RunSemvox("generate --seed 106 --set apartment.max_rooms=3 --cloud -o " + gt, log), 0) << testing::ReadText(log);
  // Floors stated here, measured above them (the mesh: flat-coloured, as the classifiers were trained; the
  // cloud: simulated scanner, the cloud CRF weights).
  ExpectLibraryEqualsBinaryAndScores(gt + "/mesh.ply", gt, dir, "mesh", {0.90, 0.65, 0.80});
  ExpectLibraryEqualsBinaryAndScores(gt + "/cloud.ply", gt, dir, "cloud", {0.85, 0.55, 0.75});
}

TEST(Pipeline, MissingModelsDirectoryIsAnErrorNamingTheOption) {
  PipelineOptions options;
  const std::string input = std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply";
  Result<PipelineResult> run = RunPipeline(input, options);
  ASSERT_FALSE(run.ok());
  EXPECT_NE(run.status().message().find("models_dir"), std::string::npos) << run.status().message();
  // Without the semantic stage no models are needed, and there are no labels, evidence, room types or objects.
  options.config.semantic.enabled = false;
  options.config.render.width = 160;
  options.config.render.height = 120;
  run = RunPipeline(input, options);
  ASSERT_TRUE(run.ok()) << run.status().message();
  EXPECT_FALSE(run->labels || run->evidence || run->room_types || run->objects);
  EXPECT_GT(run->rooms.num_rooms, 1);
  EXPECT_EQ(&run->final_grid(), &run->map.grid);
}

}  // namespace
}  // namespace semvox
