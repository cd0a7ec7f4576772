// The 3D view of report.html: voxels.ply onto the view's grid (canonical frame, sizes, attributes,
// merging, room groups, packing) and, in headless Chromium with software WebGL (skipped without chromium or
// three.js), the page itself: no console output, #3d fills the window with the label colours, switches and the
// fragment change the picture, a click names the voxel, and a page without voxels or WebGL says so in one line.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <regex>

#include "core/labels.h"
#include "core/ply.h"
#include "report/report.h"
#include "report/view3d.h"
#include "tests/report/chromium.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

struct Voxel {
  double x, y, z;
  int label;
  double confidence = 1;
  int room = -1;
  int completed = 0;
};

PlyData MakePly(const std::vector<Voxel>& voxels, bool with_attributes = true) {
  std::vector<double> x, y, z, label, confidence, room, completed;
  for (const Voxel& v : voxels) {
    x.push_back(v.x), y.push_back(v.y), z.push_back(v.z), label.push_back(v.label);
    confidence.push_back(v.confidence), room.push_back(v.room), completed.push_back(v.completed);
  }
  PlyWriter w;
  w.AddElement("vertex", voxels.size());
  w.AddProperty("x", PlyType::kFloat32, x);
  w.AddProperty("y", PlyType::kFloat32, y);
  w.AddProperty("z", PlyType::kFloat32, z);
  w.AddProperty("label", PlyType::kUInt16, label);
  if (with_attributes) {
    w.AddProperty("confidence", PlyType::kFloat32, confidence);
    w.AddProperty("room", PlyType::kInt32, room);
    w.AddProperty("completed", PlyType::kUInt8, completed);
  }
  Result<PlyData> ply = ParsePly(w.Serialize(), "test.ply");
  EXPECT_TRUE(ply.ok()) << ply.status().message();
  return ply.ok() ? std::move(ply).value() : PlyData();
}

constexpr double kSize = 0.05;

// Voxel centre of cell (i, j, k) of a 5 cm grid whose cell (0, 0, 0) is centred at (1.025, 2.025, 0.025).
Voxel At(int i, int j, int k, int label) { return {1.025 + i * kSize, 2.025 + j * kSize, 0.025 + k * kSize, label}; }

TEST(View3d, PutsTheVoxelsOnTheGridWithTheirAttributes) {
  std::vector<Voxel> vs = {At(3, 0, 1, nyu40::kChair), At(0, 2, 0, nyu40::kFloor), At(1, 0, 0, nyu40::kWall), At(3, 0, 1, nyu40::kTable)};
  vs[0].confidence = 1.7, vs[0].room = 4, vs[0].completed = 1;  // Confidence clamped to 1.
  vs[1].confidence = 0.25, vs[1].room = 2;
  Result<View3dVoxels> r = View3dVoxelsFromPly(MakePly(vs), "v.ply", Eigen::Isometry3d::Identity(), kSize);
  ASSERT_TRUE(r.ok()) << r.status().message();
  const View3dVoxels& v = r.value();
  EXPECT_EQ(v.source_voxels, 4u);
  EXPECT_TRUE(v.has_confidence && v.has_room && v.has_completed);
  EXPECT_EQ(v.dims, (std::array<int32_t, 3>{4, 3, 2}));
  EXPECT_NEAR(v.origin.x(), 1.025, 1e-6);
  EXPECT_NEAR(v.origin.y(), 2.025, 1e-6);
  EXPECT_NEAR(v.origin.z(), 0.025, 1e-6);
  // Sorted by (z, y, x); the second voxel in cell (3, 0, 1) is dropped, the first (chair) kept.
  ASSERT_EQ(v.cells.size(), 3u);
  EXPECT_EQ(v.cells[0].ijk, (std::array<int32_t, 3>{1, 0, 0}));
  EXPECT_EQ(v.cells[0].label, nyu40::kWall);
  EXPECT_EQ(v.cells[0].room, 0);  // -1 in voxels.ply: outside every room.
  EXPECT_EQ(v.cells[1].ijk, (std::array<int32_t, 3>{0, 2, 0}));
  EXPECT_FLOAT_EQ(v.cells[1].confidence, 0.25f);
  EXPECT_EQ(v.cells[1].room, 2);
  EXPECT_EQ(v.cells[2].ijk, (std::array<int32_t, 3>{3, 0, 1}));
  EXPECT_EQ(v.cells[2].label, nyu40::kChair);
  EXPECT_FLOAT_EQ(v.cells[2].confidence, 1.0f);
  EXPECT_EQ(v.cells[2].room, 4);
  EXPECT_EQ(v.cells[2].completed, 1);
  // Without confidence, room and completed the view still works, with those switches off.
  Result<View3dVoxels> bare = View3dVoxelsFromPly(MakePly(vs, false), "v.ply", Eigen::Isometry3d::Identity(), kSize);
  ASSERT_TRUE(bare.ok());
  EXPECT_FALSE(bare->has_confidence || bare->has_room || bare->has_completed);
}

