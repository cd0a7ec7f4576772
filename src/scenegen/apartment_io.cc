#include "scenegen/apartment_io.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "core/file_util.h"
#include "core/labels.h"
#include "core/mesh_ply.h"
#include "io/image_io.h"

namespace semvox {
namespace fs = std::filesystem;

bool GroundTruthOptions::Check(std::string* error) const {
  std::ostringstream os;
  if (!(resolution_m > 0)) os << "resolution_m = " << resolution_m << ". Violated constraint: > 0";
  else if (!(margin_m >= 0)) os << "margin_m = " << margin_m << ". Violated constraint: >= 0";
  else if (!(band_max_above_floor_m > band_min_above_floor_m))
    os << "band_max_above_floor_m = " << band_max_above_floor_m << ". Violated constraint: > band_min_above_floor_m";
  if (os.str().empty()) return true;
  if (error) *error = os.str();
  return false;
}

FloorGrid MakeFloorGrid(const Apartment& apt, const GroundTruthOptions& o) {
  FloorGrid g;
  g.resolution = o.resolution_m;
  const double res = o.resolution_m;
  g.origin_x = std::floor((apt.bounds.min.x() - o.margin_m) / res) * res;
  g.origin_y = std::floor((apt.bounds.min.y() - o.margin_m) / res) * res;
  g.width = int(std::ceil((apt.bounds.max.x() + o.margin_m - g.origin_x) / res));
  g.height = int(std::ceil((apt.bounds.max.y() + o.margin_m - g.origin_y) / res));
  return g;
}

ImageU16 RasterizeRooms(const Apartment& apt, const FloorGrid& g) {
  ImageU16 img(g.width, g.height, 1, 0);
  if (!apt.room_raster.data.empty()) {  // Rooms that are not boxes: sampled from the plan's raster.
    for (int r = 0; r < g.height; ++r)
      for (int c = 0; c < g.width; ++c) img.at(c, r) = uint16_t(RoomIdAt(apt, g.CenterX(c), g.CenterY(r)));
    return img;
  }
  for (const RoomGt& room : apt.rooms)
    for (int r = 0; r < g.height; ++r) {
      const double y = g.CenterY(r);
      if (y < room.y0 || y >= room.y1) continue;
      for (int c = 0; c < g.width; ++c) {
        const double x = g.CenterX(c);
        if (x >= room.x0 && x < room.x1) img.at(c, r) = uint16_t(room.id);
      }
    }
  return img;
}

ImageU16 RasterizeTopView(const Apartment& apt, const FloorGrid& g, const GroundTruthOptions& o) {
  ImageU16 img(g.width, g.height, 1, 0);
  std::vector<double> best_top(size_t(g.width) * g.height, -1e9), best_area(size_t(g.width) * g.height, 0);
  const double lo = apt.floor_z_m + o.band_min_above_floor_m, hi = apt.floor_z_m + o.band_max_above_floor_m;
  for (const SolidPart& p : apt.parts) {
    const OrientedBox& b = p.box;
    const double z0 = b.center.z() - b.size.z() / 2, z1 = b.center.z() + b.size.z() / 2;
    if (z1 <= lo || z0 >= hi) continue;
    const double top = std::min(z1, hi), area = b.size.x() * b.size.y();
    const double cs = std::cos(b.yaw_rad), sn = std::sin(b.yaw_rad);
    const double ex = std::fabs(cs) * b.size.x() / 2 + std::fabs(sn) * b.size.y() / 2;
    const double ey = std::fabs(sn) * b.size.x() / 2 + std::fabs(cs) * b.size.y() / 2;
    int c0, r0, c1, r1;
    if (!g.PixelOf(std::max(b.center.x() - ex, g.origin_x), std::min(b.center.y() + ey, g.origin_y + g.height * g.resolution - 1e-9), &c0, &r0) ||
        !g.PixelOf(std::min(b.center.x() + ex, g.origin_x + g.width * g.resolution - 1e-9), std::max(b.center.y() - ey, g.origin_y), &c1, &r1))
      continue;
    // A solid covers a pixel when it overlaps the pixel's cell, half-open as the voxel keys are: the
    // cell is shifted down by a hair, so a face on a cell edge belongs to the cell above it (as in
    // mapping/voxelizer.cc). Separating-axis test of the cell square against the solid's rectangle.
    const double half = 0.5 * g.resolution, eps = 1e-4 * g.resolution;
    const double bx = b.size.x() / 2, by = b.size.y() / 2;
    for (int r = std::max(0, r0 - 1); r <= std::min(g.height - 1, r1 + 1); ++r)
      for (int c = std::max(0, c0 - 1); c <= std::min(g.width - 1, c1 + 1); ++c) {
        const double dx = g.CenterX(c) - eps - b.center.x(), dy = g.CenterY(r) - eps - b.center.y();
        if (std::fabs(dx) > half + std::fabs(cs) * bx + std::fabs(sn) * by) continue;
        if (std::fabs(dy) > half + std::fabs(sn) * bx + std::fabs(cs) * by) continue;
        const double lx = cs * dx + sn * dy, ly = -sn * dx + cs * dy;
        if (std::fabs(lx) > bx + half * (std::fabs(cs) + std::fabs(sn))) continue;
        if (std::fabs(ly) > by + half * (std::fabs(sn) + std::fabs(cs))) continue;
        const size_t i = size_t(r) * g.width + c;
        // The highest solid wins; at equal height the smaller one (what stands on or in the larger).
        if (top > best_top[i] + 1e-9 || (std::fabs(top - best_top[i]) <= 1e-9 && area < best_area[i])) {
          best_top[i] = top;
          best_area[i] = area;
          img.at(c, r) = uint16_t(p.label);
        }
      }
  }
  // Columns a surface passes through within the band: sample every face at a quarter pixel.
  std::vector<uint8_t> seen(size_t(g.width) * g.height, 0);
  const Mesh& m = apt.mesh;
  for (const Eigen::Vector3i& f : m.faces) {
    const Eigen::Vector3d a = m.vertices[size_t(f[0])].cast<double>(), b = m.vertices[size_t(f[1])].cast<double>(),
                          c = m.vertices[size_t(f[2])].cast<double>();
    if (std::max({a.z(), b.z(), c.z()}) < lo || std::min({a.z(), b.z(), c.z()}) >= hi) continue;
    const double edge = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, int(std::ceil(edge / (0.25 * g.resolution))));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Eigen::Vector3d p = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
        int pc, pr;
        if (p.z() >= lo && p.z() < hi && g.PixelOf(p.x(), p.y(), &pc, &pr)) seen[size_t(pr) * g.width + pc] = 1;
      }
  }
  for (size_t i = 0; i < img.data.size(); ++i)
    if (img.data[i] != 0 && !seen[i]) img.data[i] = kTopViewHidden;
  return img;
}

