// report.html from a hand-made OUTDIR whose contents (and so every number the page must show) are known:
// the values on the page, "not computed" for absent inputs, no URL but data: URIs, and in headless Chromium
// (when installed) the DOM's room table and the screenshot's room-table region.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <regex>

#include "core/ply.h"
#include "io/image_io.h"
#include "report/report.h"
#include "tests/report/chromium.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

// A fake OUTDIR: 3 rooms, 10 occupied voxels (6 wall, 3 chair, 1 table), a 20x10 occupancy top view with 50
// unknown cells, 100 grid voxels of which 60 unknown, one Voxel-CRF iteration.
void WriteFakeOutdir(const std::string& dir, bool with_semantic) {
  testing::WriteText(dir + "/summary.json", std::string(R"({
  "semvox_version": "0.1.0",
  "input": {"path": "scan.ply", "format": "ply", "kind": "mesh", "vertices": 1234, "faces": 2000},
  "bounds": {"min": [0, 0, 0], "max": [8.5, 6.25, 2.6]},
  "voxel_size_m": 0.05,
  "voxels": {"occupied": 10, "free": 30, "unknown": 60},
  "floor": {"found": true, "z": 0.0}, "ceiling": {"found": true, "z": 2.6},
  "rooms": {"rooms": 3},
  )") + (with_semantic ? R"("semantic": {"occupied_voxels": 10, "completed_voxels": 2,
     "iterations": [{"energy_initial": 5123.5, "energy_final": 4021.25, "energy_per_sweep": [4500.0, 4021.25],
                     "sweeps": 2, "changed_labels": 77, "seconds": 0.5}],
     "labels": {"wall": 99}, "seconds": {"crf": 0.5},
     "wall_openings": {"doors": 3, "windows": 4, "open_leaves": 1, "relabelled_voxels": 50, "openings": []}},
  )" : "") + R"("warnings": ["a warning <b>escaped</b>"],
  "seconds": {"load": 0.25, "voxelize": 1.5, "total": 3.0}
})");
  Image<uint8_t> occ(20, 10, 1, 254);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 5; ++x) occ.at(x, y) = 205;  // 50 unknown cells: 25.0 %.
  occ.at(10, 5) = 0;
  ASSERT_TRUE(WriteImage(dir + "/occupancy.pgm", occ).ok());
  ImageU16 ids(20, 10, 1, 0);
  for (int y = 0; y < 10; ++y)
    for (int x = 5; x < 20; ++x) ids.at(x, y) = uint16_t(x < 10 ? 1 : x < 15 ? 2 : 3);
  ASSERT_TRUE(WriteImage(dir + "/rooms.png", ids).ok());
  testing::WriteText(dir + "/rooms.geojson", R"({"type": "FeatureCollection", "features": [
  {"type": "Feature", "id": 2, "geometry": null, "properties": {"id": 2, "type": "kitchen", "type_id": 6,
    "type_probabilities": {"bathroom": 0.1, "kitchen": 0.7, "dining_room": 0.2}, "area_m2": 12.5, "ceiling_height_m": 2.6}},
  {"type": "Feature", "id": 1, "geometry": null, "properties": {"id": 1, "type": "bedroom", "probability": 0.81,
    "second_type": "office", "second_probability": 0.12, "area_m2": 14.25, "ceiling_height_m": 2.55}},
  {"type": "Feature", "id": 3, "geometry": null, "properties": {"id": 3, "type": "unknown", "type_id": 0,
    "type_probabilities": {}, "area_m2": 3.75, "ceiling_height_m": null}}]})");
  PlyWriter ply;
  ply.AddElement("vertex", 10);
  std::vector<double> xs(10, 0.5), labels = {1, 1, 1, 1, 1, 1, 5, 5, 5, 7};
  ply.AddProperty("x", PlyType::kFloat32, xs);
  ply.AddProperty("y", PlyType::kFloat32, xs);
  ply.AddProperty("z", PlyType::kFloat32, xs);
  ply.AddProperty("label", PlyType::kUInt16, labels);
  ASSERT_TRUE(ply.Write(dir + "/voxels.ply").ok());
}

