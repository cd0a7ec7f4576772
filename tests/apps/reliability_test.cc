// Reliability of `semvox run`: determinism, interrupt safety, and the bad-input matrix (docs/reliability.md).
#include <gtest/gtest.h>

#include <regex>
#include <signal.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "core/mesh_ply.h"
#include "scenegen/demo_scene.h"
#include "scenegen/mesh_builder.h"
#include "tests/test_util.h"

namespace semvox {
namespace {
namespace fs = std::filesystem;

struct Outcome {
  int exit_code;
  std::string err;
};

// Runs `semvox ARGS`; `run` gets the fast test configuration unless ARGS bring their own.
Outcome RunSemvox(std::string args, const testing::ScratchDir& dir) {
  if (args.rfind("run ", 0) == 0 && args.find("--config") == std::string::npos)
    args += " --config " + std::string(SEMVOX_SOURCE_DIR) + "/tests/data/fast.yaml";
  const std::string err = dir.File("stderr.txt");
  const int rc = std::system((std::string(SEMVOX_BINARY) + " " + args + " > /dev/null 2> " + err).c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, testing::ReadText(err)};
}

std::vector<std::string> Listing(const std::string& dir) {
  std::vector<std::string> out;
  if (!fs::exists(dir)) return out;
  for (auto& e : fs::recursive_directory_iterator(dir)) out.push_back(fs::relative(e.path(), dir).string());
  std::sort(out.begin(), out.end());
  return out;
}

// summary.json without its timing fields.
nlohmann::json WithoutTimings(nlohmann::json s) {
  s.erase("seconds");
  s.erase("cpu_seconds");
  if (s.contains("views")) s["views"].erase("seconds");
  return s;
}

TEST(Reliability, TwoRunsGiveByteIdenticalOutputs) {
  testing::ScratchDir dir("determinism");
  const std::string demo = std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply";
  ASSERT_EQ(RunSemvox("run " + demo + " -o " + dir.File("a") + " -q", dir).exit_code, 0);
  ASSERT_EQ(RunSemvox("run " + demo + " -o " + dir.File("b") + " -q", dir).exit_code, 0);
  const auto files = Listing(dir.File("a"));
  ASSERT_EQ(files, Listing(dir.File("b")));
  ASSERT_FALSE(files.empty());
  for (const std::string& f : files) {
    if (fs::is_directory(dir.File("a/" + f))) continue;
    const std::string a = testing::ReadText(dir.File("a/" + f)), b = testing::ReadText(dir.File("b/" + f));
    if (f == "summary.json") {
      EXPECT_EQ(WithoutTimings(nlohmann::json::parse(a)), WithoutTimings(nlohmann::json::parse(b)));
    } else if (f == "report.html") {
      // The report shows seconds per stage and per CRF iteration; everything else must match.
      const std::regex timings(R"(<table class="time"[\s\S]*?</table>|<td class="seconds">[^<]*</td>)");
      // It also names its own directory (a or b).
      auto normalise = [&](std::string html, const std::string& self) {
        for (size_t p; (p = html.find(dir.File(self))) != std::string::npos;) html.replace(p, dir.File(self).size(), "OUTDIR");
        html = std::regex_replace(html, std::regex("semvox report: " + self + "<"), "semvox report: OUTDIR<");
        return std::regex_replace(html, timings, "");
      };
      EXPECT_EQ(normalise(a, "a"), normalise(b, "b")) << "report.html differs beyond timings";
    } else {
      EXPECT_TRUE(a == b) << f << " differs between runs";
    }
  }
}

// Interrupt a run of the demo scene at several moments (before, during and after output writing).
TEST(Reliability, InterruptLeavesNoPartialOutputAndARerunCompletes) {
  testing::ScratchDir dir("interrupt");
  const std::string input = std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply";
  const std::string fast = std::string(SEMVOX_SOURCE_DIR) + "/tests/data/fast.yaml";
  for (int delay_ms : {200, 900, 2000}) {
    const std::string out = dir.File("out" + std::to_string(delay_ms));
    const pid_t pid2 = fork();
    ASSERT_GE(pid2, 0);
    if (pid2 == 0) {
      const int devnull = ::open("/dev/null", O_WRONLY);
      ::dup2(devnull, 1), ::dup2(devnull, 2);
      ::execl(SEMVOX_BINARY, "semvox", "run", input.c_str(), "-o", out.c_str(), "--config", fast.c_str(), nullptr);
      _exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    ::kill(pid2, SIGINT);
    int status = 0;
    ::waitpid(pid2, &status, 0);
    for (const std::string& f : Listing(out)) EXPECT_EQ(f.find(".tmp."), std::string::npos) << f;
    // Whatever was written is complete: summary.json, when present, parses.
    if (fs::exists(out + "/summary.json")) {
      EXPECT_NO_THROW({
        const nlohmann::json parsed = nlohmann::json::parse(testing::ReadText(out + "/summary.json"));
        EXPECT_TRUE(parsed.is_object());
      });
    }
    // A re-run into the same directory completes.
    const Outcome again = RunSemvox("run " + input + " -o " + out + " -q", dir);
    EXPECT_EQ(again.exit_code, 0) << again.err;
    EXPECT_TRUE(fs::exists(out + "/summary.json"));
  }
}

// ---- The bad-input matrix ----

// The demo apartment scaled and shifted; `y_up`: +Y up; `camera`: in a camera's frame (x right, y down, z forward).
void WriteRoom(const std::string& path, double scale, bool y_up, double offset, bool camera = false) {
  Mesh m = BuildDemoApartment();
  for (auto& v : m.vertices) {
    Eigen::Vector3d p = v.cast<double>();
    if (y_up) p = Eigen::Vector3d(p.x(), p.z(), -p.y());
    if (camera) p = Eigen::Vector3d(p.x(), -p.z(), p.y());
    v = (p * scale + Eigen::Vector3d::Constant(offset)).cast<float>();
  }
  ASSERT_TRUE(WriteMeshPly(path, m).ok());
}

struct MatrixCase {
  std::string name;      // Row name in docs/reliability.md.
  std::string args;      // {D} = scratch dir, {DEMO} = demo scene; output is {D}/out unless args say otherwise.
  int exit_code;         // 0 = completes (degraded input), 2 = input error.
  std::string expect;    // Substring of stderr (the error line, or the warning).
};

TEST(Reliability, BadInputMatrix) {
  testing::ScratchDir dir("matrix");
  const std::string D = dir.path().string();
  // Inputs for the rows.
  testing::WriteText(dir.File("empty.ply"), "");
  testing::WriteText(dir.File("empty.pcd"), "");
  testing::WriteText(dir.File("empty.txt"), "");
  testing::WriteText(dir.File("empty.obj"), "");
  testing::WriteText(dir.File("magic.ply"), "PK\x03\x04 zip");
  testing::WriteText(dir.File("magic.pcd"), "hello world\n");
  testing::WriteText(dir.File("magic.obj"), "\x7f" "ELF\x01\x01");
  testing::WriteText(dir.File("absurd.ply"),
                     "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                     "property float y\nproperty float z\nend_header\n" + std::string(24, '\0'));
  testing::WriteText(dir.File("absurd.pcd"),
                     "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 999999999\nHEIGHT 1\n"
                     "POINTS 999999999\nDATA binary\n" + std::string(24, '\0'));
  {
    Mesh tri;
    tri.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    tri.faces = {{0, 1, 2}};
    ASSERT_TRUE(WriteMeshPly(dir.File("full.ply"), tri).ok());
    const std::string full = testing::ReadText(dir.File("full.ply"));
    testing::WriteText(dir.File("trunc.ply"), full.substr(0, full.size() - 5));
  }
  testing::WriteText(dir.File("trunc.pcd"),
                     "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 100\nHEIGHT 1\n"
                     "POINTS 100\nDATA binary\n" + std::string(40, '\0'));
  testing::WriteText(dir.File("trunc.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 ");
  testing::WriteText(dir.File("nan.txt"), "nan nan nan\ninf 0 0\n0 0 nan\n");
  {
    std::string t;
    for (int i = 0; i < 200; ++i) t += std::to_string(i % 10 * 0.1) + " " + std::to_string(i / 10 * 0.1) + " 0\n";
    t += "nan 1 1\n";
    testing::WriteText(dir.File("some_nan.txt"), t);
    testing::WriteText(dir.File("plane.txt"), t.substr(0, t.rfind("nan")));
  }
  testing::WriteText(dir.File("degenerate.obj"), "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n");
  WriteRoom(dir.File("far.ply"), 1.0, false, 1e7);
  WriteRoom(dir.File("mm.ply"), 1000.0, false, 0.0);
  WriteRoom(dir.File("yup.ply"), 1.0, true, 0.0);
  WriteRoom(dir.File("camera.ply"), 1.0, false, 0.0, true);
  {
    MeshBuilder walls;  // Four walls, no floor or ceiling.
    walls.AddBox({0, 0, 0}, {4, 0.1, 2.5}, Rgb8{}, FaceTags{}, 0, true);
    walls.AddBox({0, 2.9, 0}, {4, 3, 2.5}, Rgb8{}, FaceTags{}, 0, true);
    walls.AddBox({0, 0, 0}, {0.1, 3, 2.5}, Rgb8{}, FaceTags{}, 0, true);
    walls.AddBox({3.9, 0, 0}, {4, 3, 2.5}, Rgb8{}, FaceTags{}, 0, true);
    Mesh m = walls.Take();
    std::vector<Eigen::Vector3i> vertical;
    for (const auto& f : m.faces) {
      const Eigen::Vector3f n = (m.vertices[f[1]] - m.vertices[f[0]]).cross(m.vertices[f[2]] - m.vertices[f[0]]);
      if (std::fabs(n.normalized().z()) < 0.5f) vertical.push_back(f);
    }
    m.faces = vertical;
    m.face_attributes.clear();
    ASSERT_TRUE(WriteMeshPly(dir.File("nofloor.ply"), m).ok());
  }
  fs::create_directories(dir.File("scan_dir"));
  fs::copy_file(std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply", dir.File("scan_dir/scan.ply"));
  testing::WriteText(dir.File("cfg_unknown.yaml"), "mapping:\n  voxelsize: 1\n");
  testing::WriteText(dir.File("cfg_range.yaml"), "mapping:\n  scan_spacing_m: -1\n");
  testing::WriteText(dir.File("cfg_syntax.yaml"), "mapping: {voxel_size_m: [\n");

  const std::vector<MatrixCase> cases = {
      {"missing mesh", "run {D}/nope.ply -o {D}/out", 2, "nope.ply: no such file"},
      {"missing cloud", "run {D}/nope.pcd -o {D}/out", 2, "nope.pcd: no such file"},
      {"empty PLY", "run {D}/empty.ply -o {D}/out", 2, "empty.ply: file is empty"},
      {"empty PCD", "run {D}/empty.pcd -o {D}/out", 2, "empty.pcd: file is empty"},
      {"empty text cloud", "run {D}/empty.txt -o {D}/out", 2, "empty.txt: file is empty"},
      {"empty OBJ", "run {D}/empty.obj -o {D}/out", 2, "empty.obj: file is empty"},
      {"wrong magic PLY", "run {D}/magic.ply -o {D}/out", 2, "magic.ply: not a PLY file"},
      {"wrong magic PCD", "run {D}/magic.pcd -o {D}/out", 2, "magic.pcd: not a PCD file"},
      {"wrong magic OBJ", "run {D}/magic.obj -o {D}/out", 2, "magic.obj"},
      {"absurd PLY count", "run {D}/absurd.ply -o {D}/out", 2, "declares 4000000000 vertex"},
      {"absurd PCD count", "run {D}/absurd.pcd -o {D}/out", 2, "absurd.pcd"},
      {"truncated PLY", "run {D}/trunc.ply -o {D}/out", 2, "trunc.ply: truncated PLY"},
      {"truncated PCD", "run {D}/trunc.pcd -o {D}/out", 2, "trunc.pcd"},
      {"truncated OBJ", "run {D}/trunc.obj -o {D}/out", 2, "trunc.obj"},
      {"only NaN/Inf", "run {D}/nan.txt -o {D}/out", 2, "too little valid geometry"},
      {"some NaN", "run {D}/some_nan.txt -o {D}/out", 0, "dropped 1 points with non-finite coordinates"},
      {"only degenerate triangles", "run {D}/degenerate.obj -o {D}/out", 2, "degenerate.obj"},
      {"single plane", "run {D}/plane.txt -o {D}/out", 0, "does not look like an enclosed interior"},
      {"no floor", "run {D}/nofloor.ply -o {D}/out", 0, "no floor found"},
      {"coordinates near 1e7", "run {D}/far.ply -o {D}/out", 2, "beyond OctoMap's key range"},
      {"millimetre units", "run {D}/mm.ply -o {D}/out", 2, "--scale"},
      {"millimetre units with --scale", "run {D}/mm.ply --scale 0.001 -o {D}/out", 0, ""},
      {"Y-up with --up y", "run {D}/yup.ply --up y -o {D}/out", 0, ""},
      {"camera frame (y down) with --up=-y", "run {D}/camera.ply --up=-y -o {D}/out", 0, ""},
      {"unknown up axis", "run {DEMO} --up w -o {D}/out", 2, "--up"},
      {"read-only output location", "run {DEMO} -o /proc/semvox_out", 2, "/proc/semvox_out"},
      {"output path is a file", "run {DEMO} -o {D}/empty.ply", 2, "exists and is not a directory"},
      {"output inside the input's directory", "run {D}/scan_dir/scan.ply -o {D}/scan_dir/out", 0, ""},
      {"unknown config key", "run {DEMO} --config {D}/cfg_unknown.yaml -o {D}/out", 2, "unknown key 'mapping.voxelsize'"},
      {"config value out of range", "run {DEMO} --config {D}/cfg_range.yaml -o {D}/out", 2, "mapping.scan_spacing_m = -1"},
      {"room-type calibration on validation plans", "train --room-type-evidence --r2v-dir {D} --room-type-calibration-plans 290-310 -o {D}/models_x",
       2, "plan 300 is a validation plan"},
      {"per-view training on plans without plans", "train --view-plans 5 --r2v-dir {D}/no_plans -o {D}/models_y", 2,
       "no_plans: no such directory (the R2V plans)"},
      {"config syntax error", "run {DEMO} --config {D}/cfg_syntax.yaml -o {D}/out", 2, "invalid YAML"},
      {"missing config", "run {DEMO} --config {D}/none.yaml -o {D}/out", 2, "none.yaml: no such file"},
  };
  const std::string demo = std::string(SEMVOX_SOURCE_DIR) + "/scenes/demo_apartment.ply";
  for (const MatrixCase& c : cases) {
    std::string args = c.args;
    for (auto [key, value] : {std::pair<std::string, std::string>{"{D}", D}, {"{DEMO}", demo}})
      for (size_t p; (p = args.find(key)) != std::string::npos;) args.replace(p, key.size(), value);
    fs::remove_all(dir.File("out"));
    fs::remove_all(dir.File("scan_dir/out"));
    const Outcome o = RunSemvox(args + (c.exit_code == 0 ? " -q" : ""), dir);
    EXPECT_EQ(o.exit_code, c.exit_code) << c.name << ": " << o.err;
    EXPECT_NE(o.err.find(c.expect), std::string::npos) << c.name << ": expected '" << c.expect << "' in: " << o.err;
    if (c.exit_code != 0) {
      // Exactly one error line, the last one (warnings may precede it).
      size_t errors = 0;
      for (size_t p = 0; (p = o.err.find("semvox: error: ", p)) != std::string::npos; ++p) ++errors;
      EXPECT_EQ(errors, 1u) << c.name << ": " << o.err;
      EXPECT_NE(o.err.rfind("semvox: error: "), std::string::npos);
      EXPECT_EQ(o.err.find('\n', o.err.rfind("semvox: error: ")), o.err.size() - 1) << c.name << ": " << o.err;
      EXPECT_TRUE(Listing(dir.File("out")).empty()) << c.name;
    } else {
      const std::string out = c.name == "output inside the input's directory" ? dir.File("scan_dir/out") : dir.File("out");
      EXPECT_TRUE(fs::exists(out + "/summary.json")) << c.name;
      EXPECT_TRUE(fs::exists(out + "/occupancy.pgm")) << c.name;
    }
  }
}

}  // namespace
}  // namespace semvox