ImageRgb8 RenderPreview(const Apartment& apt, const ImageU16& rooms, const ImageU16& topview, int scale) {
  const auto& labels = Nyu40Labels();
  // Room-type tints (pastel), indexed by type id.
  static const Rgb8 kTint[kNumRoomTypes] = {{255, 255, 255}, {200, 230, 255}, {255, 220, 220}, {255, 235, 200},
                                            {230, 230, 230}, {240, 220, 255}, {255, 250, 200}, {210, 255, 240},
                                            {220, 255, 210}, {255, 225, 245}, {235, 235, 210}, {225, 215, 200},
                                            {245, 245, 245}};
  ImageRgb8 img(rooms.width * scale, rooms.height * scale, 3, 255);
  for (int r = 0; r < rooms.height; ++r)
    for (int c = 0; c < rooms.width; ++c) {
      Rgb8 col{255, 255, 255};
      const int id = rooms.at(c, r);
      if (id > 0 && id <= int(apt.rooms.size())) col = kTint[apt.rooms[size_t(id - 1)].type_id];
      const int l = topview.at(c, r);
      if (l == nyu40::kWall || l == kTopViewHidden) col = Rgb8{60, 60, 60};
      else if (l > 0 && l < kNumNyu40) col = labels[size_t(l)].color;
      for (int y = 0; y < scale; ++y)
        for (int x = 0; x < scale; ++x) {
          img.at(c * scale + x, r * scale + y, 0) = col.r;
          img.at(c * scale + x, r * scale + y, 1) = col.g;
          img.at(c * scale + x, r * scale + y, 2) = col.b;
        }
    }
  return img;
}