size_t Occurrences(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

using testing::Base64Decode;

// Every src/href is a data: URI (or a fragment) and no http(s) URL appears anywhere but in the inlined three.js,
// whose text is the library's file byte for byte (its URLs are the XHTML namespace name and references in
// comments; nothing is fetched): nothing to fetch.
void ExpectSelfContained(const std::string& html) {
  std::string rest = html;
  const std::string open = "<script id=\"v3-three\">\n";
  if (const size_t a = html.find(open); a != std::string::npos) {
    const size_t b = html.find("\n</script>", a + open.size());
    ASSERT_NE(b, std::string::npos);
    EXPECT_EQ(html.substr(a + open.size(), b - a - open.size()), testing::ReadText(DefaultThreeJsPath()));
    rest = html.substr(0, a) + html.substr(b);
  }
  EXPECT_EQ(rest.find("http://"), std::string::npos);
  EXPECT_EQ(rest.find("https://"), std::string::npos);
  const std::regex attr(R"re((src|href)\s*=\s*"([^"]*)")re");
  for (auto it = std::sregex_iterator(rest.begin(), rest.end(), attr); it != std::sregex_iterator(); ++it) {
    const std::string value = (*it)[2];
    EXPECT_TRUE(value.rfind("data:image/png;base64,", 0) == 0 || value.rfind("#", 0) == 0) << value.substr(0, 60);
  }
}

TEST(Report, ShowsTheOutdirsNumbersAndInlineImages) {
  testing::ScratchDir dir("report_values");
  WriteFakeOutdir(dir.path().string(), /*with_semantic=*/true);
  Result<std::string> html_or = RenderReportHtml(dir.path().string());
  ASSERT_TRUE(html_or.ok()) << html_or.status().message();
  const std::string& html = html_or.value();
  ExpectSelfContained(html);
  // Unknown space: 60 of 100 voxels; 50 of 200 top-view cells.
  EXPECT_NE(html.find("<b>60.0 %</b> of 100 voxels"), std::string::npos);
  EXPECT_NE(html.find("<b>25.0 %</b> of 200 cells"), std::string::npos);
  EXPECT_NE(html.find("doors and windows found in the walls</th><td>3 doors (1 standing open), 4 windows"), std::string::npos);
  // Room table: sorted by id; explicit fields for room 1, the distribution's argmax and runner-up for room 2,
  // dashes for room 3's absent probabilities and ceiling.
  const size_t r1 = html.find("<tr data-room=\"1\">"), r2 = html.find("<tr data-room=\"2\">"), r3 = html.find("<tr data-room=\"3\">");
  ASSERT_NE(r1, std::string::npos);
  ASSERT_NE(r2, std::string::npos);
  ASSERT_NE(r3, std::string::npos);
  EXPECT_LT(r1, r2);
  EXPECT_LT(r2, r3);
  auto row = [&](size_t at) { return html.substr(at, html.find("</tr>", at) - at); };
  EXPECT_NE(row(r1).find("<td>bedroom</td><td>0.81</td><td>office</td><td>0.12</td><td>14.25</td><td>2.55</td>"), std::string::npos) << row(r1);
  EXPECT_NE(row(r2).find("<td>kitchen</td><td>0.70</td><td>dining_room</td><td>0.20</td><td>12.50</td><td>2.60</td>"), std::string::npos) << row(r2);
  EXPECT_NE(row(r3).find("<td>unknown</td><td>&mdash;</td><td>&mdash;</td><td>&mdash;</td><td>3.75</td><td>&mdash;</td>"), std::string::npos) << row(r3);
  EXPECT_NE(html.find("3 rooms, 30.50 m&sup2;"), std::string::npos);
  // Class histogram from voxels.ply (not the summary's {"wall": 99}): 6 wall, 3 chair, 1 table.
  EXPECT_NE(html.find("from voxels.ply (10 occupied voxels)"), std::string::npos);
  EXPECT_NE(html.find("wall</td><td>6</td>"), std::string::npos);
  EXPECT_NE(html.find("chair</td><td>3</td>"), std::string::npos);
  EXPECT_NE(html.find("table</td><td>1</td>"), std::string::npos);
  EXPECT_NE(html.find("60.0 %</td>"), std::string::npos);
  // Energies and seconds.
  EXPECT_NE(html.find("<td>1</td><td>5123.5</td><td>4021.2</td><td>2</td><td>77</td><td class=\"seconds\">0.500</td>"), std::string::npos);
  EXPECT_NE(html.find("4500.0, 4021.2"), std::string::npos);
  EXPECT_NE(html.find("<td>voxelize</td>"), std::string::npos);
  EXPECT_NE(html.find("1.500"), std::string::npos);
  // Escaped text; the absent semantic top view.
  EXPECT_NE(html.find("a warning &lt;b&gt;escaped&lt;/b&gt;"), std::string::npos);
  EXPECT_EQ(Occurrences(html, "not computed"), 1u);
  // Two inline images (occupancy, rooms) that decode to the maps' size; room 1's cells in its display colour.
  const std::regex img(R"re(alt="([a-z ]+)" width="(\d+)" height="(\d+)" src="data:image/png;base64,([A-Za-z0-9+/=]+)")re");
  int images = 0;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), img); it != std::sregex_iterator(); ++it, ++images) {
    Result<ImageRgb8> decoded = DecodeImageRgb8(Base64Decode((*it)[4]), (*it)[1]);
    ASSERT_TRUE(decoded.ok()) << decoded.status().message();
    EXPECT_EQ(decoded->width, 20);
    EXPECT_EQ(decoded->height, 10);
    EXPECT_EQ(std::stoi((*it)[2]), 20 * 32);  // Integer zoom to 640 px.
    if ((*it)[1] == "rooms top view") {
      const Rgb8 c = RoomDisplayColour(1);
      EXPECT_EQ(decoded->at(7, 3, 0), c.r);
      EXPECT_EQ(decoded->at(7, 3, 1), c.g);
      EXPECT_EQ(decoded->at(7, 3, 2), c.b);
    }
  }
  EXPECT_EQ(images, 2);
}