TEST(View3d, EstimatesTheVoxelSizeFromTheCentresWhenNotGiven) {
  Result<View3dVoxels> r = View3dVoxelsFromPly(MakePly({At(0, 0, 0, 1), At(2, 0, 0, 1), At(2, 1, 3, 1)}), "v.ply");
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_NEAR(r->voxel_size_m, kSize, 1e-6);
  EXPECT_EQ(r->dims, (std::array<int32_t, 3>{3, 2, 4}));
}

// voxels.ply is in the input frame; the view undoes summary.json's canonical frame so the voxels sit on the grid.
TEST(View3d, UndoesTheCanonicalFrame) {
  Eigen::Isometry3d input_from_canonical = Eigen::Isometry3d::Identity();
  input_from_canonical.linear() = (Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX())).toRotationMatrix();
  input_from_canonical.translation() = Eigen::Vector3d(10, -3, 1.5);
  std::vector<Voxel> vs;
  for (int i = 0; i < 7; ++i)
    for (int k = 0; k < 3; ++k) {
      const Voxel c = At(i, i % 2, k, nyu40::kWall);
      const Eigen::Vector3d p = input_from_canonical * Eigen::Vector3d(c.x, c.y, c.z);
      vs.push_back({p.x(), p.y(), p.z(), nyu40::kWall});
    }
  Result<View3dVoxels> r = View3dVoxelsFromPly(MakePly(vs), "v.ply", input_from_canonical.inverse(), kSize);
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_EQ(r->dims, (std::array<int32_t, 3>{7, 2, 3}));
  EXPECT_EQ(r->cells.size(), 21u);  // No two voxels fall into one cell.
  EXPECT_NEAR(r->origin.x(), 1.025, 1e-4);
  EXPECT_NEAR(r->origin.z(), 0.025, 1e-4);
}

TEST(View3d, BadVerticesAreErrorsNamingTheFile) {
  PlyWriter w;
  w.AddElement("vertex", 1);
  for (const char* p : {"x", "y", "z"}) w.AddProperty(p, PlyType::kFloat32, {0.0});
  Result<PlyData> no_label = ParsePly(w.Serialize(), "n.ply");
  ASSERT_TRUE(no_label.ok());
  Result<View3dVoxels> r = View3dVoxelsFromPly(no_label.value(), "/out/voxels.ply");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("/out/voxels.ply: expected vertex properties x, y, z and label"), std::string::npos) << r.status().message();
  r = View3dVoxelsFromPly(MakePly({{0, 0, NAN, 1}}), "/out/voxels.ply");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("vertex 0 has a non-finite coordinate"), std::string::npos) << r.status().message();
  PlyWriter neg;
  neg.AddElement("vertex", 1);
  for (const char* p : {"x", "y", "z"}) neg.AddProperty(p, PlyType::kFloat32, {0.0});
  neg.AddProperty("label", PlyType::kInt16, {-3});
  r = View3dVoxelsFromPly(ParsePly(neg.Serialize(), "n.ply").value(), "/out/voxels.ply");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("is not a NYU40 id"), std::string::npos) << r.status().message();
}