namespace {
double R4(double v) { return std::round(v * 1e4) / 1e4; }
}  // namespace

std::string GroundTruthJson(const Apartment& apt, const FloorGrid& g, const GroundTruthOptions& go,
                            const ApartmentOptions& options, const ScanArtefactOptions& art, bool with_cloud) {
  using nlohmann::ordered_json;
  const auto& labels = Nyu40Labels();
  const auto& types = RoomTypes();
  ordered_json j;
  j["format"] = kGroundTruthFormat;
  j["version"] = 1;
  j["seed"] = apt.seed;
  if (!apt.plan.empty()) j["plan"] = apt.plan;  // Absent for drawn layouts: their files stay as they were.
  j["floor_z_m"] = R4(apt.floor_z_m);
  j["ceiling_z_m"] = R4(apt.ceiling_z_m);
  j["interior_wall_m"] = R4(apt.interior_wall_m);
  j["exterior_wall_m"] = R4(apt.exterior_wall_m);
  j["topview_band_above_floor_m"] = {R4(go.band_min_above_floor_m), R4(go.band_max_above_floor_m)};
  const ordered_json grid = {{"resolution", R4(g.resolution)}, {"origin", {R4(g.origin_x), R4(g.origin_y)}},
                             {"width", g.width}, {"height", g.height}};
  j["rooms_gt"] = grid;
  j["rooms_gt"]["image"] = "rooms_gt.png";
  j["topview_gt"] = grid;
  j["topview_gt"]["image"] = "topview_gt.png";
  j["topview_gt"]["hidden_value"] = kTopViewHidden;
  j["files"] = {{"mesh", "mesh.ply"}, {"gt_mesh", "gt_mesh.ply"}};
  if (with_cloud) j["files"]["cloud"] = "cloud.ply";
  ordered_json rooms = ordered_json::array();
  for (const RoomGt& r : apt.rooms) {
    rooms.push_back({{"id", r.id},
                     {"type_id", r.type_id},
                     {"type", types[size_t(r.type_id)].name},
                     {"polygon", {{R4(r.x0), R4(r.y0)}, {R4(r.x1), R4(r.y0)}, {R4(r.x1), R4(r.y1)}, {R4(r.x0), R4(r.y1)}}},
                     {"area_m2", R4(r.area_m2())},
                     {"open_to", r.open_to}});
  }
  j["rooms"] = rooms;
  ordered_json doors = ordered_json::array();
  for (const DoorGt& d : apt.doors)
    doors.push_back({{"rooms", {d.room_a, d.room_b}}, {"center", {R4(d.center.x()), R4(d.center.y())}},
                     {"wall_along", d.along_x ? "x" : "y"}, {"width_m", R4(d.width_m)}, {"height_m", R4(d.height_m)},
                     {"wall_thickness_m", R4(d.wall_thickness_m)}});
  j["doors"] = doors;
  ordered_json windows = ordered_json::array();
  for (const WindowGt& w : apt.windows)
    windows.push_back({{"room", w.room}, {"center", {R4(w.center.x()), R4(w.center.y())}}, {"wall_along", w.along_x ? "x" : "y"},
                       {"width_m", R4(w.width_m)}, {"sill_m", R4(w.sill_m)}, {"top_m", R4(w.top_m)}});
  j["windows"] = windows;
  ordered_json objects = ordered_json::array();
  std::map<std::string, int> per_class;
  for (const ObjectGt& o : apt.objects) {
    objects.push_back({{"instance", o.instance},
                       {"label", o.label},
                       {"class", labels[size_t(o.label)].name},
                       {"room", o.room},
                       {"on", o.support_of},
                       {"box", {{"center", {R4(o.box.center.x()), R4(o.box.center.y()), R4(o.box.center.z())}},
                                {"size", {R4(o.box.size.x()), R4(o.box.size.y()), R4(o.box.size.z())}},
                                {"yaw_rad", R4(o.box.yaw_rad)}}}});
    ++per_class[labels[size_t(o.label)].name];
  }
  j["objects"] = objects;
  j["counts"] = {{"rooms", apt.rooms.size()}, {"objects", apt.objects.size()}, {"gt_mesh_faces", apt.mesh.faces.size()},
                 {"objects_per_class", per_class}};
  j["generator_options"] = {{"seed", options.seed}, {"min_rooms", options.min_rooms}, {"max_rooms", options.max_rooms},
                            {"floor_z_m", options.floor_z_m}, {"min_ceiling_m", options.min_ceiling_m},
                            {"max_ceiling_m", options.max_ceiling_m}, {"min_wall_m", options.min_wall_m},
                            {"max_wall_m", options.max_wall_m}, {"surface_cell_m", options.surface_cell_m},
                            {"furniture", options.furniture}, {"props", options.props}};
  if (options.shape_variety) j["generator_options"]["shape_variety"] = true;  // Absent when off: files as before.
  j["artefact_options"] = {{"remove_hidden", art.remove_hidden}, {"hidden_margin_m", art.hidden_margin_m},
                           {"holes_per_m2", art.holes_per_m2}, {"min_hole_radius_m", art.min_hole_radius_m},
                           {"max_hole_radius_m", art.max_hole_radius_m},
                           {"unscanned_ceiling_fraction", art.unscanned_ceiling_fraction},
                           {"face_dropout", art.face_dropout}, {"vertex_noise_m", art.vertex_noise_m},
                           {"roughness_m", art.roughness_m}, {"roughness_wavelength_m", art.roughness_wavelength_m}};
  return j.dump(2) + "\n";
}