TEST(Report, AbsentSectionsSayNotComputedAndBadFilesAreErrors) {
  testing::ScratchDir dir("report_absent");
  const std::string d = dir.path().string();
  Status st = WriteReport(d);
  EXPECT_EQ(st.code(), StatusCode::kInvalidInput);
  EXPECT_NE(st.message().find("summary.json: no such file"), std::string::npos) << st.message();
  testing::WriteText(d + "/summary.json", R"({"input": {"path": "x.ply"}, "voxels": {"occupied": 1, "free": 1, "unknown": 2}, "seconds": {"load": 1}})");
  ASSERT_TRUE(WriteReport(d).ok());
  const std::string html = testing::ReadText(d + "/report.html");
  // Occupancy, semantic and room views; room table; classes; energies: 6 sections without data.
  EXPECT_EQ(Occurrences(html, "not computed"), 6u);
  EXPECT_NE(html.find("<b>50.0 %</b> of 4 voxels"), std::string::npos);
  EXPECT_NE(html.find("3D view not available: voxels.ply not found"), std::string::npos);
  for (auto& e : std::filesystem::directory_iterator(d)) EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
  testing::WriteText(d + "/rooms.geojson", "{\"features\": [");
  st = WriteReport(d);
  EXPECT_EQ(st.code(), StatusCode::kInvalidInput);
  EXPECT_NE(st.message().find("rooms.geojson: not valid JSON"), std::string::npos) << st.message();
  ReportOptions bad;
  bad.output_name = "../x.html";
  EXPECT_EQ(WriteReport(d, bad).code(), StatusCode::kInvalidInput);
}


// A fake three.js: the page inlines whatever file three_js_path names.
std::string WriteFakeThreeJs(const std::string& dir) {
  const std::string path = dir + "/three.fake.js";
  testing::WriteText(path, "var THREE = {REVISION: 'fake'}; /* fake three.js for report_test */");
  return path;
}

