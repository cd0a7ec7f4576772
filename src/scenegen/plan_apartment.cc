#include "scenegen/plan_apartment.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <sstream>
#include <tuple>

#include "core/labels.h"
#include "scenegen/apartment_builder.h"
#include "scenegen/layout.h"
#include "scenegen/random.h"

namespace semvox {

bool PlanApartmentOptions::Check(std::string* error) const {
  std::ostringstream os;
  if (!(ceiling_m >= 2 && ceiling_m <= 4)) os << "ceiling_m = " << ceiling_m << ". Violated constraint: 2 <= ceiling_m <= 4";
  else if (!(wall_m >= 0.05 && wall_m <= 0.4)) os << "wall_m = " << wall_m << ". Violated constraint: 0.05 <= wall_m <= 0.4";
  else if (!(door_height_m > 0 && door_height_m < ceiling_m))
    os << "door_height_m = " << door_height_m << ". Violated constraint: 0 < door_height_m < ceiling_m";
  else if (!(window_sill_m > 0 && window_sill_m < window_top_m && window_top_m < ceiling_m))
    os << "window_sill_m = " << window_sill_m << ", window_top_m = " << window_top_m
       << ". Violated constraint: 0 < window_sill_m < window_top_m < ceiling_m";
  else if (!(min_window_wall_m > 0)) os << "min_window_wall_m = " << min_window_wall_m << ". Violated constraint: > 0";
  else if (!(surface_cell_m > 0)) os << "surface_cell_m = " << surface_cell_m << ". Violated constraint: > 0";
  else if (!(min_room_area_m2 >= 0)) os << "min_room_area_m2 = " << min_room_area_m2 << ". Violated constraint: >= 0";
  if (os.str().empty()) return true;
  if (error) *error = os.str();
  return false;
}

namespace {

using scenegen::ApartmentBuilder;
using scenegen::Pose;
using scenegen::RoomTypeIds;

// Room ids spread by up to `reach` pixels into the pixels of no room (4-neighbour rings, lowest id first on
// ties): the floor under walls and in door gaps belongs to a neighbouring room.
ImageU16 SpreadRooms(const ImageU16& rooms, int reach) {
  ImageU16 out = rooms;
  std::vector<int> dist(out.data.size(), -1);
  std::deque<int> queue;
  for (size_t i = 0; i < out.data.size(); ++i)
    if (out.data[i]) dist[i] = 0, queue.push_back(int(i));
  while (!queue.empty()) {
    const int i = queue.front();
    queue.pop_front();
    if (dist[size_t(i)] >= reach) continue;
    const int x = i % out.width, y = i / out.width;
    const int nb[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
    for (const auto& n : nb) {
      if (n[0] < 0 || n[1] < 0 || n[0] >= out.width || n[1] >= out.height) continue;
      const size_t j = size_t(n[1]) * size_t(out.width) + size_t(n[0]);
      if (dist[j] >= 0) continue;
      dist[j] = dist[size_t(i)] + 1;
      out.data[j] = out.data[size_t(i)];
      queue.push_back(int(j));
    }
  }
  return out;
}

struct Span {
  double a, b, bottom, top;
  bool door;
};

// The largest axis-aligned rectangle of set pixels in `mask` (histogram method, O(pixels)); area 0 when the
// mask is empty. Ties: the first found scanning rows upward, then columns.
struct PixelRect {
  int c0 = 0, r0 = 0, c1 = -1, r1 = -1;  // Inclusive.
  int64_t area() const { return c1 < c0 || r1 < r0 ? 0 : int64_t(c1 - c0 + 1) * (r1 - r0 + 1); }
};
PixelRect LargestRectangle(const std::vector<uint8_t>& mask, int w, int h) {
  PixelRect best;
  std::vector<int> height(size_t(w), 0), stack;
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) height[size_t(c)] = mask[size_t(r) * size_t(w) + size_t(c)] ? height[size_t(c)] + 1 : 0;
    stack.clear();
    for (int c = 0; c <= w; ++c) {
      const int hc = c < w ? height[size_t(c)] : 0;
      while (!stack.empty() && height[size_t(stack.back())] >= hc) {
        const int top = stack.back();
        stack.pop_back();
        const int left = stack.empty() ? 0 : stack.back() + 1;
        const int hh = height[size_t(top)];
        const int64_t area = int64_t(hh) * (c - left);
        if (area > best.area()) best = PixelRect{left, r - hh + 1, c - 1, r};
      }
      stack.push_back(c);
    }
  }
  return best;
}

// Furniture by room type (scenegen/furniture.cc) in the typed rooms, except kitchens, bathrooms and
// laundries that hold fixtures of the plan (counters, basins, toilets, baths); a living room with a cooking
// counter is furnished as an open-plan kitchen and living room. Each room is
// furnished inside the largest axis-aligned rectangle of its floor that keeps clear of every pixel of no
// room (walls, outside) by half a wall and 3 cm and of the fixtures by 0.1 m. A side of that rectangle is a
// wall (furniture may stand against it) when most of the pixels just beyond it are not the room's; door gaps
// within 0.35 m of a side become doors of that side, whose swing squares the furniture keeps clear (as in
// generated apartments). Rooms whose rectangle is under 1.2 x 1.0 m get none.
void FurnishPlanRooms(const Apartment& apt, const PlanLayout& layout, const PlanApartmentOptions& o, Rng* rng, ApartmentBuilder* b) {
  const ImageU16& raster = apt.room_raster;
  const int W = raster.width, H = raster.height;
  const double res = apt.room_raster_m;
  const Eigen::Vector2d origin = apt.room_raster_origin;
  const int max_id = int(apt.rooms.size());
  auto px_x = [&](double x) { return int(std::floor((x - origin.x()) / res)); };
  auto px_y = [&](double y) { return int(std::floor((y - origin.y()) / res)); };
  std::vector<uint8_t> blocked(size_t(W) * size_t(H), 0);  // Fixtures and 0.1 m around them.
  std::vector<bool> has_fixture(size_t(max_id) + 1, false);
  for (const PlanLayout::Fixture& f : layout.fixtures) {
    const Eigen::Vector2d lo = f.lo.cwiseMin(f.hi), hi = f.lo.cwiseMax(f.hi), c = 0.5 * (lo + hi);
    if (!lo.allFinite() || !hi.allFinite()) continue;
    if (const int id = RoomIdAt(apt, c.x(), c.y())) has_fixture[size_t(id)] = true;
    for (int r = std::max(0, px_y(lo.y() - 0.1)); r <= std::min(H - 1, px_y(hi.y() + 0.1)); ++r)
      for (int cc = std::max(0, px_x(lo.x() - 0.1)); cc <= std::min(W - 1, px_x(hi.x() + 0.1)); ++cc)
        blocked[size_t(r) * size_t(W) + size_t(cc)] = 1;
  }
  const int wall_clear = int(std::ceil((0.5 * o.wall_m + 0.03) / res));  // Pixels (chessboard) from no room.
  const RoomTypeIds& types = RoomTypeIds::Get();
  scenegen::FloorPlan plan;
  plan.ceiling = o.ceiling_m;
  plan.front_clearance_scale = 0.5;  // Real rooms are tighter than drawn ones: 0.3 m in front of a bed.
  plan.max_door_swing = 0.5;
  plan.single_bed_fallback = true;
  plan.place_defining_furniture = true;
  plan.rooms.resize(size_t(max_id));
  std::vector<uint8_t> mask(size_t(W) * size_t(H));
  for (int id = 1; id <= max_id; ++id) {
    scenegen::PlanRoom& pr = plan.rooms[size_t(id - 1)];
    const int type = apt.rooms[size_t(id - 1)].type_id;
    // Kitchens, bathrooms and laundries with fixtures of the plan are furnished by them; a living room with a
    // cooking counter is an open-plan kitchen and living room.
    const bool fixture_room = type == types.kitchen || type == types.bathroom || type == types.laundry;
    if (type <= 0 || (has_fixture[size_t(id)] && fixture_room) || apt.rooms[size_t(id - 1)].area <= 0) continue;
    pr.open_group = has_fixture[size_t(id)] ? 0 : -1;
    for (int r = 0; r < H; ++r)
      for (int c = 0; c < W; ++c) {
        bool ok = raster.at(c, r) == id && !blocked[size_t(r) * size_t(W) + size_t(c)];
        for (int dr = -wall_clear; ok && dr <= wall_clear; ++dr)
          for (int dc = -wall_clear; ok && dc <= wall_clear; ++dc) {
            const int rr = r + dr, cc = c + dc;
            ok = rr >= 0 && rr < H && cc >= 0 && cc < W && raster.at(cc, rr) == id;
          }
        mask[size_t(r) * size_t(W) + size_t(c)] = ok;
      }
    const PixelRect rect = LargestRectangle(mask, W, H);
    const double wx = (rect.c1 - rect.c0 + 1) * res, wy = (rect.r1 - rect.r0 + 1) * res;
    if (rect.area() == 0 || std::max(wx, wy) < 1.2 || std::min(wx, wy) < 1.0) continue;
    pr.type = type;
    pr.interior = scenegen::Rect{origin.x() + rect.c0 * res, origin.y() + rect.r0 * res, origin.x() + (rect.c1 + 1) * res,
                                 origin.y() + (rect.r1 + 1) * res};
    pr.cell = pr.interior;
    // A side is a wall when most pixels wall_clear + 2 beyond it are not the room's.
    auto beyond_is_wall = [&](int side) {
      int other = 0, total = 0;
      const int reach = wall_clear + 2;
      if (side == scenegen::kSouth || side == scenegen::kNorth) {
        const int r = side == scenegen::kSouth ? rect.r0 - reach : rect.r1 + reach;
        for (int c = rect.c0; c <= rect.c1; ++c, ++total) other += !(r >= 0 && r < H && raster.at(c, r) == id);
      } else {
        const int c = side == scenegen::kWest ? rect.c0 - reach : rect.c1 + reach;
        for (int r = rect.r0; r <= rect.r1; ++r, ++total) other += !(c >= 0 && c < W && raster.at(c, r) == id);
      }
      return total > 0 && 2 * other > total;
    };
    for (int side = 0; side < 4; ++side) pr.shrink[side] = beyond_is_wall(side) ? 0.5 * o.wall_m : 0.0;
    // Door gaps along a side (parallel to it, within 0.35 m of its line, overlapping its extent).
    const scenegen::Rect& in = pr.interior;
    for (const PlanLayout::Segment& d : layout.doors) {
      const Eigen::Vector2d dd = d.b - d.a;
      if (dd.norm() < 1e-3) continue;
      const bool along_x = std::fabs(dd.x()) >= std::fabs(dd.y());
      const double mid = along_x ? 0.5 * (d.a.y() + d.b.y()) : 0.5 * (d.a.x() + d.b.x());
      const double lo = along_x ? std::min(d.a.x(), d.b.x()) : std::min(d.a.y(), d.b.y());
      const double hi = along_x ? std::max(d.a.x(), d.b.x()) : std::max(d.a.y(), d.b.y());
      for (int side = 0; side < 4; ++side) {
        const bool side_along_x = side == scenegen::kSouth || side == scenegen::kNorth;
        if (side_along_x != along_x) continue;
        const double line = side == scenegen::kSouth ? in.y0 : side == scenegen::kNorth ? in.y1 : side == scenegen::kWest ? in.x0 : in.x1;
        const double s0 = side_along_x ? in.x0 : in.y0, s1 = side_along_x ? in.x1 : in.y1;
        if (std::fabs(mid - line) > 0.35 || hi <= s0 || lo >= s1) continue;
        scenegen::PlanDoor door;
        door.room_a = id - 1, door.side_a = side;
        door.a = std::max(lo, s0), door.b = std::min(hi, s1);
        plan.doors.push_back(door);
      }
    }
  }
  scenegen::FurnishApartment(plan, o.props, /*variety=*/true, rng, b);
}

}  // namespace