TEST(View3d, MergingKeepsTheMajorityAndFitsTheBudget) {
  // One 2x2x2 block: 5 chair and 3 table voxels, 3 of them completed, rooms 2 (x4), 1 (x4).
  std::vector<Voxel> vs;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        Voxel v = At(i, j, k, vs.size() < 5 ? nyu40::kChair : nyu40::kTable);
        v.confidence = 0.1 * double(vs.size());
        v.completed = vs.size() < 3;
        v.room = vs.size() % 2 ? 1 : 2;
        vs.push_back(v);
      }
  vs.push_back(At(5, 0, 0, nyu40::kWall));  // A second block, alone.
  Result<View3dVoxels> r = View3dVoxelsFromPly(MakePly(vs), "v.ply", Eigen::Isometry3d::Identity(), kSize);
  ASSERT_TRUE(r.ok());
  const View3dVoxels m = MergeBlocks(r.value());
  EXPECT_EQ(m.merge, 2);
  EXPECT_NEAR(m.voxel_size_m, 2 * kSize, 1e-12);
  EXPECT_EQ(m.dims, (std::array<int32_t, 3>{3, 1, 1}));
  EXPECT_EQ(m.source_voxels, 9u);
  ASSERT_EQ(m.cells.size(), 2u);
  EXPECT_EQ(m.cells[0].label, nyu40::kChair);
  EXPECT_EQ(m.cells[0].room, 1);  // A tie (4 and 4): the smaller id.
  EXPECT_NEAR(m.cells[0].confidence, 0.35, 1e-6);
  EXPECT_EQ(m.cells[0].completed, 0);  // 3 of 8.
  // The merged cell's centre is the centre of its block.
  EXPECT_NEAR(m.origin.x(), 1.025 + kSize / 2, 1e-6);
  EXPECT_EQ(m.cells[1].ijk, (std::array<int32_t, 3>{2, 0, 0}));
  EXPECT_EQ(m.cells[1].label, nyu40::kWall);
  // MergeToFit: as often as needed, and not at all when the map fits.
  EXPECT_EQ(MergeToFit(r.value(), 100).merge, 1);
  const View3dVoxels one = MergeToFit(r.value(), 1);
  EXPECT_EQ(one.cells.size(), 1u);
  EXPECT_EQ(one.merge, 8);
}

// Room 1 floor at x < 5, room 2 floor at x >= 8, a wall at x = 6 and a cupboard at x = 20 far from both.
TEST(View3d, WallsAndFurnitureSwitchWithTheNearestRoom) {
  std::vector<Voxel> vs;
  for (int i = 0; i < 12; ++i)
    if (i < 5 || i >= 8) {
      Voxel f = At(i, 0, 0, nyu40::kFloor);
      f.room = i < 5 ? 1 : 2;
      vs.push_back(f);
    }
  for (int k = 0; k < 4; ++k) vs.push_back(At(6, 0, k, nyu40::kWall));     // 2 cells from room 1, 2 from room 2.
  vs.push_back(At(7, 0, 1, nyu40::kChair));                                 // 1 cell from room 2.
  vs.push_back(At(40, 0, 1, nyu40::kCabinet));                              // 28 cells = 1.4 m from room 2.
  Result<View3dVoxels> r = View3dVoxelsFromPly(MakePly(vs), "v.ply", Eigen::Isometry3d::Identity(), kSize);
  ASSERT_TRUE(r.ok());
  const std::vector<int32_t> groups = RoomGroups(r.value(), 1.0);
  ASSERT_EQ(groups.size(), r->cells.size());
  for (size_t i = 0; i < groups.size(); ++i) {
    const View3dCell& c = r->cells[i];
    if (c.room > 0) EXPECT_EQ(groups[i], c.room);
    else if (c.label == nyu40::kWall) EXPECT_EQ(groups[i], 1) << "a tie goes to the smaller id";
    else if (c.label == nyu40::kChair) EXPECT_EQ(groups[i], 2);
    else EXPECT_EQ(groups[i], 0) << "beyond the reach";
  }
}

using testing::Base64Decode;

