// `semvox generate --seed N` through the binary: same bytes for every file (the cloud included), and
// bad settings rejected with exit code 2.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

int RunSemvox(const std::string& args) {
  const int st = std::system((std::string(SEMVOX_BINARY) + " -q " + args + " >/dev/null 2>&1").c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

std::string Slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream os;
  os << f.rdbuf();
  return os.str();
}

TEST(GenerateCommand, SameSeedSameBytesWithCloud) {
  if (!fs::exists(SEMVOX_BINARY)) GTEST_SKIP() << "semvox binary not built";
  const fs::path root = fs::temp_directory_path() / ("semvox_generate_cli_" + std::to_string(::getpid()));
  fs::remove_all(root);
  for (const char* d : {"a", "b"})
    ASSERT_EQ(RunSemvox("generate --seed 21 --cloud --set scan.azimuth_steps=180 --set scan.elevation_steps=90 -o " + (root / d).string()), 0);
  for (const char* name : {"mesh.ply", "gt_mesh.ply", "cloud.ply", "gt.json", "rooms_gt.png", "topview_gt.png", "preview.png"}) {
    const std::string a = Slurp(root / "a" / name), b = Slurp(root / "b" / name);
    EXPECT_FALSE(a.empty()) << name;
    EXPECT_EQ(a, b) << name;
  }
  EXPECT_EQ(RunSemvox("generate --seed 21 --set artefacts.no_such_field=1 -o " + (root / "c").string()), 2);
  EXPECT_EQ(RunSemvox("generate --seed 21 --set artefacts.face_dropout=2 -o " + (root / "c").string()), 2);
  EXPECT_FALSE(fs::exists(root / "c" / "mesh.ply")) << "nothing written on bad options";
  fs::remove_all(root);
}

}  // namespace
