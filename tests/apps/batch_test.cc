#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "tests/test_util.h"

namespace semvox {
namespace {
namespace fs = std::filesystem;

int Batch(const std::string& args) {
  const int rc = std::system((std::string(SEMVOX_BINARY) + " batch " + args + " > /dev/null 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

TEST(Batch, KeepsGoingPastFailuresWritesAnIndexAndResumes) {
  testing::ScratchDir dir("batch");
  const std::string demo = std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply";
  const std::string fast = std::string(SEMVOX_SOURCE_DIR) + "/tests/data/fast.yaml";
  testing::WriteText(dir.File("manifest.txt"), "# scans\nflat_a " + demo + "\nmissing_scan.ply\nflat_b " + demo + "\n");
  const std::string root = dir.File("root");
  const std::string args = dir.File("manifest.txt") + " -o " + root + " -j 2 --config " + fast;
  EXPECT_EQ(Batch(args), 1);  // One scan failed.
  auto index = nlohmann::json::parse(testing::ReadText(root + "/index.json"));
  ASSERT_EQ(index.size(), 3u);
  EXPECT_EQ(index[0]["name"], "flat_a");
  EXPECT_EQ(index[0]["status"], "ok");
  EXPECT_EQ(index[1]["name"], "missing_scan");
  EXPECT_EQ(index[1]["status"], "failed");
  EXPECT_EQ(index[1]["exit_code"], 2);
  EXPECT_NE(index[1]["error"].get<std::string>().find("no such file"), std::string::npos);
  EXPECT_EQ(index[2]["status"], "ok");
  EXPECT_TRUE(fs::exists(root + "/flat_b/summary.json"));
  EXPECT_NE(testing::ReadText(root + "/index.csv").find("missing_scan"), std::string::npos);

  // Resume: complete scans are skipped; a removed one is redone.
  fs::remove_all(root + "/flat_b");
  EXPECT_EQ(Batch(args), 1);
  index = nlohmann::json::parse(testing::ReadText(root + "/index.json"));
  EXPECT_EQ(index[0]["status"], "skipped");
  EXPECT_EQ(index[2]["status"], "ok");
  EXPECT_TRUE(fs::exists(root + "/flat_b/summary.json"));
}

TEST(Batch, RejectsAnEmptyManifest) {
  testing::ScratchDir dir("batch_empty");
  testing::WriteText(dir.File("m.txt"), "# nothing\n\n");
  EXPECT_EQ(Batch(dir.File("m.txt") + " -o " + dir.File("root")), 2);
  EXPECT_EQ(Batch(dir.File("none.txt") + " -o " + dir.File("root")), 2);
}

}  // namespace
}  // namespace semvox