// The section's JSON decodes back to the cells; switches hold every class and room; script text is safe.
TEST(View3d, PageSectionCarriesThePackedVoxels) {
  std::vector<Voxel> vs = {At(0, 0, 0, nyu40::kFloor), At(1, 0, 0, nyu40::kFloor), At(1, 0, 5, nyu40::kCeiling), At(2, 1, 1, 45)};
  vs[0].room = 1, vs[1].room = 7, vs[1].completed = 1, vs[2].confidence = 0.5;
  Result<View3dVoxels> r = View3dVoxelsFromPly(MakePly(vs), "v.ply", Eigen::Isometry3d::Identity(), kSize);
  ASSERT_TRUE(r.ok());
  const std::string html = View3dHtml(r.value(), {{1, "kitchen"}, {7, "</script><b>"}}, "var THREE = {};");
  const std::smatch m = [&] {
    std::smatch match;
    std::regex_search(html, match, std::regex(R"re(<script type="application/json" id="v3-data">([^<]*)</script>)re"));
    return match;
  }();
  ASSERT_EQ(m.size(), 2u) << "the data is one script element without '<' inside";
  const nlohmann::json data = nlohmann::json::parse(m[1].str());
  EXPECT_EQ(data["count"], 4);
  EXPECT_EQ(data["dims"], nlohmann::json({3, 2, 6}));
  const std::string cells = Base64Decode(data["cells"]);
  ASSERT_EQ(cells.size(), 4u * 6);
  EXPECT_EQ(uint8_t(cells[6]), 1);   // Second voxel: i = 1.
  EXPECT_EQ(uint8_t(cells[22]), 5);  // Fourth in (z, y, x) order is the ceiling at k = 5.
  const std::string completed = Base64Decode(data["completed"]);
  ASSERT_EQ(completed.size(), 1u);
  EXPECT_EQ(uint8_t(completed[0]), 0b0010);
  EXPECT_EQ(uint8_t(Base64Decode(data["confidence"])[3]), 128);  // 0.5 * 255, rounded.
  // Rooms 1 and 7; the ceiling and the label-45 voxel are within reach of room 7's column: no "outside" switch.
  ASSERT_EQ(data["room_list"].size(), 2u);
  EXPECT_EQ(data["room_list"][1]["name"], "7 </script><b>");  // Written as \u003c/script>.
  // The ceiling starts hidden; an id beyond NYU40 still gets a switch.
  EXPECT_NE(html.find("data-class=\"22\"><span"), std::string::npos);
  EXPECT_NE(html.find("data-class=\"2\" checked>"), std::string::npos);
  EXPECT_NE(html.find("> label 45 <"), std::string::npos);
  EXPECT_NE(html.find("7 &lt;/script&gt;&lt;b&gt;"), std::string::npos);
  EXPECT_NE(html.find("<script id=\"v3-three\">\nvar THREE = {};\n</script>"), std::string::npos);
  EXPECT_EQ(html, View3dHtml(r.value(), {{1, "kitchen"}, {7, "</script><b>"}}, "var THREE = {};")) << "deterministic";
}

// ---------------------------------------------------------------------------------------------------------
// In the browser. The scene: 40 x 30 cells of 5 cm; floor at k = 0 (room 1 at i < 20, room 2 beyond), a wall
// ring 13 cells high, a table in the middle (the centre of a top view), a bed in room 2 whose top layer was
// completed, and a ceiling over everything at k = 13.
constexpr int kNx = 40, kNy = 30;

bool IsTable(int i, int j) { return i >= 14 && i <= 25 && j >= 11 && j <= 18; }

void WriteSceneOutdir(const std::string& dir, bool with_voxels) {
  testing::WriteText(dir + "/summary.json", R"({"input": {"path": "scene.ply"}, "voxel_size_m": 0.05,
    "voxels": {"occupied": 1, "free": 1, "unknown": 1}})");
  testing::WriteText(dir + "/rooms.geojson", R"({"type": "FeatureCollection", "features": [
    {"type": "Feature", "geometry": null, "properties": {"id": 1, "type": "kitchen", "area_m2": 1.5}},
    {"type": "Feature", "geometry": null, "properties": {"id": 2, "type": "bedroom", "area_m2": 1.5}}]})");
  if (!with_voxels) return;
  std::vector<Voxel> vs;
  auto add = [&](int i, int j, int k, int label, double confidence, int room, int completed) {
    Voxel v = At(i, j, k, label);
    v.confidence = confidence, v.room = room, v.completed = completed;
    vs.push_back(v);
  };
  for (int j = 0; j < kNy; ++j)
    for (int i = 0; i < kNx; ++i) {
      const bool ring = i == 0 || j == 0 || i == kNx - 1 || j == kNy - 1;
      if (ring)
        for (int k = 0; k < 13; ++k) add(i, j, k, nyu40::kWall, 0.8, -1, 0);
      else add(i, j, 0, nyu40::kFloor, 0.9, i < 20 ? 1 : 2, 0);
      if (IsTable(i, j))
        for (int k = 1; k <= 4; ++k) add(i, j, k, nyu40::kTable, 0.75, -1, 0);
      if (i >= 28 && i <= 36 && j >= 3 && j <= 9)
        for (int k = 1; k <= 2; ++k) add(i, j, k, nyu40::kBed, 0.5, 2, k == 2);
      add(i, j, 13, nyu40::kCeiling, 0.6, -1, 0);
    }
  PlyWriter w;
  std::vector<double> x, y, z, label, confidence, room, completed;
  for (const Voxel& v : vs) {
    x.push_back(v.x), y.push_back(v.y), z.push_back(v.z), label.push_back(v.label);
    confidence.push_back(v.confidence), room.push_back(v.room), completed.push_back(v.completed);
  }
  w.AddElement("vertex", vs.size());
  w.AddProperty("x", PlyType::kFloat32, x);
  w.AddProperty("y", PlyType::kFloat32, y);
  w.AddProperty("z", PlyType::kFloat32, z);
  w.AddProperty("label", PlyType::kUInt16, label);
  w.AddProperty("confidence", PlyType::kFloat32, confidence);
  w.AddProperty("room", PlyType::kInt32, room);
  w.AddProperty("completed", PlyType::kUInt8, completed);
  ASSERT_TRUE(w.Write(dir + "/voxels.ply").ok());
}

