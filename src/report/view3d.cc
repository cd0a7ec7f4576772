#include "report/view3d.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

#include "core/labels.h"
#include "core/majority.h"
#include "report/html_text.h"
#include "report/report.h"

namespace semvox {

// The view's script (src/report/view3d.js), compiled in by src/report/CMakeLists.txt.
extern const char* const kView3dScript;

namespace {

// When neither summary.json nor the centres give a spacing (a single voxel): the default mapping.voxel_size_m.
constexpr double kFallbackVoxelSizeM = 0.05;
// Centres closer than this along an axis are the same coordinate (float rounding), metres.
constexpr double kSameCoordinateM = 1e-4;
// Cells of the view along an axis before MergeToFit must be representable (indices are int32).
constexpr double kMaxCellIndex = double(1 << 30);
// Walls and furniture switch with the nearest room this close (RoomGroups), metres: half the width of a bed.
constexpr double kRoomReachM = 1.0;

// Smallest gap between distinct sorted coordinates over the three axes; 0 when every axis has one value.
double SmallestSpacing(const std::vector<Eigen::Vector3d>& centres) {
  double best = 0;
  std::vector<double> v(centres.size());
  for (int a = 0; a < 3; ++a) {
    for (size_t i = 0; i < centres.size(); ++i) v[i] = centres[i][a];
    std::sort(v.begin(), v.end());
    for (size_t i = 1; i < v.size(); ++i) {
      const double gap = v[i] - v[i - 1];
      if (gap > kSameCoordinateM && (best == 0 || gap < best)) best = gap;
    }
  }
  return best;
}

int64_t CellKey(const std::array<int32_t, 3>& ijk, const std::array<int32_t, 3>& dims) {
  return (int64_t(ijk[2]) * dims[1] + ijk[1]) * dims[0] + ijk[0];
}

// Sorts by (z, y, x) and keeps the first cell of each position (stable, so "first" is the input order).
void SortAndDeduplicate(std::vector<View3dCell>* cells, const std::array<int32_t, 3>& dims) {
  std::stable_sort(cells->begin(), cells->end(),
                   [&](const View3dCell& a, const View3dCell& b) { return CellKey(a.ijk, dims) < CellKey(b.ijk, dims); });
  cells->erase(std::unique(cells->begin(), cells->end(), [](const View3dCell& a, const View3dCell& b) { return a.ijk == b.ijk; }),
               cells->end());
}

bool FitsThePage(const View3dVoxels& v, size_t max_cells) {
  const int64_t cells = int64_t(v.dims[0]) * v.dims[1] * v.dims[2];
  return v.cells.size() <= max_cells && cells <= kView3dMaxGridCells &&
         std::max({v.dims[0], v.dims[1], v.dims[2]}) <= kView3dMaxCellsPerAxis;
}

std::string LittleEndian16(const std::vector<uint16_t>& values) {
  std::string out(values.size() * 2, '\0');
  for (size_t i = 0; i < values.size(); ++i) out[2 * i] = char(values[i] & 0xff), out[2 * i + 1] = char(values[i] >> 8);
  return out;
}

std::string Count(size_t n) {
  std::string digits = std::to_string(n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

// "5 cm", "12.5 cm", "1 m", "1.6 m".
std::string Metres(double v) {
  std::ostringstream os;
  if (v >= 1.0) os << std::round(v * 100.0) / 100.0 << " m";
  else os << std::round(v * 1000.0) / 10.0 << " cm";
  return os.str();
}

nlohmann::ordered_json ColourJson(const Rgb8& c) { return {c.r, c.g, c.b}; }

}  // namespace

Result<View3dVoxels> View3dVoxelsFromPly(const PlyData& ply, const std::string& name, const Eigen::Isometry3d& canonical_from_input,
                                         double voxel_size_m) {
  const PlyElement* vertex = ply.Find("vertex");
  if (!vertex) return Status::InvalidInput(FileError(name, "no 'vertex' element", "pass the voxels.ply of `semvox run`"));
  auto scalar = [&](const char* p) -> const PlyProperty* {
    const PlyProperty* q = vertex->Find(p);
    return q && !q->is_list ? q : nullptr;
  };
  const PlyProperty *x = scalar("x"), *y = scalar("y"), *z = scalar("z"), *label = scalar("label");
  if (!x || !y || !z || !label)
    return Status::InvalidInput(FileError(name, "expected vertex properties x, y, z and label (NYU40 id)", "pass the voxels.ply of `semvox run`"));
  const PlyProperty *confidence = scalar("confidence"), *room = scalar("room"), *completed = scalar("completed");
  View3dVoxels v;
  v.source_voxels = vertex->count;
  v.has_confidence = confidence != nullptr, v.has_room = room != nullptr, v.has_completed = completed != nullptr;
  const size_t n = vertex->count;
  std::vector<Eigen::Vector3d> centres(n);
  const bool identity = IsIdentity(canonical_from_input);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p(x->values[i], y->values[i], z->values[i]);
    if (!p.allFinite()) return Status::InvalidInput(FileError(name, "vertex " + std::to_string(i) + " has a non-finite coordinate", "re-run semvox run"));
    centres[i] = identity ? p : Eigen::Vector3d(canonical_from_input * p);
    const double l = label->values[i];
    if (!(l >= 0 && l <= 65535 && l == std::floor(l)))
      return Status::InvalidInput(FileError(name, "vertex " + std::to_string(i) + ": label " + std::to_string(l) + " is not a NYU40 id (an integer >= 0)",
                                            "re-run semvox run"));
  }
  if (voxel_size_m > 0) v.voxel_size_m = voxel_size_m;
  else {
    v.voxel_size_m = SmallestSpacing(centres);
    if (v.voxel_size_m <= 0) v.voxel_size_m = kFallbackVoxelSizeM;
  }
  if (n == 0) return v;
  Eigen::Vector3d lo = centres[0];
  for (const auto& c : centres) lo = lo.cwiseMin(c);
  v.origin = lo;
  v.cells.resize(n);
  for (size_t i = 0; i < n; ++i) {
    View3dCell& cell = v.cells[i];
    for (int a = 0; a < 3; ++a) {
      const double index = std::round((centres[i][a] - lo[a]) / v.voxel_size_m);
      if (index > kMaxCellIndex)
        return Status::InvalidInput(FileError(name, "the voxels span more than 2^30 voxels of " + Metres(v.voxel_size_m) + " along an axis",
                                              "check summary.json's voxel_size_m"));
      cell.ijk[a] = int32_t(index);
      v.dims[a] = std::max(v.dims[a], cell.ijk[a] + 1);
    }
    cell.label = uint16_t(label->values[i]);
    if (confidence) {
      const double c = confidence->values[i];
      cell.confidence = std::isfinite(c) ? float(std::clamp(c, 0.0, 1.0)) : 0.0f;
    }
    if (room) {
      const double r = room->values[i];
      cell.room = std::isfinite(r) && r > 0 ? int32_t(std::min(r, 65535.0)) : 0;
    }
    if (completed) cell.completed = completed->values[i] != 0;
  }
  SortAndDeduplicate(&v.cells, v.dims);
  return v;
}

View3dVoxels MergeBlocks(const View3dVoxels& in) {
  View3dVoxels out;
  out.voxel_size_m = 2 * in.voxel_size_m;
  out.merge = 2 * in.merge;
  out.source_voxels = in.source_voxels;
  // Cell I covers cells 2I and 2I + 1: its centre is half an old cell above the old cell 2I's.
  out.origin = in.origin + Eigen::Vector3d::Constant(0.5 * in.voxel_size_m);
  for (int a = 0; a < 3; ++a) out.dims[a] = (in.dims[a] + 1) / 2;
  out.has_confidence = in.has_confidence, out.has_room = in.has_room, out.has_completed = in.has_completed;
  std::vector<std::pair<int64_t, size_t>> order(in.cells.size());
  for (size_t i = 0; i < in.cells.size(); ++i) {
    const auto& c = in.cells[i].ijk;
    order[i] = {CellKey({c[0] / 2, c[1] / 2, c[2] / 2}, out.dims), i};
  }
  std::sort(order.begin(), order.end());
  std::vector<uint16_t> labels;
  std::vector<int32_t> rooms;
  for (size_t g = 0; g < order.size();) {
    size_t e = g;
    labels.clear(), rooms.clear();
    double confidence = 0;
    size_t completed = 0;
    for (; e < order.size() && order[e].first == order[g].first; ++e) {
      const View3dCell& c = in.cells[order[e].second];
      labels.push_back(c.label), rooms.push_back(c.room);
      confidence += c.confidence, completed += c.completed;
    }
    const size_t count = e - g;
    const View3dCell& first = in.cells[order[g].second];
    View3dCell m;
    m.ijk = {first.ijk[0] / 2, first.ijk[1] / 2, first.ijk[2] / 2};
    m.label = Majority(&labels);
    m.room = Majority(&rooms);
    m.confidence = float(confidence / double(count));
    m.completed = 2 * completed > count;
    out.cells.push_back(m);
    g = e;
  }
  return out;
}

std::vector<int32_t> RoomGroups(const View3dVoxels& v, double reach_m) {
  const int64_t nx = v.dims[0], ny = v.dims[1];
  // Room of each column: the most frequent room > 0 among its voxels (ties: the smaller id), 0 for none.
  std::map<int64_t, std::map<int32_t, size_t>> votes;
  for (const View3dCell& c : v.cells)
    if (c.room > 0) ++votes[c.ijk[1] * nx + c.ijk[0]][c.room];
  std::vector<int32_t> column(size_t(nx * ny), 0);
  std::vector<int64_t> layer;
  for (const auto& [col, rooms] : votes) {
    int32_t best = 0;
    size_t best_n = 0;
    for (const auto& [room, n] : rooms)
      if (n > best_n) best = room, best_n = n;
    column[size_t(col)] = best;
    layer.push_back(col);
  }
  // Brushfire from those columns, one ring of cells per step; a column reached by several rooms in the same
  // step takes the smallest id.
  const int steps = int(std::floor(reach_m / v.voxel_size_m + 1e-9));
  std::vector<uint8_t> done(column.size(), 0);
  for (int64_t col : layer) done[size_t(col)] = 1;
  for (int step = 0; step < steps && !layer.empty(); ++step) {
    std::map<int64_t, int32_t> next;
    for (int64_t col : layer) {
      const int64_t x = col % nx, y = col / nx;
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dx = -1; dx <= 1; ++dx) {
          const int64_t ax = x + dx, ay = y + dy;
          if (ax < 0 || ay < 0 || ax >= nx || ay >= ny) continue;
          const int64_t a = ay * nx + ax;
          if (done[size_t(a)]) continue;
          auto [it, inserted] = next.emplace(a, column[size_t(col)]);
          if (!inserted) it->second = std::min(it->second, column[size_t(col)]);
        }
    }
    layer.clear();
    for (const auto& [a, room] : next) column[size_t(a)] = room, done[size_t(a)] = 1, layer.push_back(a);
  }
  std::vector<int32_t> groups(v.cells.size());
  for (size_t i = 0; i < v.cells.size(); ++i) {
    const View3dCell& c = v.cells[i];
    groups[i] = c.room > 0 ? c.room : column[size_t(c.ijk[1] * nx + c.ijk[0])];
  }
  return groups;
}

View3dVoxels MergeToFit(View3dVoxels voxels, size_t max_cells) {
  max_cells = std::max<size_t>(max_cells, 1);
  while (!FitsThePage(voxels, max_cells)) voxels = MergeBlocks(voxels);
  return voxels;
}

const char* View3dCss() {
  return R"CSS(
.v3{border:1px solid #c0c0c0;background:#f7f7f7;font-size:13px}
.v3-bar{display:flex;flex-wrap:wrap;gap:6px 14px;align-items:center;padding:4px 8px;border-bottom:1px solid #c0c0c0}
.v3-bar button{font-size:12px}
.v3-body{display:flex;height:560px}
.v3-stage{position:relative;flex:1;min-width:0;background:rgb(233,236,241)}
.v3-stage canvas{display:block;width:100%;height:100%;touch-action:none;cursor:grab}
.v3-info{position:absolute;left:8px;top:6px;right:8px;font-size:12px;color:#202020;pointer-events:none}
.v3-side{width:240px;overflow-y:auto;border-left:1px solid #c0c0c0;padding:4px 8px}
.v3-group{margin-bottom:10px} .v3-group button{font-size:11px;padding:0 4px}
.v3-row{display:block;white-space:nowrap;overflow:hidden;text-overflow:ellipsis;font-size:12px}
.v3-row input{margin:1px 4px 1px 0;vertical-align:middle}
.v3-help{margin:2px 8px 4px 8px}
.v3-ramp{display:inline-block;width:120px;height:10px;vertical-align:middle;border:1px solid #404040;
 background:linear-gradient(to right,rgb(68,1,84),rgb(59,82,139),rgb(33,145,140),rgb(94,201,98),rgb(253,231,37))}
#v3-back{display:none}
body.v3-full{overflow:hidden;margin:0;max-width:none}
body.v3-full>*:not(#view3d){display:none!important}
body.v3-full #view3d{position:fixed;left:0;top:0;right:0;bottom:0;display:flex;flex-direction:column;border:none;z-index:10}
body.v3-full .v3-body{flex:1;height:auto;min-height:0}
body.v3-full #v3-full{display:none} body.v3-full #v3-back{display:inline}
)CSS";
}

std::string View3dAbsentHtml(const std::string& reason) {
  return "<h2 id=\"view3d-title\">3D view</h2>\n<p class=\"na\" id=\"view3d-absent\">3D view not available: " + html::Escape(reason) + "</p>\n";
}

std::string View3dHtml(const View3dVoxels& voxels, const std::vector<View3dRoom>& rooms, const std::string& three_js) {
  const size_t n = voxels.cells.size();
  // Switches: every class present and every room (the room table's, then any other id the voxels carry).
  const std::vector<int32_t> groups = voxels.has_room ? RoomGroups(voxels, kRoomReachM) : std::vector<int32_t>(n, 0);
  std::map<int, size_t> class_voxels, room_voxels;  // Room switches count the voxels that switch with the room.
  for (size_t i = 0; i < n; ++i) ++class_voxels[voxels.cells[i].label], ++room_voxels[groups[i]];
  std::map<int, std::string> room_types;
  for (const View3dRoom& r : rooms) room_types[r.id] = r.type;
  const auto& nyu40 = Nyu40Labels();
  auto class_name = [&](int id) { return id < kNumNyu40 ? std::string(nyu40[size_t(id)].name) : "label " + std::to_string(id); };
  auto class_colour = [&](int id) { return id < kNumNyu40 ? nyu40[size_t(id)].color : Rgb8{128, 128, 128}; };
  auto room_colour = [&](int id) { return id > 0 ? RoomDisplayColour(id) : kView3dNoRoomColour; };
  auto room_text = [&](int id) {
    if (id == 0) return std::string("outside every room");
    auto it = room_types.find(id);
    return std::to_string(id) + (it != room_types.end() && !it->second.empty() ? " " + it->second : "");
  };

  // The packed voxels (little-endian; the page decodes them byte by byte).
  std::vector<uint16_t> ijk(3 * n), labels(n), room_ids(n), room_groups(n);
  std::string confidence(n, '\0'), completed((n + 7) / 8, '\0');
  for (size_t i = 0; i < n; ++i) {
    const View3dCell& c = voxels.cells[i];
    for (int a = 0; a < 3; ++a) ijk[3 * i + a] = uint16_t(c.ijk[a]);
    labels[i] = c.label;
    room_ids[i] = uint16_t(c.room);
    room_groups[i] = uint16_t(groups[i]);
    confidence[i] = char(std::lround(c.confidence * 255.0f));
    if (c.completed) completed[i / 8] = char(uint8_t(completed[i / 8]) | uint8_t(1u << (i % 8)));
  }
  nlohmann::ordered_json data;
  data["voxel_size_m"] = voxels.voxel_size_m;
  data["merge"] = voxels.merge;
  data["source_voxels"] = voxels.source_voxels;
  data["count"] = n;
  data["origin"] = {voxels.origin.x(), voxels.origin.y(), voxels.origin.z()};
  data["dims"] = {voxels.dims[0], voxels.dims[1], voxels.dims[2]};
  data["background"] = ColourJson(kView3dBackground);
  data["no_room_colour"] = ColourJson(kView3dNoRoomColour);
  data["completed_colour"] = ColourJson(kView3dCompletedColour);
  data["seen_colour"] = ColourJson(kView3dSeenColour);
  data["cells"] = html::Base64(LittleEndian16(ijk));
  data["labels"] = html::Base64(LittleEndian16(labels));
  data["confidence"] = voxels.has_confidence ? nlohmann::ordered_json(html::Base64(confidence)) : nlohmann::ordered_json();
  data["rooms"] = voxels.has_room ? nlohmann::ordered_json(html::Base64(LittleEndian16(room_ids))) : nlohmann::ordered_json();
  data["room_groups"] = voxels.has_room ? nlohmann::ordered_json(html::Base64(LittleEndian16(room_groups))) : nlohmann::ordered_json();
  data["completed"] = voxels.has_completed ? nlohmann::ordered_json(html::Base64(completed)) : nlohmann::ordered_json();
  data["classes"] = nlohmann::ordered_json::array();
  for (const auto& [id, count] : class_voxels)
    data["classes"].push_back({{"id", id}, {"name", class_name(id)}, {"colour", ColourJson(class_colour(id))}});
  data["room_list"] = nlohmann::ordered_json::array();
  for (const auto& [id, count] : room_voxels)
    data["room_list"].push_back({{"id", id}, {"name", room_text(id)}, {"colour", ColourJson(room_colour(id))}});

  std::ostringstream os;
  os << "<h2 id=\"view3d-title\">3D view</h2>\n"
     << "<section id=\"view3d\" class=\"v3\" data-state=\"loading\">\n<div class=\"v3-bar\">\n"
     << "<label>colour by <select id=\"v3-colour\" autocomplete=\"off\"><option value=\"class\" selected>class</option>"
     << "<option value=\"room\"" << (voxels.has_room ? "" : " disabled") << ">room</option>"
     << "<option value=\"confidence\"" << (voxels.has_confidence ? "" : " disabled") << ">confidence</option>"
     << "<option value=\"completed\"" << (voxels.has_completed ? "" : " disabled") << ">seen / completed</option></select></label>\n"
     << "<span id=\"v3-legend\"></span>\n"
     << "<button type=\"button\" id=\"v3-top\">top view</button><button type=\"button\" id=\"v3-reset\">reset view</button>\n"
     << "<a id=\"v3-full\" href=\"#3d\">full window</a><a id=\"v3-back\" href=\"#view3d-title\">back to the report</a>\n"
     << "</div>\n<div class=\"v3-body\">\n<div class=\"v3-stage\" id=\"v3-stage\"><canvas id=\"v3-canvas\"></canvas>"
     << "<div class=\"v3-info\" id=\"v3-info\">click a voxel for its class, confidence and room</div></div>\n<div class=\"v3-side\">\n";
  os << "<div class=\"v3-group\" id=\"v3-classes\"><b>classes</b> <button type=\"button\" data-all=\"class\">all</button>"
        "<button type=\"button\" data-none=\"class\">none</button>\n";
  for (const auto& [id, count] : class_voxels)
    os << "<label class=\"v3-row\"><input type=\"checkbox\" autocomplete=\"off\" data-class=\"" << id << "\""
       << (id == nyu40::kCeiling ? "" : " checked") << "><span class=\"swatch\" style=\"background:" << html::Hex(class_colour(id))
       << "\"></span> " << html::Escape(class_name(id)) << " <span class=\"muted\">" << Count(count) << "</span></label>\n";
  os << "</div>\n";
  if (voxels.has_room) {
    os << "<div class=\"v3-group\" id=\"v3-rooms\"><b>rooms</b> <button type=\"button\" data-all=\"room\">all</button>"
          "<button type=\"button\" data-none=\"room\">none</button>\n";
    for (const auto& [id, count] : room_voxels)
      os << "<label class=\"v3-row\"><input type=\"checkbox\" autocomplete=\"off\" data-room=\"" << id << "\" checked><span class=\"swatch\" style=\"background:"
         << html::Hex(room_colour(id)) << "\"></span> " << html::Escape(room_text(id)) << " <span class=\"muted\">" << Count(count) << "</span></label>\n";
    os << "</div>\n";
  }
  os << "</div>\n</div>\n<p class=\"muted v3-help\">" << Count(n) << " voxels";
  if (voxels.merge > 1)
    os << " (" << Count(voxels.source_voxels) << " voxels of voxels.ply merged into cells of " << voxels.merge << "&times;" << voxels.merge
       << "&times;" << voxels.merge << " to keep the page small)";
  os << " of " << Metres(voxels.voxel_size_m) << ", canonical frame (floor at z = 0, walls along x and y); the ceiling starts hidden. "
        "Drag: turn; right-drag or shift-drag: pan; wheel: zoom; click: a voxel's class, confidence and room. "
        "A room's switch also takes the walls and furniture within " << Metres(kRoomReachM) << " of its floor. "
        "<a href=\"#3d\">report.html#3d</a> opens this view in the full window.</p>\n</section>\n";
  os << "<script type=\"application/json\" id=\"v3-data\">" << html::ScriptSafeJson(data.dump()) << "</script>\n";
  os << "<script id=\"v3-three\">\n" << three_js << "\n</script>\n";
  os << "<script id=\"v3-script\">\n" << kView3dScript << "\n</script>\n";
  return os.str();
}

}  // namespace semvox