Result<Apartment> ApartmentFromLayout(const PlanLayout& layout, const PlanApartmentOptions& o) {
  using namespace nyu40;
  std::string error;
  if (!o.Check(&error)) return Status::InvalidInput("plan apartment options: " + error);
  if (!(layout.resolution_m > 0) || layout.rooms.data.empty())
    return Status::InvalidInput("plan layout: no room raster");
  // Rooms large enough to enter, renumbered 1..max_id in the order of their ids.
  std::vector<int64_t> pixels;
  for (uint16_t v : layout.rooms.data) {
    if (v >= pixels.size()) pixels.resize(size_t(v) + 1, 0);
    ++pixels[v];
  }
  std::vector<int> new_id(pixels.size(), 0);
  std::vector<int> kept_type(1, 0);
  int max_id = 0;
  for (size_t id = 1; id < pixels.size(); ++id)
    if (pixels[id] > 0 && double(pixels[id]) * layout.resolution_m * layout.resolution_m >= o.min_room_area_m2) {
      new_id[id] = ++max_id;
      kept_type.push_back(id < layout.room_type.size() ? layout.room_type[id] : 0);
    }
  if (max_id == 0) return Status::InvalidInput("plan layout: no closed room (every region reaches the plan's border)");
  ImageU16 room_raster = layout.rooms;
  for (uint16_t& v : room_raster.data) v = uint16_t(new_id[v]);
  for (const auto* list : {&layout.walls, &layout.doors})
    for (const PlanLayout::Segment& s : *list)
      if (!s.a.allFinite() || !s.b.allFinite()) return Status::InvalidInput("plan layout: a wall or door segment is not finite");
  const RoomTypeIds& t = RoomTypeIds::Get();
  Rng rng(SplitMix64(o.seed));
  const double H = o.ceiling_m, W = o.wall_m, res = layout.resolution_m;

  Apartment apt;
  apt.seed = o.seed;
  apt.floor_z_m = 0;
  apt.ceiling_z_m = H;
  apt.interior_wall_m = apt.exterior_wall_m = W;
  apt.room_raster = room_raster;
  apt.room_raster_m = res;
  apt.room_raster_origin = layout.origin;
  // Rooms: bounding box and pixel area of each id.
  apt.rooms.resize(size_t(max_id));
  std::vector<int> cmin(size_t(max_id) + 1, 1 << 30), cmax(size_t(max_id) + 1, -1), rmin = cmin, rmax = cmax, count(size_t(max_id) + 1, 0);
  for (int r = 0; r < room_raster.height; ++r)
    for (int c = 0; c < room_raster.width; ++c)
      if (const int id = room_raster.at(c, r)) {
        cmin[size_t(id)] = std::min(cmin[size_t(id)], c), cmax[size_t(id)] = std::max(cmax[size_t(id)], c);
        rmin[size_t(id)] = std::min(rmin[size_t(id)], r), rmax[size_t(id)] = std::max(rmax[size_t(id)], r);
        ++count[size_t(id)];
      }
  for (int id = 1; id <= max_id; ++id) {
    RoomGt& g = apt.rooms[size_t(id - 1)];
    g.id = id;
    g.type_id = kept_type[size_t(id)];
    if (count[size_t(id)] == 0) continue;  // An id the raster skips: an empty room.
    g.x0 = layout.origin.x() + cmin[size_t(id)] * res, g.x1 = layout.origin.x() + (cmax[size_t(id)] + 1) * res;
    g.y0 = layout.origin.y() + rmin[size_t(id)] * res, g.y1 = layout.origin.y() + (rmax[size_t(id)] + 1) * res;
    g.area = count[size_t(id)] * res * res;
  }
  ApartmentBuilder b(&apt, o.surface_cell_m);
  const std::vector<Rgb8> wall_colors = {{236, 232, 222}, {245, 245, 240}, {222, 226, 230}, {238, 228, 210}, {215, 225, 215}};
  const std::vector<Rgb8> floor_colors = {{164, 118, 76}, {190, 150, 105}, {140, 100, 70}, {200, 200, 195}, {120, 110, 100}};
  const Rgb8 wall_c = wall_colors[size_t(rng.UniformInt(0, int(wall_colors.size()) - 1))];
  const Rgb8 wood = floor_colors[size_t(rng.UniformInt(0, int(floor_colors.size()) - 1))], tile{205, 210, 214};
  const Rgb8 ceiling_c{248, 248, 246};
  auto wet = [&](int type) { return type == t.bathroom || type == t.laundry || type == t.kitchen; };

  // Floors and ceilings: rectangles of equal room id over the room pixels spread 3 pixels (under the walls and
  // across door gaps), merged row by row.
  const ImageU16 spread = SpreadRooms(apt.room_raster, int(std::ceil(0.15 / res)));
  std::map<std::tuple<int, int, int>, int> open;  // (c0, c1, id) -> first row of a rectangle still growing
  auto emit = [&](int c0, int c1, int id, int r0, int r1) {
    const double x0 = layout.origin.x() + c0 * res, x1 = layout.origin.x() + (c1 + 1) * res;
    const double y0 = layout.origin.y() + r0 * res, y1 = layout.origin.y() + (r1 + 1) * res;
    const int type = apt.rooms[size_t(id - 1)].type_id;
    b.AddSurface({x0, y0, 0}, Eigen::Vector3d::UnitX(), x1 - x0, Eigen::Vector3d::UnitY(), y1 - y0, wet(type) ? tile : wood,
                 FaceTags{kFloor, -1, id}, -1);
    b.AddSurface({x0, y0, H}, Eigen::Vector3d::UnitY(), y1 - y0, Eigen::Vector3d::UnitX(), x1 - x0, ceiling_c,
                 FaceTags{kCeiling, -1, id}, -1);
  };
  for (int r = 0; r <= spread.height; ++r) {
    std::map<std::tuple<int, int, int>, int> next;
    for (int c = 0; r < spread.height && c < spread.width;) {
      const int id = spread.at(c, r);
      int e = c;
      while (e + 1 < spread.width && spread.at(e + 1, r) == id) ++e;
      if (id) {
        const auto key = std::make_tuple(c, e, id);
        const auto it = open.find(key);
        next[key] = it == open.end() ? r : it->second;
        if (it != open.end()) open.erase(it);
      }
      c = e + 1;
    }
    for (const auto& [key, r0] : open) emit(std::get<0>(key), std::get<1>(key), std::get<2>(key), r0, r - 1);
    open = std::move(next);
  }

  // Walls: solid pieces around the door gaps (lintels above) and windows (sill and lintel pieces).
  const Eigen::Vector3d Z = Eigen::Vector3d::UnitZ();
  for (const PlanLayout::Segment& w : layout.walls) {
    const Eigen::Vector2d ab = w.b - w.a;
    const double L = ab.norm();
    if (L < 1e-3) continue;
    const Eigen::Vector2d d2 = ab / L, n2(-d2.y(), d2.x());
    const Eigen::Vector3d d(d2.x(), d2.y(), 0), n(n2.x(), n2.y(), 0);
    const double t_lo = -W / 2, t_hi = L + W / 2;  // Walls run on by half their thickness so that corners close.
    auto at = [&](double along, double perp) -> Eigen::Vector2d { return w.a + d2 * along + n2 * perp; };
    std::vector<Span> spans;
    for (const PlanLayout::Segment& door : layout.doors) {
      const Eigen::Vector2d dd = door.b - door.a;
      if (dd.norm() < 1e-3 || std::fabs(dd.normalized().dot(d2)) < 0.95) continue;
      if (std::fabs((door.a - w.a).dot(n2)) > std::max(W, 0.15) || std::fabs((door.b - w.a).dot(n2)) > std::max(W, 0.15)) continue;
      double s0 = (door.a - w.a).dot(d2), s1 = (door.b - w.a).dot(d2);
      if (s0 > s1) std::swap(s0, s1);
      s0 = std::max(s0, t_lo), s1 = std::min(s1, t_hi);
      if (s1 - s0 > 0.2) spans.push_back({s0, s1, 0.0, o.door_height_m, true});
    }
    std::sort(spans.begin(), spans.end(), [](const Span& x, const Span& y) { return x.a < y.a; });
    // Merge overlapping door gaps.
    std::vector<Span> doors;
    for (const Span& s : spans) {
      if (!doors.empty() && s.a <= doors.back().b) doors.back().b = std::max(doors.back().b, s.b);
      else doors.push_back(s);
    }
    // Windows: in each door-free stretch of an exterior wall (a room on one side, nothing on the other, 0.3 and
    // 1 m out) long enough, beside rooms that usually have one.
    std::vector<Span> all = doors;
    double from = t_lo;
    for (size_t k = 0; k <= doors.size(); ++k) {
      const double to = k < doors.size() ? doors[k].a : t_hi;
      const double len = to - from - 0.4;  // 0.2 m of wall either side.
      if (len >= o.min_window_wall_m) {
        const double mid = 0.5 * (from + to);
        const int ra = RoomIdAt(apt, at(mid, W / 2 + 0.3).x(), at(mid, W / 2 + 0.3).y());
        const int rb = RoomIdAt(apt, at(mid, -W / 2 - 0.3).x(), at(mid, -W / 2 - 0.3).y());
        const bool out_a = ra == 0 && RoomIdAt(apt, at(mid, W / 2 + 1).x(), at(mid, W / 2 + 1).y()) == 0;
        const bool out_b = rb == 0 && RoomIdAt(apt, at(mid, -W / 2 - 1).x(), at(mid, -W / 2 - 1).y()) == 0;
        const int room = out_a && rb ? rb : out_b && ra ? ra : 0;
        const int type = room ? apt.rooms[size_t(room - 1)].type_id : -1;
        const bool wants = room && type != t.bathroom && type != t.storage && type != t.corridor && type != t.laundry;
        if (wants && rng.Bernoulli(0.8)) {
          const double width = std::min(1.6, 0.6 * len);
          const double a = mid - width / 2, bb = mid + width / 2;
          all.push_back({a, bb, o.window_sill_m, o.window_top_m, false});
          WindowGt g;
          g.room = room;
          g.along_x = std::fabs(d2.x()) >= std::fabs(d2.y());
          g.center = at(mid, 0);
          g.width_m = width, g.sill_m = o.window_sill_m, g.top_m = o.window_top_m;
          apt.windows.push_back(g);
          const Eigen::Vector2d c = at(mid, 0);
          b.Begin(kWindow, room, Pose{c.x(), c.y(), std::atan2(d2.y(), d2.x()), 0});
          b.Box(-width / 2, -0.01, o.window_sill_m, width / 2, 0.01, o.window_top_m, Rgb8{170, 200, 225});
          b.End();
        }
      }
      if (k < doors.size()) from = doors[k].b;
    }
    std::sort(all.begin(), all.end(), [](const Span& x, const Span& y) { return x.a < y.a; });
    // The room a face looks into: sampled just off the face.
    auto room_off = [&](double along, double perp) {
      const Eigen::Vector2d p = at(along, perp);
      return RoomIdAt(apt, p.x(), p.y());
    };
    auto piece = [&](double t0, double t1, double z0, double z1) {
      if (t1 - t0 < 1e-6 || z1 - z0 < 1e-6) return;
      const Eigen::Vector2d c2 = at(0.5 * (t0 + t1), 0);
      const int part = b.AddSolid(OrientedBox{Eigen::Vector3d(c2.x(), c2.y(), 0.5 * (z0 + z1)), Eigen::Vector3d(t1 - t0, W, z1 - z0),
                                              std::atan2(d2.y(), d2.x())},
                                  kWall, -1, true);
      // The two long faces, split where the room beside them changes.
      for (int side : {1, -1}) {
        const double perp = side * W / 2;
        double s0 = t0;
        int id = room_off(t0 + 0.025, perp + side * 0.08);
        for (double s = t0 + 0.05;; s += 0.05) {
          const bool end = s >= t1 - 1e-9;
          const int here = end ? -1 : room_off(s + 0.025, perp + side * 0.08);
          if (end || here != id) {
            const double s1 = std::min(s, t1);
            const Eigen::Vector2d p = at(s0, perp);
            const FaceTags tags{kWall, -1, id > 0 ? id : -1};
            if (side > 0) b.AddSurface({p.x(), p.y(), z0}, Z, z1 - z0, d, s1 - s0, wall_c, tags, part);
            else b.AddSurface({p.x(), p.y(), z0}, d, s1 - s0, Z, z1 - z0, wall_c, tags, part);
            if (end) break;
            s0 = s1, id = here;
          }
        }
      }
      auto tag_at = [&](double along) {
        const int r = std::max(room_off(along, W / 2 + 0.08), room_off(along, -W / 2 - 0.08));
        return FaceTags{kWall, -1, r > 0 ? r : -1};
      };
      const Eigen::Vector2d e0 = at(t0, -W / 2), e1 = at(t1, -W / 2);
      b.AddSurface({e0.x(), e0.y(), z0}, Z, z1 - z0, n, W, wall_c, tag_at(t0 - 0.05), part);  // End at t0 (faces -d).
      b.AddSurface({e1.x(), e1.y(), z0}, n, W, Z, z1 - z0, wall_c, tag_at(t1 + 0.05), part);  // End at t1 (faces +d).
      if (z0 > 1e-6) b.AddSurface({e0.x(), e0.y(), z0}, n, W, d, t1 - t0, wall_c, tag_at(0.5 * (t0 + t1)), part);      // Underside.
      if (z1 < H - 1e-6) b.AddSurface({e0.x(), e0.y(), z1}, d, t1 - t0, n, W, wall_c, tag_at(0.5 * (t0 + t1)), part);  // Top.
    };
    double cur = t_lo;
    for (const Span& s : all) {
      piece(cur, s.a, 0, H);
      piece(s.a, s.b, 0, s.bottom);
      piece(s.a, s.b, s.top, H);
      cur = std::max(cur, s.b);
    }
    piece(cur, t_hi, 0, H);
  }
  // Door ground truth: the rooms on either side of the gap.
  for (const PlanLayout::Segment& door : layout.doors) {
    const Eigen::Vector2d dd = door.b - door.a;
    if (dd.norm() < 1e-3) continue;
    const Eigen::Vector2d dir = dd.normalized(), nn(-dir.y(), dir.x()), c = 0.5 * (door.a + door.b);
    DoorGt g;
    const int ra = RoomIdAt(apt, c.x() + 0.3 * nn.x(), c.y() + 0.3 * nn.y());
    const int rb = RoomIdAt(apt, c.x() - 0.3 * nn.x(), c.y() - 0.3 * nn.y());
    g.room_a = ra ? ra : rb ? rb : -1;
    g.room_b = ra && rb ? rb : -1;
    g.center = c;
    g.along_x = std::fabs(dir.x()) >= std::fabs(dir.y());
    g.width_m = dd.norm(), g.height_m = o.door_height_m, g.wall_thickness_m = W;
    apt.doors.push_back(g);
  }
  // Fixtures: boxes of the plan's footprint, at the height of their kind.
  for (const PlanLayout::Fixture& f : layout.fixtures) {
    const Eigen::Vector2d lo = f.lo.cwiseMin(f.hi), hi = f.lo.cwiseMax(f.hi), c = 0.5 * (lo + hi), size = hi - lo;
    if (!lo.allFinite() || !hi.allFinite() || size.minCoeff() < 0.1) continue;
    const double h = f.label == kToilet ? 0.75 : f.label == kBathtub ? 0.55 : f.label == kSink ? 0.85 : f.label == kCounter ? 0.9 : 0.8;
    const Rgb8 colour = f.label == kCounter ? Rgb8{200, 195, 185} : Rgb8{240, 240, 238};
    b.Begin(f.label, RoomIdAt(apt, c.x(), c.y()), Pose{c.x(), c.y(), 0, 0});
    b.Box(-size.x() / 2, -size.y() / 2, 0, size.x() / 2, size.y() / 2, h, colour, true);
    b.End();
  }
  if (o.furniture) FurnishPlanRooms(apt, layout, o, &rng, &b);
  b.Finish();
  return apt;
}

}  // namespace semvox