// Pixels of colour `c` left of the switches (the side panel is 240 px wide; its swatches do not count).
size_t PixelsOf(const ImageRgb8& img, const Rgb8& c, int tolerance = 2) {
  size_t n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width - 260; ++x)
      n += std::abs(img.at(x, y, 0) - c.r) <= tolerance && std::abs(img.at(x, y, 1) - c.g) <= tolerance &&
           std::abs(img.at(x, y, 2) - c.b) <= tolerance;
  return n;
}

Rgb8 ColourOf(int nyu40_id) { return Nyu40Labels()[size_t(nyu40_id)].color; }

class View3dInChromium : public ::testing::Test {
 protected:
  void SetUp() override {
    chromium_ = testing::FindChromium();
    if (chromium_.empty()) GTEST_SKIP() << "chromium is not installed (Debian package chromium; scripts/test.sh installs it)";
    if (!std::filesystem::exists(DefaultThreeJsPath()))
      GTEST_SKIP() << DefaultThreeJsPath() << " is missing (Debian package libjs-three; scripts/setup-deps.sh installs it)";
    WriteSceneOutdir(dir_.path().string(), /*with_voxels=*/true);
    ASSERT_EQ(testing::Shell(std::string(SEMVOX_BINARY) + " report " + dir_.path().string() + " -q"), 0);
  }
  testing::PageLoad Load(const std::string& fragment, int width = 0, int height = 0, const std::string& flags = "") {
    return testing::LoadPage(chromium_, "file://" + dir_.File("report.html") + fragment, dir_.path().string(), width, height, flags);
  }
  std::string chromium_;
  testing::ScratchDir dir_{"view3d_chromium"};
};

constexpr int kShotWidth = 900, kShotHeight = 600;

// #3d: the view fills the window, the page's other sections are hidden, the top view shows the floor, wall,
// table and bed colours and not the ceiling's (hidden by default); nothing on the console.
TEST_F(View3dInChromium, FullWindowShowsTheLabelColoursWithoutConsoleOutput) {
  const testing::PageLoad p = Load("#3d&view=top", kShotWidth, kShotHeight);
  ASSERT_EQ(p.exit_code, 0) << p.log;
  EXPECT_EQ(p.console, "") << "the page wrote to the console";
  EXPECT_NE(p.dom.find("data-state=\"ready\""), std::string::npos) << "the view's script did not finish";
  EXPECT_NE(p.dom.find("class=\"v3-full\""), std::string::npos);
  ASSERT_EQ(p.shot.width, kShotWidth);
  const double total = double(kShotWidth) * kShotHeight;
  EXPECT_GT(PixelsOf(p.shot, ColourOf(nyu40::kFloor)) / total, 0.15);
  EXPECT_GT(PixelsOf(p.shot, ColourOf(nyu40::kWall)) / total, 0.01);
  EXPECT_GT(PixelsOf(p.shot, ColourOf(nyu40::kTable)) / total, 0.03);
  EXPECT_GT(PixelsOf(p.shot, ColourOf(nyu40::kBed)) / total, 0.02);
  EXPECT_EQ(PixelsOf(p.shot, ColourOf(nyu40::kCeiling), 0), 0u);
  EXPECT_EQ(PixelsOf(p.shot, kRoomTableBackground, 0), 0u) << "the report's sections show beside the full-window view";
  // The canvas spans the window but for the bar above, the help line below and the switches on the right.
  int x0 = kShotWidth, x1 = -1, y0 = kShotHeight, y1 = -1;
  for (int y = 0; y < kShotHeight; ++y)
    for (int x = 0; x < kShotWidth; ++x)
      if (p.shot.at(x, y, 0) == kView3dBackground.r && p.shot.at(x, y, 1) == kView3dBackground.g && p.shot.at(x, y, 2) == kView3dBackground.b)
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  EXPECT_LE(x0, 2);
  EXPECT_LE(y0, 60);
  EXPECT_GE(x1, kShotWidth - 300);
  EXPECT_GE(y1, kShotHeight - 80);
}

