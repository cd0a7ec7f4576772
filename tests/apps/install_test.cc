// Where the binary finds its models (apps/models_dir.h), and `cmake --install`: the installed binary maps the
// demo apartment with the models installed beside it, from a working directory outside the source tree and
// without $SEMVOX_MODELS; with those models gone it fails with one error line naming --models.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "apps/models_dir.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

namespace fs = std::filesystem;

// Sets (or with nullptr unsets) $SEMVOX_MODELS for the test's lifetime; restores it afterwards.
class ScopedModelsEnv {
 public:
  explicit ScopedModelsEnv(const char* value) {
    if (const char* old = std::getenv("SEMVOX_MODELS")) old_ = old, had_ = true;
    value ? ::setenv("SEMVOX_MODELS", value, 1) : ::unsetenv("SEMVOX_MODELS");
  }
  ~ScopedModelsEnv() { had_ ? ::setenv("SEMVOX_MODELS", old_.c_str(), 1) : ::unsetenv("SEMVOX_MODELS"); }

 private:
  std::string old_;
  bool had_ = false;
};

struct Outcome {
  int exit_code;
  std::string stderr_text;
};

// Runs `command` through the shell in `cwd`, stdout discarded.
Outcome RunIn(const std::string& cwd, const std::string& command, const testing::ScratchDir& dir) {
  const std::string err = dir.File("stderr.txt");
  const int rc = std::system(("cd " + cwd + " && " + command + " > /dev/null 2> " + err).c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, testing::ReadText(err)};
}

TEST(ModelsDir, FlagThenEnvironmentThenBesideTheExecutable) {
  {
    ScopedModelsEnv env("/from/env");
    Result<std::string> flag = ResolveModelsDir("/from/flag", "");
    ASSERT_TRUE(flag.ok());
    EXPECT_EQ(*flag, "/from/flag");
    Result<std::string> from_env = ResolveModelsDir("", "");
    ASSERT_TRUE(from_env.ok());
    EXPECT_EQ(*from_env, "/from/env");
  }
  // This test binary is in BUILD/bin too: BUILD/share/semvox/models links to the source tree's models/.
  ScopedModelsEnv env(nullptr);
  Result<std::string> beside = ResolveModelsDir("", "");
  ASSERT_TRUE(beside.ok()) << beside.status().message();
  EXPECT_EQ(*beside, fs::canonical(std::string(SEMVOX_SOURCE_DIR) + "/models").string());
  EXPECT_EQ(ModelsDirBesideExecutable("/opt/semvox/bin/semvox"), "/opt/semvox/share/semvox/models");
  EXPECT_EQ(ExecutablePath(""), fs::read_symlink("/proc/self/exe").string());
}

TEST(Install, InstalledBinaryFindsItsModelsAndFailsClearlyWithoutThem) {
  testing::ScratchDir dir("install");
  const std::string prefix = dir.File("prefix");
  Outcome o = RunIn(dir.path().string(),
                    std::string(SEMVOX_CMAKE_COMMAND) + " --install " + SEMVOX_BUILD_DIR + " --prefix " + prefix, dir);
  ASSERT_EQ(o.exit_code, 0) << o.stderr_text;

  // The binary alone in bin/, and a copy (not a link) of every file of models/.
  const fs::path models = fs::path(prefix) / "share/semvox/models";
  std::vector<std::string> binaries;
  for (const auto& e : fs::directory_iterator(fs::path(prefix) / "bin")) binaries.push_back(e.path().filename().string());
  EXPECT_EQ(binaries, std::vector<std::string>{"semvox"});
  ASSERT_TRUE(fs::is_directory(models));
  EXPECT_FALSE(fs::is_symlink(models));
  size_t shipped = 0;
  for (const auto& e : fs::directory_iterator(std::string(SEMVOX_SOURCE_DIR) + "/models")) {
    ++shipped;
    const fs::path copy = models / e.path().filename();
    ASSERT_TRUE(fs::is_regular_file(copy) && !fs::is_symlink(copy)) << copy;
    EXPECT_EQ(fs::file_size(copy), fs::file_size(e.path())) << copy;
  }
  EXPECT_GT(shipped, 0u);

  // tests/data/fast.yaml's views with the semantic stage on (fast.yaml turns it off, and then no model is
  // read): small classification views, one CRF iteration.
  const std::string config = dir.File("fast_semantic.yaml");
  testing::WriteText(config,
                     "render:\n  width: 80\n  height: 60\n  grid_spacing_m: 3.0\n  yaw_step_deg: 90\n"
                     "semantic:\n  classify_yaw_step_deg: 90\n  classify_width: 80\n  classify_height: 60\n  max_iterations: 1\n");
  const std::string work = dir.File("work");  // The working directory: outside the source and build trees.
  fs::create_directories(work);
  const std::string run = prefix + "/bin/semvox run " + std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply --config " +
                          config + " -q -o ";
  ScopedModelsEnv env(nullptr);

  const std::string out = dir.File("out");
  o = RunIn(work, run + out, dir);
  ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
  for (const char* f : {"summary.json", "voxels.ply", "rooms.geojson", "occupancy.pgm"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  const auto summary = nlohmann::json::parse(testing::ReadText(out + "/summary.json"));
  const std::string room_model = summary["rooms"]["room_types"]["model"].get<std::string>();
  EXPECT_EQ(room_model, (fs::canonical(models) / "room_type_crf.json").string()) << "read models from elsewhere";

  // Without the installed models: one error line that says where it looked and names --models; nothing written.
  fs::rename(models, dir.File("moved_models"));
  const std::string out2 = dir.File("out2");
  o = RunIn(work, run + out2, dir);
  EXPECT_EQ(o.exit_code, 2) << o.stderr_text;
  EXPECT_EQ(std::count(o.stderr_text.begin(), o.stderr_text.end(), '\n'), 1) << o.stderr_text;
  EXPECT_EQ(o.stderr_text.rfind("semvox: error: no models directory", 0), 0u) << o.stderr_text;
  for (const std::string& what : {std::string("--models"), std::string("SEMVOX_MODELS"), models.string()})
    EXPECT_NE(o.stderr_text.find(what), std::string::npos) << what << " not in: " << o.stderr_text;
  EXPECT_FALSE(fs::exists(out2)) << "the failed run wrote " << out2;
}

}  // namespace
}  // namespace semvox
