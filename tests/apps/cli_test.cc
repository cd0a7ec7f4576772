// The semvox binary end to end: outputs of `semvox run`, and one clear error line with exit code 2 and no
// partial outputs for every bad input.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/mesh_ply.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

struct Outcome {
  int exit_code;
  std::string stderr_text;
};

Outcome RunSemvox(const std::string& args, const testing::ScratchDir& dir) {
  const std::string err = dir.File("stderr.txt");
  const std::string cmd = std::string(SEMVOX_BINARY) + " " + args + " > /dev/null 2> " + err;
  const int rc = std::system(cmd.c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, testing::ReadText(err)};
}

size_t CountEntries(const std::string& dir) {
  if (!std::filesystem::exists(dir)) return 0;
  size_t n = 0;
  for (auto& e : std::filesystem::directory_iterator(dir)) (void)e, ++n;
  return n;
}

TEST(Cli, RunOnTheDemoSceneWritesEveryOutput) {
  testing::ScratchDir dir("cli_run");
  const std::string out = dir.File("out");
  const Outcome o = RunSemvox("run " + std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply -o " + out +
                                  " --config " + std::string(SEMVOX_SOURCE_DIR) + "/tests/data/fast.yaml", dir);
  ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
  for (const char* f : {"occupancy.pgm", "occupancy.yaml", "map.bt", "summary.json", "config_used.yaml"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + f)) << f;
  const auto s = nlohmann::json::parse(testing::ReadText(out + "/summary.json"));
  EXPECT_EQ(s["input"]["kind"], "mesh");
  EXPECT_TRUE(s["floor"]["found"].get<bool>());
  EXPECT_NEAR(s["floor"]["z"].get<double>(), 0.0, 0.01);
  EXPECT_NEAR(s["ceiling"]["z"].get<double>(), 2.6, 0.01);
  EXPECT_GT(s["voxels"]["free"].get<long>(), 0);
  EXPECT_GT(s["voxels"]["occupied"].get<long>(), 0);
  EXPECT_TRUE(s["seconds"].contains("voxelize"));
  for (auto& e : std::filesystem::directory_iterator(out))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
}

// `semvox run` prints its stages and a short summary by default; each step's detail only with -v; with -q nothing
// but warnings and errors.
TEST(Cli, RunIsQuietByDefaultAndDetailedWithVerbose) {
  testing::ScratchDir dir("cli_verbosity");
  const std::string run = "run " + std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply --config " +
                          std::string(SEMVOX_SOURCE_DIR) + "/tests/data/fast.yaml -o ";
  const Outcome plain = RunSemvox(run + dir.File("plain"), dir);
  ASSERT_EQ(plain.exit_code, 0) << plain.stderr_text;
  EXPECT_NE(plain.stderr_text.find("voxelize done in"), std::string::npos) << plain.stderr_text;
  EXPECT_NE(plain.stderr_text.find("rooms: 3"), std::string::npos) << plain.stderr_text;
  EXPECT_NE(plain.stderr_text.find("outputs in"), std::string::npos) << plain.stderr_text;
  EXPECT_EQ(plain.stderr_text.find("voxelised at"), std::string::npos) << plain.stderr_text;
  const Outcome verbose = RunSemvox(run + dir.File("verbose") + " -v", dir);
  ASSERT_EQ(verbose.exit_code, 0) << verbose.stderr_text;
  EXPECT_NE(verbose.stderr_text.find("voxelised at"), std::string::npos) << verbose.stderr_text;
  EXPECT_NE(verbose.stderr_text.find("outputs in"), std::string::npos) << verbose.stderr_text;
  const Outcome quiet = RunSemvox(run + dir.File("quiet") + " -q", dir);
  ASSERT_EQ(quiet.exit_code, 0) << quiet.stderr_text;
  EXPECT_EQ(quiet.stderr_text.find("outputs in"), std::string::npos) << quiet.stderr_text;
  EXPECT_EQ(quiet.stderr_text.find("done in"), std::string::npos) << quiet.stderr_text;
}

TEST(Cli, BadInputsGiveOneLineExitTwoAndNoOutputs) {
  testing::ScratchDir dir("cli_bad");
  testing::WriteText(dir.File("empty.ply"), "");
  testing::WriteText(dir.File("magic.ply"), "solid x\n");
  Mesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.faces = {{0, 1, 2}};
  ASSERT_TRUE(WriteMeshPly(dir.File("tri.ply"), m).ok());
  const std::string full = testing::ReadText(dir.File("tri.ply"));
  testing::WriteText(dir.File("trunc.ply"), full.substr(0, full.size() - 7));
  testing::WriteText(dir.File("nofaces.stl"), "solid x\nendsolid x\n");
  testing::WriteText(dir.File("x.abc"), "1 2 3\n");
  testing::WriteText(dir.File("a_file"), "x");
  testing::WriteText(dir.File("bad.yaml"), "mapping:\n  voxel_size: 0.05\n");
  testing::WriteText(dir.File("range.yaml"), "mapping:\n  voxel_size_m: 7\n");
  const std::string demo = std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply";
  struct Case {
    std::string args, expect, outdir;
  };
  const std::vector<Case> cases = {
      {"run " + dir.File("missing.ply") + " -o OUT", "missing.ply: no such file", dir.File("o1")},
      {"run " + dir.File("empty.ply") + " -o OUT", "empty.ply: file is empty", dir.File("o2")},
      {"run " + dir.File("magic.ply") + " -o OUT", "magic.ply: not a PLY", dir.File("o3")},
      {"run " + dir.File("trunc.ply") + " -o OUT", "trunc.ply: truncated", dir.File("o4")},
      {"run " + dir.File("nofaces.stl") + " -o OUT", "nofaces.stl", dir.File("o5")},
      {"run " + dir.File("x.abc") + " -o OUT", "unsupported file extension", dir.File("o6")},
      {"run " + demo + " -o OUT", "a_file/out", dir.File("a_file/out")},
      {"run " + demo + " --config " + dir.File("bad.yaml") + " -o OUT", "unknown key 'mapping.voxel_size'", dir.File("o8")},
      {"run " + demo + " --config " + dir.File("range.yaml") + " -o OUT", "mapping.voxel_size_m = 7", dir.File("o9")},
      {"run " + demo + " --scale -1 -o OUT", "scale", dir.File("o10")},
      {"run", "input", dir.File("o11")},
  };
  for (const Case& c : cases) {
    std::string args = c.args;
    if (auto p = args.find("OUT"); p != std::string::npos) args.replace(p, 3, c.outdir);
    const Outcome o = RunSemvox(args, dir);
    EXPECT_EQ(o.exit_code, 2) << args << "\n" << o.stderr_text;
    EXPECT_EQ(std::count(o.stderr_text.begin(), o.stderr_text.end(), '\n'), 1) << args << "\n" << o.stderr_text;
    EXPECT_EQ(o.stderr_text.rfind("semvox: error: ", 0), 0u) << o.stderr_text;
    EXPECT_NE(o.stderr_text.find(c.expect), std::string::npos) << "expected '" << c.expect << "' in: " << o.stderr_text;
    EXPECT_EQ(CountEntries(c.outdir), 0u) << args;
  }
}

TEST(Cli, ConfigDumpIsAValidConfiguration) {
  testing::ScratchDir dir("cli_cfg");
  const std::string cmd = std::string(SEMVOX_BINARY) + " config --dump > " + dir.File("d.yaml");
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const Outcome o = RunSemvox("config --check " + dir.File("d.yaml"), dir);
  EXPECT_EQ(o.exit_code, 0) << o.stderr_text;
}

}  // namespace
}  // namespace semvox