// Hiding a class through the switches (here the fragment) changes the picture: the table's colour goes, the floor
// under it appears; showing the ceiling covers everything.
TEST_F(View3dInChromium, HidingAndShowingClassesChangesThePicture) {
  const testing::PageLoad all = Load("#3d&view=top", kShotWidth, kShotHeight);
  const testing::PageLoad no_table = Load("#3d&view=top&hide=table", kShotWidth, kShotHeight);
  const testing::PageLoad ceiling = Load("#3d&view=top&show=ceiling", kShotWidth, kShotHeight);
  for (const auto* p : {&all, &no_table, &ceiling}) {
    ASSERT_EQ(p->shot.width, kShotWidth) << p->log;
    EXPECT_EQ(p->console, "");
  }
  const size_t table = PixelsOf(all.shot, ColourOf(nyu40::kTable));
  ASSERT_GT(table, 1000u);
  EXPECT_EQ(PixelsOf(no_table.shot, ColourOf(nyu40::kTable)), 0u);
  EXPECT_GT(double(PixelsOf(no_table.shot, ColourOf(nyu40::kFloor))), double(PixelsOf(all.shot, ColourOf(nyu40::kFloor))) + 0.8 * double(table));
  EXPECT_NE(no_table.dom.find("data-class=\"7\"><span"), std::string::npos) << "the table's switch is off";
  EXPECT_GT(PixelsOf(ceiling.shot, ColourOf(nyu40::kCeiling)), size_t(0.3 * kShotWidth * kShotHeight));
  EXPECT_EQ(PixelsOf(ceiling.shot, ColourOf(nyu40::kFloor)), 0u);
}

// Colour by room: the floors in the room table's colours; seen / completed: the bed's completed top.
TEST_F(View3dInChromium, ColourByRoomAndByCompletion) {
  const testing::PageLoad rooms = Load("#3d&view=top&colour=room", kShotWidth, kShotHeight);
  const testing::PageLoad completed = Load("#3d&view=top&colour=completed", kShotWidth, kShotHeight);
  ASSERT_EQ(rooms.shot.width, kShotWidth) << rooms.log;
  ASSERT_EQ(completed.shot.width, kShotWidth) << completed.log;
  const double total = double(kShotWidth) * kShotHeight;
  EXPECT_GT(PixelsOf(rooms.shot, RoomDisplayColour(1)) / total, 0.08);
  EXPECT_GT(PixelsOf(rooms.shot, RoomDisplayColour(2)) / total, 0.05);
  EXPECT_EQ(PixelsOf(rooms.shot, ColourOf(nyu40::kFloor)), 0u);
  EXPECT_GT(PixelsOf(completed.shot, kView3dCompletedColour) / total, 0.02);  // The bed's top layer.
  EXPECT_GT(PixelsOf(completed.shot, kView3dSeenColour) / total, 0.15);
}

