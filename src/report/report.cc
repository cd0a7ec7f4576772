#include "report/report.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "core/file_util.h"
#include "core/image.h"
#include "core/labels.h"
#include "core/ply.h"
#include "io/image_encode.h"
#include "io/image_io.h"
#include "report/html_text.h"
#include "report/view3d.h"

namespace semvox {
namespace fs = std::filesystem;
using nlohmann::ordered_json;

namespace {

constexpr const char* kNotComputed = "<p class=\"na\">not computed</p>\n";
// occupancy.pgm values (mapping/occupancy_map.h, map_server trinary).
constexpr uint8_t kPgmOccupied = 0, kPgmFree = 254, kPgmUnknown = 205;

using html::Base64;
using html::Escape;
using html::Hex;

std::string Num(double v, int decimals) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

// Integers with thin-space-free thousands separators (1,234,567).
std::string Count(double v) {
  if (!std::isfinite(v)) return "n/a";
  const long long n = std::llround(v);
  std::string digits = std::to_string(n < 0 ? -n : n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return (n < 0 ? "-" : "") + out;
}

// A JSON scalar as text (strings unquoted, numbers with up to 4 decimals, null as "n/a").
std::string Scalar(const ordered_json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "yes" : "no";
  if (v.is_number_integer() || v.is_number_unsigned()) return Count(v.get<double>());
  if (v.is_number()) {
    std::string s = Num(v.get<double>(), 4);
    while (s.find('.') != std::string::npos && (s.back() == '0' || s.back() == '.')) {
      const bool dot = s.back() == '.';
      s.pop_back();
      if (dot) break;
    }
    return s;
  }
  if (v.is_null()) return "n/a";
  if (v.is_array()) {
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + Scalar(v[i]);
    return s + "]";
  }
  return v.dump();
}

const ordered_json* Get(const ordered_json& j, const std::string& key) {
  if (!j.is_object()) return nullptr;
  auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}

double NumberOr(const ordered_json* v, double fallback) { return v && v->is_number() ? v->get<double>() : fallback; }

struct Row {
  std::string key, value;
};

std::string KeyValueTable(const std::vector<Row>& rows) {
  std::ostringstream os;
  os << "<table class=\"kv\">\n";
  for (const Row& r : rows) os << "<tr><th>" << Escape(r.key) << "</th><td>" << r.value << "</td></tr>\n";
  os << "</table>\n";
  return os.str();
}

// A horizontal bar (CSS width in percent of the cell) with a text after it.
std::string Bar(double fraction, const std::string& colour, const std::string& text) {
  const double pct = std::clamp(fraction, 0.0, 1.0) * 100.0;
  return "<span class=\"bar\" style=\"width:" + Num(pct * 2.5, 1) + "px;background:" + colour + "\"></span> " + text;
}

std::string ImageTag(const std::string& png_bytes, int width, int height, int display_width, const std::string& alt) {
  // Integer zoom for small maps (crisp cells), CSS max-width for large ones.
  const int zoom = std::max(1, display_width / std::max(1, width));
  const int shown_w = width * zoom, shown_h = height * zoom;
  return "<img class=\"map\" alt=\"" + Escape(alt) + "\" width=\"" + std::to_string(shown_w) + "\" height=\"" +
         std::to_string(shown_h) + "\" src=\"data:image/png;base64," + Base64(png_bytes) + "\">\n";
}

bool Exists(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

struct RoomRow {
  int id = 0;
  std::string type = "unknown";
  std::optional<double> probability;
  std::string second_type;
  std::optional<double> second_probability;
  std::optional<double> area_m2, ceiling_height_m;
};

Status ReadRooms(const fs::path& path, std::vector<RoomRow>* rooms) {
  std::string text;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path.string(), &text));
  ordered_json j;
  try {
    j = ordered_json::parse(text);
  } catch (const std::exception& e) {
    return Status::InvalidInput(FileError(path.string(), std::string("not valid JSON: ") + e.what(), "re-run semvox run"));
  }
  const ordered_json* features = Get(j, "features");
  if (!features || !features->is_array())
    return Status::InvalidInput(FileError(path.string(), "no 'features' array (not a GeoJSON FeatureCollection)", "re-run semvox run"));
  for (const auto& f : *features) {
    const ordered_json* props = Get(f, "properties");
    if (!props || !props->is_object())
      return Status::InvalidInput(FileError(path.string(), "a feature without 'properties'", "re-run semvox run"));
    RoomRow r;
    const ordered_json* id = Get(*props, "id");
    if (!id) id = Get(f, "id");
    if (!id || !id->is_number_integer())
      return Status::InvalidInput(FileError(path.string(), "a room without an integer 'id'", "re-run semvox run"));
    r.id = id->get<int>();
    if (const auto* t = Get(*props, "type"); t && t->is_string()) r.type = t->get<std::string>();
    if (const auto* p = Get(*props, "probability"); p && p->is_number()) r.probability = p->get<double>();
    if (const auto* t = Get(*props, "second_type"); t && t->is_string()) r.second_type = t->get<std::string>();
    if (const auto* p = Get(*props, "second_probability"); p && p->is_number()) r.second_probability = p->get<double>();
    // Older files carry only the distribution: the probability of the type and the runner-up come from it.
    if (const auto* dist = Get(*props, "type_probabilities"); dist && dist->is_object() && !dist->empty()) {
      if (!r.probability)
        if (const auto* p = Get(*dist, r.type); p && p->is_number()) r.probability = p->get<double>();
      if (r.second_type.empty()) {
        double best = -1;
        for (const auto& [name, p] : dist->items())
          if (name != r.type && p.is_number() && p.get<double>() > best) best = p.get<double>(), r.second_type = name;
        if (best >= 0 && !r.second_probability) r.second_probability = best;
      }
    }
    if (const auto* a = Get(*props, "area_m2"); a && a->is_number()) r.area_m2 = a->get<double>();
    if (const auto* c = Get(*props, "ceiling_height_m"); c && c->is_number()) r.ceiling_height_m = c->get<double>();
    rooms->push_back(r);
  }
  std::sort(rooms->begin(), rooms->end(), [](const RoomRow& a, const RoomRow& b) { return a.id < b.id; });
  return Status::Ok();
}

const char* kCss = R"CSS(
body{font-family:sans-serif;margin:16px 24px;color:#202020;background:#ffffff;max-width:1100px}
h1{font-size:22px;margin:0 0 4px 0} h2{font-size:17px;margin:22px 0 6px 0;border-bottom:1px solid #c0c0c0}
h3{font-size:14px;margin:12px 0 4px 0}
table{border-collapse:collapse;font-size:13px} th,td{text-align:left;padding:2px 8px;vertical-align:top}
table.kv th{font-weight:normal;color:#505050}
table.num td,table.num th{text-align:right} table.num td:first-child,table.num th:first-child{text-align:left}
.na{color:#a00000;font-style:italic}
.bar{display:inline-block;height:10px;vertical-align:middle}
.views{display:flex;flex-wrap:wrap;gap:16px} figure{margin:0} figcaption{font-size:12px;color:#505050}
img.map{image-rendering:pixelated;max-width:100%;height:auto;border:1px solid #c0c0c0}
table.rooms{border-collapse:collapse;border-spacing:0}
table.rooms thead tr{background:#c9b45c}
table.rooms tbody td{padding:0 10px;border:none;white-space:nowrap}
table.rooms td:nth-child(2),table.rooms td:nth-child(4),table.rooms th:nth-child(2),table.rooms th:nth-child(4){text-align:left}
.swatch{display:inline-block;width:12px;height:12px;vertical-align:middle;border:1px solid #404040}
.muted{color:#707070;font-size:12px}
)CSS";

// Body rows of the room table: the background and row height tests look for (report.h).
std::string RoomTableCss() {
  const std::string h = std::to_string(kRoomTableRowHeightPx) + "px";
  return "table.rooms tbody tr{background:" + Hex(kRoomTableBackground) + ";height:" + h + "}\n" +
         "table.rooms tbody td{height:" + h + ";line-height:" + h + "}\n";
}

// What voxels.ply holds for the class histogram and the 3D view: absent, unreadable (with the reader's
// message) or read.
struct VoxelsPly {
  std::string path;
  bool present = false;
  std::optional<PlyData> data;
  std::string error;  // When present but unreadable.
};

VoxelsPly ReadVoxelsPly(const fs::path& path) {
  VoxelsPly v;
  v.path = path.string();
  v.present = Exists(path);
  if (!v.present) return v;
  Result<PlyData> ply = ReadPly(path.string());
  if (ply.ok()) v.data = std::move(ply).value();
  else v.error = ply.status().message();
  return v;
}

// summary.json's frame.input_from_canonical (4x4 row-major) inverted; the identity when absent, not applied or
// not a rigid 4x4 matrix of numbers.
Eigen::Isometry3d CanonicalFromInput(const ordered_json& s) {
  const ordered_json* frame = Get(s, "frame");
  const ordered_json* applied = frame ? Get(*frame, "applied") : nullptr;
  const ordered_json* m = frame ? Get(*frame, "input_from_canonical") : nullptr;
  if (!applied || !applied->is_boolean() || !applied->get<bool>() || !m || !m->is_array() || m->size() != 4)
    return Eigen::Isometry3d::Identity();
  Eigen::Matrix4d t;
  for (int r = 0; r < 4; ++r) {
    const ordered_json& row = (*m)[size_t(r)];
    if (!row.is_array() || row.size() != 4) return Eigen::Isometry3d::Identity();
    for (int c = 0; c < 4; ++c) {
      if (!row[size_t(c)].is_number()) return Eigen::Isometry3d::Identity();
      t(r, c) = row[size_t(c)].get<double>();
    }
  }
  const Eigen::Matrix3d rot = t.topLeftCorner<3, 3>();
  if (!t.allFinite() || !(rot.transpose() * rot).isIdentity(1e-6)) return Eigen::Isometry3d::Identity();
  Eigen::Isometry3d input_from_canonical = Eigen::Isometry3d::Identity();
  input_from_canonical.linear() = rot;
  input_from_canonical.translation() = t.topRightCorner<3, 1>();
  return input_from_canonical.inverse();
}

// The 3D view, or the line saying why there is none (summary->view_3d_absent).
std::string View3dSection(const ordered_json& s, const VoxelsPly& voxels, const std::vector<RoomRow>& room_rows,
                          const ReportOptions& options, ReportSummary* summary) {
  auto absent = [&](const std::string& why) {
    summary->view_3d_absent = why;
    return View3dAbsentHtml(why);
  };
  if (!voxels.present) return absent("voxels.ply not found (the semantic stage did not run; semantic.enabled: true writes it)");
  if (!voxels.data) return absent(voxels.error);  // The reader's message: the file, what is wrong, a hint.
  Result<View3dVoxels> read = View3dVoxelsFromPly(*voxels.data, voxels.path, CanonicalFromInput(s), NumberOr(Get(s, "voxel_size_m"), 0));
  if (!read.ok()) return absent(read.status().message());
  if (read->cells.empty()) return absent("voxels.ply holds no occupied voxels");
  const std::string three_path = options.three_js_path.empty() ? DefaultThreeJsPath() : options.three_js_path;
  std::string three_js;
  if (!Exists(three_path) || !ReadFileBytes(three_path, &three_js).ok())
    return absent("three.js not found at " + three_path + " (install the Debian package libjs-three, or set SEMVOX_THREE_JS to a three.min.js)");
  std::string lower(three_js.size(), ' ');
  std::transform(three_js.begin(), three_js.end(), lower.begin(), [](char c) { return char(std::tolower(uint8_t(c))); });
  if (lower.find("</script") != std::string::npos)
    return absent(three_path + " cannot be inlined into the page (it contains \"</script\")");
  const View3dVoxels shown = MergeToFit(std::move(read).value(), size_t(options.view_3d_max_voxels));
  std::vector<View3dRoom> rooms;
  for (const RoomRow& r : room_rows) rooms.push_back({r.id, r.type});
  summary->view_3d = true;
  summary->view_3d_voxels = shown.cells.size();
  summary->view_3d_merge = shown.merge;
  return View3dHtml(shown, rooms, three_js);
}

}  // namespace

std::string DefaultThreeJsPath() {
  if (const char* env = std::getenv("SEMVOX_THREE_JS"); env && *env) return env;
  return SEMVOX_THREE_JS_DEFAULT;
}

bool ReportOptions::Check(std::string* error) const {
  if (!CheckOptions(*this, Options(), error)) return false;
  if (output_name.empty() || output_name.find('/') != std::string::npos || output_name == "." || output_name == "..") {
    *error = "output_name = '" + output_name + "'. Violated constraint: a plain file name";
    return false;
  }
  if (image_display_width_px < 64 || image_display_width_px > 8192) {
    *error = "image_display_width_px = " + std::to_string(image_display_width_px) + ". Allowed range: [64, 8192]";
    return false;
  }
  return true;
}

Rgb8 RoomDisplayColour(int id) {
  // Hue by the golden angle, saturation 0.45, value 0.95 (max channel 242).
  const double h = std::fmod(double(id) * 137.50776405, 360.0) / 60.0;
  const double v = 0.95, s = 0.45, c = v * s, x = c * (1 - std::fabs(std::fmod(h, 2.0) - 1)), m = v - c;
  double r = 0, g = 0, b = 0;
  switch (int(h) % 6) {
    case 0: r = c, g = x; break;
    case 1: r = x, g = c; break;
    case 2: g = c, b = x; break;
    case 3: g = x, b = c; break;
    case 4: r = x, b = c; break;
    default: r = c, b = x; break;
  }
  auto q = [&](double u) { return uint8_t(std::lround((u + m) * 255.0)); };
  return {q(r), q(g), q(b)};
}

Result<std::string> RenderReportHtml(const std::string& outdir, const ReportOptions& options, ReportSummary* summary) {
  ReportSummary local_summary;
  if (!summary) summary = &local_summary;
  *summary = ReportSummary();
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("report options: " + error);
  const fs::path dir(outdir);
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    return Status::InvalidInput(FileError(outdir, "not a directory", "give the OUTDIR of a `semvox run`"));
  const fs::path summary_path = dir / "summary.json";
  if (!Exists(summary_path))
    return Status::InvalidInput(FileError(summary_path.string(), "no such file", "run `semvox run INPUT -o " + outdir + "` first"));
  ordered_json s;
  {
    std::string text;
    SEMVOX_RETURN_IF_ERROR(ReadFileBytes(summary_path.string(), &text));
    try {
      s = ordered_json::parse(text);
    } catch (const std::exception& e) {
      return Status::InvalidInput(FileError(summary_path.string(), std::string("not valid JSON: ") + e.what(), "re-run semvox run"));
    }
    if (!s.is_object()) return Status::InvalidInput(FileError(summary_path.string(), "not a JSON object", "re-run semvox run"));
  }
  // The semantic section: "voxel_crf" (planned name) or "semantic" (pipeline/pipeline_summary.cc).
  const ordered_json* semantic = Get(s, "voxel_crf");
  if (!semantic) semantic = Get(s, "semantic");

  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>semvox report: "
       << Escape(fs::path(outdir).filename().string()) << "</title>\n<style>" << kCss << RoomTableCss() << (options.view_3d ? View3dCss() : "")
       << "</style>\n</head>\n<body>\n";
  html << "<h1>semvox report</h1>\n<p class=\"muted\">" << Escape(outdir);
  if (const auto* v = Get(s, "semvox_version")) html << " &middot; semvox " << Escape(Scalar(*v));
  if (options.view_3d) html << " &middot; <a href=\"#3d\">3D view</a>";
  html << "</p>\n";

  // ---- input summary ----
  html << "<h2 id=\"input\">Input</h2>\n";
  {
    std::vector<Row> rows;
    if (const auto* in = Get(s, "input"); in && in->is_object())
      for (const auto& [k, v] : in->items()) rows.push_back({k, Escape(Scalar(v))});
    if (const auto* b = Get(s, "bounds"); b && Get(*b, "min") && Get(*b, "max")) {
      const auto &mn = (*b)["min"], &mx = (*b)["max"];
      std::string size;
      if (mn.is_array() && mx.is_array() && mn.size() == 3 && mx.size() == 3) {
        for (int i = 0; i < 3; ++i) size += (i ? " x " : "") + Num(mx[i].get<double>() - mn[i].get<double>(), 2);
        rows.push_back({"bounds (m, input frame)", Escape(Scalar(mn) + " .. " + Scalar(mx))});
        rows.push_back({"extent (m)", size});
      }
    }
    if (const auto* v = Get(s, "voxel_size_m")) rows.push_back({"voxel size (m)", Escape(Scalar(*v))});
    if (const auto* g = Get(s, "grid"); g && Get(*g, "dims")) rows.push_back({"grid (voxels)", Escape(Scalar((*g)["dims"]))});
    for (const char* k : {"floor", "ceiling"})
      if (const auto* f = Get(s, k); f && f->is_object()) {
        const bool found = Get(*f, "found") && (*f)["found"].is_boolean() && (*f)["found"].get<bool>();
        rows.push_back({std::string(k) + " z (m)", found && Get(*f, "z") ? Escape(Scalar((*f)["z"])) : "not found"});
      }
    if (const auto* p = Get(s, "scan_positions"); p && p->is_array()) rows.push_back({"virtual scan positions", Count(double(p->size()))});
    if (const auto* e = Get(s, "enclosed")) rows.push_back({"enclosed", Escape(Scalar(*e))});
    if (const auto* v = Get(s, "views"); v && v->is_object())
      rows.push_back({"views (kept / rendered)", Count(NumberOr(Get(*v, "kept"), NAN)) + " / " + Count(NumberOr(Get(*v, "views"), NAN))});
    if (rows.empty()) html << kNotComputed;
    else html << KeyValueTable(rows);
    if (const auto* w = Get(s, "warnings"); w && w->is_array() && !w->empty()) {
      html << "<h3>Warnings</h3>\n<ul>\n";
      for (const auto& x : *w) html << "<li>" << Escape(Scalar(x)) << "</li>\n";
      html << "</ul>\n";
    }
  }

  // ---- space: unknown percentage ----
  html << "<h2 id=\"space\">Space</h2>\n";
  Image<uint8_t> occupancy;
  const fs::path occ_path = dir / "occupancy.pgm";
  if (Exists(occ_path)) {
    Result<Image<uint8_t>> o = ReadImageGrey8(occ_path.string());
    if (!o.ok()) return o.status();
    occupancy = std::move(o).value();
  }
  {
    std::vector<Row> rows;
    if (const auto* v = Get(s, "voxels"); v && v->is_object()) {
      const double occ = NumberOr(Get(*v, "occupied"), 0), fr = NumberOr(Get(*v, "free"), 0), un = NumberOr(Get(*v, "unknown"), 0);
      const double total = occ + fr + un;
      if (total > 0) {
        rows.push_back({"voxels occupied / free / unknown", Count(occ) + " / " + Count(fr) + " / " + Count(un)});
        rows.push_back({"unknown space (voxel grid)", "<b>" + Num(100.0 * un / total, 1) + " %</b> of " + Count(total) + " voxels"});
        if (fr + un > 0) rows.push_back({"unknown among non-occupied voxels", Num(100.0 * un / (fr + un), 1) + " %"});
      }
    }
    if (!occupancy.empty()) {
      size_t n_occ = 0, n_free = 0, n_unknown = 0;
      for (uint8_t p : occupancy.data) n_occ += p == kPgmOccupied, n_free += p == kPgmFree, n_unknown += p == kPgmUnknown;
      const double n = double(occupancy.data.size());
      rows.push_back({"unknown space (occupancy top view)", "<b>" + Num(100.0 * double(n_unknown) / n, 1) + " %</b> of " +
                                                             Count(n) + " cells (" + Num(100.0 * double(n_free) / n, 1) +
                                                             " % free, " + Num(100.0 * double(n_occ) / n, 1) + " % occupied)"});
    }
    if (semantic) {
      for (const char* k : {"occupied_voxels", "completed_voxels"})
        if (const auto* v = Get(*semantic, k)) rows.push_back({std::string("voxel CRF ") + k, Escape(Scalar(*v))});
      if (const auto* o = Get(*semantic, "wall_openings")) {  // objects/wall_openings.h
        const auto* doors = Get(*o, "doors");
        const auto* windows = Get(*o, "windows");
        const auto* leaves = Get(*o, "open_leaves");
        if (doors && windows && leaves)
          rows.push_back({"doors and windows found in the walls", Escape(Scalar(*doors)) + " doors (" + Escape(Scalar(*leaves)) +
                                                                      " standing open), " + Escape(Scalar(*windows)) + " windows"});
      }
    }
    if (rows.empty()) html << kNotComputed;
    else html << KeyValueTable(rows);
  }

  // ---- top views ----
  html << "<h2 id=\"topviews\">Top views</h2>\n<div class=\"views\">\n";
  const int shown = options.image_display_width_px;
  {
    html << "<figure><figcaption>Occupancy (black occupied, white free, grey unknown)</figcaption>\n";
    if (occupancy.empty()) html << kNotComputed;
    else {
      Result<std::string> png = EncodePng(occupancy);
      if (!png.ok()) return png.status();
      html << ImageTag(png.value(), occupancy.width, occupancy.height, shown, "occupancy top view");
    }
    html << "</figure>\n";
  }
  {
    html << "<figure><figcaption>Semantic (NYU40 colours)</figcaption>\n";
    const fs::path p = dir / "semantic_topview.png";
    if (!Exists(p)) html << kNotComputed;
    else {
      Result<ImageRgb8> img = ReadImageRgb8(p.string());
      if (!img.ok()) return img.status();
      Result<std::string> png = EncodePng(img.value());
      if (!png.ok()) return png.status();
      html << ImageTag(png.value(), img->width, img->height, shown, "semantic top view");
    }
    html << "</figure>\n";
  }
  std::vector<RoomRow> rooms;
  bool have_rooms_table = false;
  {
    html << "<figure><figcaption>Rooms (colours as in the room table)</figcaption>\n";
    const fs::path p = dir / "rooms.png";
    if (!Exists(p)) html << kNotComputed;
    else {
      Result<ImageU16> ids = ReadImageU16(p.string());
      if (!ids.ok()) return ids.status();
      ImageRgb8 rgb(ids->width, ids->height, 3);
      const bool same_size = !occupancy.empty() && occupancy.width == ids->width && occupancy.height == ids->height;
      for (int y = 0; y < ids->height; ++y)
        for (int x = 0; x < ids->width; ++x) {
          const int id = ids->at(x, y);
          Rgb8 c;
          if (id > 0) c = RoomDisplayColour(id);
          else {
            // Outside every room: the occupancy cell (walls dark), else light grey.
            const uint8_t g = same_size ? (occupancy.at(x, y) == kPgmFree ? 255 : occupancy.at(x, y) == kPgmUnknown ? 215 : 60) : 215;
            c = {g, g, g};
          }
          rgb.at(x, y, 0) = c.r, rgb.at(x, y, 1) = c.g, rgb.at(x, y, 2) = c.b;
        }
      Result<std::string> png = EncodePng(rgb);
      if (!png.ok()) return png.status();
      html << ImageTag(png.value(), rgb.width, rgb.height, shown, "rooms top view");
    }
    html << "</figure>\n</div>\n";
  }

  // ---- room table ----
  html << "<h2 id=\"rooms\">Rooms</h2>\n";
  {
    const fs::path p = dir / "rooms.geojson";
    if (Exists(p)) {
      SEMVOX_RETURN_IF_ERROR(ReadRooms(p, &rooms));
      have_rooms_table = true;
    }
    if (!have_rooms_table) html << kNotComputed;
    else if (rooms.empty()) html << "<p>no rooms found</p>\n";
    else {
      auto opt = [](const std::optional<double>& v, int decimals) { return v ? Num(*v, decimals) : std::string("&mdash;"); };
      html << "<table class=\"rooms num\" id=\"room-table\">\n<thead><tr><th>room</th><th>type</th><th>probability</th>"
              "<th>second type</th><th>probability</th><th>area (m&sup2;)</th><th>ceiling height (m)</th></tr></thead>\n<tbody>\n";
      double total_area = 0;
      for (const RoomRow& r : rooms) {
        total_area += r.area_m2.value_or(0);
        html << "<tr data-room=\"" << r.id << "\"><td><span class=\"swatch\" style=\"background:" << Hex(RoomDisplayColour(r.id))
             << "\"></span> " << r.id << "</td><td>" << Escape(r.type) << "</td><td>" << opt(r.probability, 2) << "</td><td>"
             << (r.second_type.empty() ? "&mdash;" : Escape(r.second_type)) << "</td><td>" << opt(r.second_probability, 2)
             << "</td><td>" << opt(r.area_m2, 2) << "</td><td>" << opt(r.ceiling_height_m, 2) << "</td></tr>\n";
      }
      html << "</tbody>\n</table>\n<p class=\"muted\">" << rooms.size() << " rooms, " << Num(total_area, 2)
           << " m&sup2; in all (floor area including furniture). Probabilities are the room-type CRF's; &mdash; = absent from rooms.geojson.</p>\n";
    }
  }

  // voxels.ply: the class histogram and the 3D view. Unreadable is no error: both say so.
  const VoxelsPly voxels = options.read_voxels_ply || options.view_3d ? ReadVoxelsPly(dir / "voxels.ply") : VoxelsPly();

  // ---- class histogram ----
  html << "<h2 id=\"classes\">Classes</h2>\n";
  {
    std::map<std::string, double> counts;  // NYU40 name -> occupied voxels.
    std::string source, unreadable;
    if (options.read_voxels_ply && voxels.data) {
      const PlyElement* vertex = voxels.data->Find("vertex");
      const PlyProperty* label = vertex ? vertex->Find("label") : nullptr;
      if (label && !label->is_list) {
        const auto& names = Nyu40Labels();
        for (double v : label->values) {
          const int id = int(v);
          counts[id >= 0 && id < kNumNyu40 ? names[size_t(id)].name : std::to_string(id)] += 1;
        }
        source = "voxels.ply (" + Count(double(vertex->count)) + " occupied voxels)";
      } else {
        unreadable = "voxels.ply has no vertex label";
      }
    } else if (options.read_voxels_ply && voxels.present) {
      unreadable = "voxels.ply is damaged";
    }
    if (source.empty() && semantic)
      if (const auto* labels = Get(*semantic, "labels"); labels && labels->is_object() && !labels->empty()) {
        for (const auto& [name, v] : labels->items())
          if (v.is_number()) counts[name] += v.get<double>();
        source = "summary.json" + (unreadable.empty() ? "" : " (" + unreadable + ")");
      }
    if (source.empty()) html << kNotComputed;
    else {
      std::vector<std::pair<std::string, double>> sorted(counts.begin(), counts.end());
      std::stable_sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
      double total = 0;
      for (const auto& e : sorted) total += e.second;
      html << "<p class=\"muted\">occupied voxels per NYU40 class, from " << Escape(source) << "</p>\n"
           << "<table class=\"classes\" id=\"class-table\">\n<tr><th>class</th><th>voxels</th><th>share</th></tr>\n";
      for (const auto& [name, n] : sorted) {
        const int id = Nyu40IdByName(name);
        const std::string colour = id >= 0 ? Hex(Nyu40Labels()[size_t(id)].color) : "#808080";
        html << "<tr><td><span class=\"swatch\" style=\"background:" << colour << "\"></span> " << Escape(name) << "</td><td>"
             << Count(n) << "</td><td>" << Bar(total > 0 ? n / total : 0, colour, Num(total > 0 ? 100.0 * n / total : 0, 1) + " %")
             << "</td></tr>\n";
      }
      html << "</table>\n";
    }
  }

  // ---- 3D view ----
  if (options.view_3d) html << View3dSection(s, voxels, rooms, options, summary);

  // ---- seconds per stage ----
  html << "<h2 id=\"time\">Seconds per stage</h2>\n";
  {
    std::vector<std::pair<std::string, double>> stages;
    if (const auto* t = Get(s, "seconds"); t && t->is_object())
      for (const auto& [k, v] : t->items())
        if (v.is_number()) stages.push_back({k, v.get<double>()});
    if (semantic)
      if (const auto* t = Get(*semantic, "seconds"); t && t->is_object())
        for (const auto& [k, v] : t->items())
          if (v.is_number()) stages.push_back({"voxel CRF: " + k, v.get<double>()});
    if (stages.empty()) html << kNotComputed;
    else {
      double total = 0;
      for (const auto& [k, v] : stages)
        if (k == "total") total = v;
      if (total <= 0)
        for (const auto& [k, v] : stages) total = std::max(total, v);
      html << "<table class=\"time\" id=\"time-table\">\n<tr><th>stage</th><th>seconds</th></tr>\n";
      for (const auto& [k, v] : stages)
        html << "<tr><td>" << Escape(k) << "</td><td>" << Bar(total > 0 ? v / total : 0, "#4a7ab0", Num(v, 3)) << "</td></tr>\n";
      html << "</table>\n";
    }
  }

  // ---- energies: every summary section with per-iteration energies (the Voxel-CRF, later the room-type CRF) ----
  html << "<h2 id=\"energy\">Energy per stage and iteration</h2>\n";
  {
    bool any = false;
    for (const auto& [section, value] : s.items()) {
      const ordered_json* its = Get(value, "iterations");
      if (!its || !its->is_array() || its->empty()) continue;
      any = true;
      html << "<h3>" << Escape(section == "semantic" ? "semantic (Voxel-CRF)" : section) << "</h3>\n"
           << "<table class=\"num energy\">\n<tr><th>iteration</th><th>energy before</th><th>energy after</th><th>sweeps</th>"
              "<th>changed labels</th><th>seconds</th><th>energy per sweep</th></tr>\n";
      for (size_t i = 0; i < its->size(); ++i) {
        const ordered_json& it = (*its)[i];
        auto field = [&](const char* k, int decimals) {
          const ordered_json* v = Get(it, k);
          return v && v->is_number() ? (decimals < 0 ? Count(v->get<double>()) : Num(v->get<double>(), decimals)) : std::string("&mdash;");
        };
        std::string sweeps;
        if (const auto* e = Get(it, "energy_per_sweep"); e && e->is_array())
          for (size_t k = 0; k < e->size(); ++k) sweeps += (k ? ", " : "") + ((*e)[k].is_number() ? Num((*e)[k].get<double>(), 1) : "?");
        html << "<tr><td>" << i + 1 << "</td><td>" << field("energy_initial", 1) << "</td><td>" << field("energy_final", 1) << "</td><td>"
             << field("sweeps", -1) << "</td><td>" << field("changed_labels", -1) << "</td><td class=\"seconds\">" << field("seconds", 3)
             << "</td><td class=\"muted\">" << (sweeps.empty() ? "&mdash;" : sweeps) << "</td></tr>\n";
      }
      html << "</table>\n";
    }
    if (!any) html << kNotComputed;
  }

  html << "<p class=\"muted\">Written by <code>semvox report</code> from the files in this directory; self-contained "
       << (summary->view_3d ? "(inline images, styles and scripts; no network)" : "(inline images and styles, no scripts, no network)")
       << ".</p>\n</body>\n</html>\n";
  std::string page = html.str();
  summary->bytes = page.size();
  return page;
}

Status WriteReport(const std::string& outdir, const ReportOptions& options, ReportSummary* summary) {
  Result<std::string> html = RenderReportHtml(outdir, options, summary);
  if (!html.ok()) return html.status();
  return WriteFileAtomic((fs::path(outdir) / options.output_name).string(), html.value());
}

}  // namespace semvox