// The 3D view: three.js and the view's script inline, the voxels' data, the header's link to #3d; the page is
// the same twice; the summary says what it holds.
TEST(Report, HoldsThe3dViewWithThreeJsInline) {
  testing::ScratchDir dir("report_3d");
  const std::string d = dir.path().string();
  WriteFakeOutdir(d, /*with_semantic=*/true);
  ReportOptions options;
  options.three_js_path = WriteFakeThreeJs(d);
  ReportSummary summary;
  Result<std::string> html = RenderReportHtml(d, options, &summary);
  ASSERT_TRUE(html.ok()) << html.status().message();
  EXPECT_TRUE(summary.view_3d);
  EXPECT_EQ(summary.view_3d_absent, "");
  EXPECT_EQ(summary.view_3d_voxels, 1u);  // The fake voxels.ply puts its 10 voxels at one point.
  EXPECT_EQ(summary.bytes, html->size());
  EXPECT_NE(html->find("<script id=\"v3-three\">\nvar THREE = {REVISION: 'fake'};"), std::string::npos);
  EXPECT_NE(html->find("<script id=\"v3-script\">"), std::string::npos);
  EXPECT_NE(html->find("<canvas id=\"v3-canvas\">"), std::string::npos);
  EXPECT_NE(html->find("\"count\":1,"), std::string::npos);
  EXPECT_NE(html->find("<a href=\"#3d\">3D view</a>"), std::string::npos);
  EXPECT_EQ(html.value(), RenderReportHtml(d, options).value());
}

// --no-3d (ReportOptions::view_3d = false, config report.view_3d: false) leaves the view, its scripts and its
// link out; without three.js the section is one line naming the path.
TEST(Report, No3dLeavesTheViewOutAndMissingThreeJsIsOneLine) {
  testing::ScratchDir dir("report_no3d");
  const std::string d = dir.path().string();
  WriteFakeOutdir(d, /*with_semantic=*/false);
  ReportOptions options;
  options.view_3d = false;
  Result<std::string> html = RenderReportHtml(d, options);
  ASSERT_TRUE(html.ok());
  EXPECT_EQ(html->find("<script"), std::string::npos);
  EXPECT_EQ(html->find("3D view"), std::string::npos);
  EXPECT_EQ(html->find("v3-"), std::string::npos);
  ASSERT_EQ(testing::Shell(std::string(SEMVOX_BINARY) + " report " + d + " --no-3d -q"), 0);
  EXPECT_EQ(testing::ReadText(d + "/report.html").find("<script"), std::string::npos);
  testing::WriteText(d + "/no3d.yaml", "report:\n  view_3d: false\n");
  ASSERT_EQ(testing::Shell(std::string(SEMVOX_BINARY) + " report " + d + " --config " + d + "/no3d.yaml -q"), 0);
  EXPECT_EQ(testing::ReadText(d + "/report.html").find("<script"), std::string::npos);
  testing::WriteText(d + "/bad.yaml", "report:\n  view_3d_max_voxels: 10\n");
  EXPECT_EQ(testing::Shell(std::string(SEMVOX_BINARY) + " report " + d + " --config " + d + "/bad.yaml -q 2> " + d + "/err.txt"), 2);
  EXPECT_NE(testing::ReadText(d + "/err.txt").find("report.view_3d_max_voxels"), std::string::npos) << testing::ReadText(d + "/err.txt");
  options.view_3d = true;
  options.three_js_path = d + "/no/three.min.js";
  ReportSummary summary;
  html = RenderReportHtml(d, options, &summary);
  ASSERT_TRUE(html.ok());
  EXPECT_FALSE(summary.view_3d);
  const std::string line = "<p class=\"na\" id=\"view3d-absent\">3D view not available: three.js not found at " + d +
                           "/no/three.min.js (install the Debian package libjs-three, or set SEMVOX_THREE_JS to a three.min.js)</p>";
  EXPECT_NE(html->find(line), std::string::npos);
  EXPECT_EQ(html->find("<script"), std::string::npos);
}