// A click (pick=x,y: at that fraction of the canvas) left of the top view's centre lands on the table in room 1's
// half, and the info line names class, confidence and room.
TEST_F(View3dInChromium, ClickNamesTheVoxel) {
  const testing::PageLoad p = Load("#3d&view=top&pick=0.45,0.5", kShotWidth, kShotHeight);
  ASSERT_EQ(p.exit_code, 0) << p.log;
  EXPECT_EQ(p.console, "");
  EXPECT_NE(p.dom.find("table (NYU40 7) \u00b7 confidence 0.75 \u00b7 outside every room \u00b7 switches with room 1 \u00b7 seen"),
            std::string::npos)
      << p.dom.substr(p.dom.find("id=\"v3-info\""), 300);
  const testing::PageLoad miss = Load("#3d&view=top&pick=0.01,0.5");
  EXPECT_NE(miss.dom.find("no voxel there"), std::string::npos);
  // Nonsense in the fragment is ignored.
  const testing::PageLoad odd = Load("#3d&colour=a%22b&hide=nothing,%3Cb%3E&pick=x,y&view=sideways&hide_rooms=-1");
  EXPECT_EQ(odd.console, "");
  EXPECT_NE(odd.dom.find("data-state=\"ready\""), std::string::npos);
  EXPECT_NE(odd.dom.find("click a voxel for its class"), std::string::npos);
}

// Mouse input, as synthetic pointer and wheel events injected into a copy of the page: a drag turns the view, the
// wheel zooms in (the map covers more of the canvas), a click without movement picks a voxel.
TEST_F(View3dInChromium, DragTurnsWheelZoomsAndClickPicks) {
  const std::string page = testing::ReadText(dir_.File("report.html"));
  const size_t end = page.rfind("</body>");
  ASSERT_NE(end, std::string::npos);
  auto with_events = [&](const std::string& name, const std::string& events) {
    const std::string script = R"(<script>
(function () {
  var c = document.getElementById('v3-canvas'), r = c.getBoundingClientRect();
  function p(type, x, y, button) {
    c.dispatchEvent(new PointerEvent(type, {pointerId: 7, bubbles: true, cancelable: true, pointerType: 'mouse', button: button || 0,
                                             buttons: 1, clientX: r.left + x * r.width, clientY: r.top + y * r.height}));
  }
  function wheel(dy) {
    c.dispatchEvent(new WheelEvent('wheel', {bubbles: true, cancelable: true, deltaY: dy, clientX: r.left + r.width / 2, clientY: r.top + r.height / 2}));
  }
  )" + events + R"(
})();
</script>
)";
    testing::WriteText(dir_.File(name), page.substr(0, end) + script + page.substr(end));
    return testing::LoadPage(chromium_, "file://" + dir_.File(name) + "#3d&view=top", dir_.path().string(), kShotWidth, kShotHeight);
  };
  const testing::PageLoad still = with_events("still.html", "");
  const testing::PageLoad turned = with_events("turned.html", "p('pointerdown', 0.5, 0.5); p('pointermove', 0.7, 0.6); p('pointerup', 0.7, 0.6);");
  const testing::PageLoad zoomed = with_events("zoomed.html", "wheel(-400);");
  const testing::PageLoad clicked = with_events("clicked.html", "p('pointerdown', 0.45, 0.5); p('pointerup', 0.45, 0.5);");
  for (const auto* p : {&still, &turned, &zoomed, &clicked}) {
    ASSERT_EQ(p->shot.width, kShotWidth) << p->log;
    EXPECT_EQ(p->console, "") << "the page wrote to the console";
    EXPECT_NE(p->dom.find("data-state=\"ready\""), std::string::npos);
  }
  size_t changed = 0;
  for (int y = 0; y < kShotHeight; ++y)
    for (int x = 0; x < kShotWidth - 260; ++x)
      changed += still.shot.at(x, y, 0) != turned.shot.at(x, y, 0) || still.shot.at(x, y, 1) != turned.shot.at(x, y, 1);
  EXPECT_GT(changed, size_t(0.1 * kShotWidth * kShotHeight)) << "the drag did not turn the view";
  EXPECT_LT(PixelsOf(zoomed.shot, kView3dBackground, 0), PixelsOf(still.shot, kView3dBackground, 0) / 2) << "the wheel did not zoom in";
  EXPECT_NE(clicked.dom.find("table (NYU40 7) \u00b7 confidence 0.75"), std::string::npos);
  EXPECT_EQ(turned.dom.find("table (NYU40 7)"), std::string::npos) << "a drag is no click";
}