Status WriteApartment(const std::string& dir, const Apartment& apt, const ApartmentOptions& options,
                      const ScanArtefactOptions& artefacts, const GroundTruthOptions& go, bool with_cloud) {
  std::string error;
  if (!artefacts.Check(&error)) return Status::InvalidInput("scan artefact options: " + error);
  if (!go.Check(&error)) return Status::InvalidInput("ground truth options: " + error);
  SEMVOX_RETURN_IF_ERROR(EnsureWritableDirectory(dir));
  const fs::path d(dir);
  const std::string comment = "semvox generated apartment seed " + std::to_string(apt.seed) +
                              "; face label = NYU40 id, instance = object, room = gt.json room id";
  SEMVOX_RETURN_IF_ERROR(WriteMeshPly((d / "mesh.ply").string(), ApplyScanArtefacts(apt, artefacts), comment + "; scan artefacts"));
  SEMVOX_RETURN_IF_ERROR(WriteMeshPly((d / "gt_mesh.ply").string(), apt.mesh, comment + "; clean"));
  const FloorGrid grid = MakeFloorGrid(apt, go);
  const ImageU16 rooms = RasterizeRooms(apt, grid), topview = RasterizeTopView(apt, grid, go);
  SEMVOX_RETURN_IF_ERROR(WriteImage((d / "rooms_gt.png").string(), rooms));
  SEMVOX_RETURN_IF_ERROR(WriteImage((d / "topview_gt.png").string(), topview));
  SEMVOX_RETURN_IF_ERROR(WriteImage((d / "preview.png").string(), RenderPreview(apt, rooms, topview, 3)));
  return WriteFileAtomic((d / "gt.json").string(), GroundTruthJson(apt, grid, go, options, artefacts, with_cloud));
}

}  // namespace semvox