// A damaged or empty voxels.ply is no error: the class histogram falls back to summary.json and says why, the 3D
// view is one line naming the file.
TEST(Report, DamagedVoxelsPlyStillGivesAReport) {
  testing::ScratchDir dir("report_damaged");
  const std::string d = dir.path().string();
  WriteFakeOutdir(d, /*with_semantic=*/true);
  ReportOptions options;
  options.three_js_path = WriteFakeThreeJs(d);
  testing::WriteText(d + "/voxels.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\nend_header\nxx");
  ReportSummary summary;
  Result<std::string> html = RenderReportHtml(d, options, &summary);
  ASSERT_TRUE(html.ok()) << html.status().message();
  EXPECT_NE(html->find("from summary.json (voxels.ply is damaged)"), std::string::npos);
  EXPECT_NE(html->find("wall</td><td>99</td>"), std::string::npos);
  EXPECT_NE(summary.view_3d_absent.find(d + "/voxels.ply: "), std::string::npos) << summary.view_3d_absent;
  EXPECT_NE(html->find("id=\"view3d-absent\">3D view not available: " + d + "/voxels.ply: "), std::string::npos);
  EXPECT_EQ(html->find("<canvas"), std::string::npos);
  PlyWriter empty;
  empty.AddElement("vertex", 0);
  for (const char* p : {"x", "y", "z"}) empty.AddProperty(p, PlyType::kFloat32, {});
  empty.AddProperty("label", PlyType::kUInt16, {});
  ASSERT_TRUE(empty.Write(d + "/voxels.ply").ok());
  html = RenderReportHtml(d, options);
  ASSERT_TRUE(html.ok());
  EXPECT_NE(html->find("3D view not available: voxels.ply holds no occupied voxels"), std::string::npos);
}

// `semvox report` on the fake OUTDIR, loaded in headless Chromium: the DOM holds the three room rows and the
// screenshot shows the room table's body as a region of its background colour, 3 rows of 22 px high.
TEST(Report, HeadlessChromiumRendersTheRoomTable) {
  const std::string chromium = testing::FindChromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (Debian package chromium; scripts/test.sh installs it)";
  testing::ScratchDir dir("report_chromium");
  const std::string d = dir.path().string();
  WriteFakeOutdir(d, /*with_semantic=*/false);
  ASSERT_EQ(testing::Shell(std::string(SEMVOX_BINARY) + " report " + d + " -q"), 0);
  const std::string page = "file://" + d + "/report.html";
  ExpectSelfContained(testing::ReadText(d + "/report.html"));
  const std::string common = chromium + " --headless --no-sandbox --disable-gpu --no-first-run --disable-extensions "
                             "--hide-scrollbars --force-device-scale-factor=1 --user-data-dir=" + d + "/profile ";
  ASSERT_EQ(testing::Shell(common + "--dump-dom " + page + " > " + d + "/dom.html 2> " + d + "/chromium1.log"), 0)
      << testing::ReadText(d + "/chromium1.log");
  const std::string dom = testing::ReadText(d + "/dom.html");
  EXPECT_EQ(Occurrences(dom, "<tr data-room="), 3u);
  for (const char* type : {">bedroom<", ">kitchen<", ">unknown<", ">14.25<", ">12.50<", ">3.75<"})
    EXPECT_NE(dom.find(type), std::string::npos) << type;
  const std::string shot = d + "/shot.png";
  ASSERT_EQ(testing::Shell(common + "--window-size=1200,2400 --screenshot=" + shot + " " + page + " > " + d + "/chromium2.log 2>&1"), 0)
      << testing::ReadText(d + "/chromium2.log");
  Result<ImageRgb8> img = ReadImageRgb8(shot);
  ASSERT_TRUE(img.ok()) << img.status().message();
  ASSERT_EQ(img->width, 1200);
  int x0 = img->width, x1 = -1, y0 = img->height, y1 = -1;
  size_t n = 0;
  for (int y = 0; y < img->height; ++y)
    for (int x = 0; x < img->width; ++x)
      if (img->at(x, y, 0) == kRoomTableBackground.r && img->at(x, y, 1) == kRoomTableBackground.g &&
          img->at(x, y, 2) == kRoomTableBackground.b) {
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y), ++n;
      }
  ASSERT_GT(n, 0u) << "no room-table background in the screenshot";
  const int h = y1 - y0 + 1, w = x1 - x0 + 1;
  EXPECT_NEAR(h, 3 * kRoomTableRowHeightPx, 2) << "rows " << y0 << ".." << y1;
  EXPECT_GT(w, 300) << "columns " << x0 << ".." << x1;  // Seven columns of text.
  EXPECT_LT(w, 1100);
  EXPECT_GT(double(n), 0.6 * w * h);  // A filled block (text and swatches cover the rest).
}

}  // namespace
}  // namespace semvox