// A browser without WebGL gets one line instead of an empty canvas.
TEST_F(View3dInChromium, WithoutWebGlTheViewSaysSo) {
  const testing::PageLoad p = Load("#3d", 0, 0, "--disable-3d-apis");
  ASSERT_EQ(p.exit_code, 0) << p.log;
  EXPECT_EQ(p.console, "");
  EXPECT_NE(p.dom.find("data-state=\"unavailable\""), std::string::npos);
  EXPECT_NE(p.dom.find("3D view not available: this browser offers no WebGL"), std::string::npos);
  EXPECT_EQ(p.dom.find("<canvas"), std::string::npos);
}

// report.view_3d_max_voxels: a map over the budget is merged into 2x2x2 blocks until it fits, and says so.
TEST(View3dReport, LargeMapsAreMergedToTheBudget) {
  testing::ScratchDir dir("view3d_budget");
  const std::string d = dir.path().string();
  WriteSceneOutdir(d, /*with_voxels=*/true);
  testing::WriteText(d + "/three.js", "var THREE = {};");
  ReportOptions options;
  options.three_js_path = d + "/three.js";
  ReportSummary summary;
  ASSERT_TRUE(RenderReportHtml(d, options, &summary).ok());
  EXPECT_EQ(summary.view_3d_merge, 1);
  const size_t all = summary.view_3d_voxels;
  EXPECT_GT(all, 3000u);
  options.view_3d_max_voxels = 1000;
  Result<std::string> html = RenderReportHtml(d, options, &summary);
  ASSERT_TRUE(html.ok());
  EXPECT_LE(summary.view_3d_voxels, 1000u);
  EXPECT_GE(summary.view_3d_merge, 2);
  EXPECT_NE(html->find(std::to_string(summary.view_3d_voxels) + " voxels (" ), std::string::npos);
  EXPECT_NE(html->find("voxels of voxels.ply merged into cells of " + std::to_string(summary.view_3d_merge) + "&times;"), std::string::npos);
}

// A run directory without voxels.ply, or with a damaged one: the report is still written and its 3D section is one
// line saying why, in the browser too (no canvas, no console output).
TEST(View3dReport, WithoutUsableVoxelsThePageSaysWhy) {
  const std::string chromium = testing::FindChromium();
  testing::ScratchDir dir("view3d_absent");
  const std::string d = dir.path().string();
  WriteSceneOutdir(d, /*with_voxels=*/false);
  ASSERT_EQ(testing::Shell(std::string(SEMVOX_BINARY) + " report " + d + " -q 2> " + d + "/err.txt"), 0);
  std::string html = testing::ReadText(d + "/report.html");
  EXPECT_NE(html.find("3D view not available: voxels.ply not found"), std::string::npos);
  EXPECT_EQ(html.find("<canvas"), std::string::npos);
  if (!chromium.empty()) {
    const testing::PageLoad p = testing::LoadPage(chromium, "file://" + d + "/report.html#3d", d);
    ASSERT_EQ(p.exit_code, 0) << p.log;
    EXPECT_EQ(p.console, "");
    EXPECT_NE(p.dom.find("id=\"view3d-absent\">3D view not available: voxels.ply not found"), std::string::npos);
    EXPECT_EQ(p.dom.find("<canvas"), std::string::npos);
  }
  // Damaged: a truncated binary body. `semvox report` succeeds, warns in one line and the page names the file.
  WriteSceneOutdir(d, /*with_voxels=*/true);
  const std::string full = testing::ReadText(d + "/voxels.ply");
  testing::WriteText(d + "/voxels.ply", full.substr(0, full.size() / 2));
  ASSERT_EQ(testing::Shell(std::string(SEMVOX_BINARY) + " report " + d + " -q 2> " + d + "/err.txt"), 0);
  const std::string err = testing::ReadText(d + "/err.txt");
  EXPECT_NE(err.find("3D view not available: " + d + "/voxels.ply: "), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  html = testing::ReadText(d + "/report.html");
  EXPECT_NE(html.find("id=\"view3d-absent\">3D view not available: " + d + "/voxels.ply: "), std::string::npos);
  EXPECT_EQ(html.find("<canvas"), std::string::npos);
  if (!chromium.empty()) {
    const testing::PageLoad p = testing::LoadPage(chromium, "file://" + d + "/report.html", d);
    EXPECT_EQ(p.console, "");
    EXPECT_NE(p.dom.find("3D view not available: "), std::string::npos);
  }
}

}  // namespace
}  // namespace semvox
