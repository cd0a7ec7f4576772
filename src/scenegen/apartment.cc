#include "scenegen/apartment.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/labels.h"
#include "scenegen/apartment_builder.h"
#include "scenegen/layout.h"
#include "scenegen/random.h"

namespace semvox {

bool ApartmentOptions::Check(std::string* error) const {
  std::ostringstream os;
  if (min_rooms < 1 || min_rooms > 8) os << "min_rooms = " << min_rooms << ". Violated constraint: 1 <= min_rooms <= 8";
  else if (max_rooms < min_rooms || max_rooms > 8)
    os << "max_rooms = " << max_rooms << ". Violated constraint: min_rooms <= max_rooms <= 8";
  else if (!(min_ceiling_m >= 2.2 && max_ceiling_m >= min_ceiling_m && max_ceiling_m <= 4.0))
    os << "min_ceiling_m = " << min_ceiling_m << ", max_ceiling_m = " << max_ceiling_m
       << ". Violated constraint: 2.2 <= min_ceiling_m <= max_ceiling_m <= 4";
  else if (!(min_wall_m >= 0.05 && max_wall_m >= min_wall_m + 0.05 && max_wall_m <= 0.5))
    os << "min_wall_m = " << min_wall_m << ", max_wall_m = " << max_wall_m
       << ". Violated constraint: 0.05 <= min_wall_m, min_wall_m + 0.05 <= max_wall_m <= 0.5";
  else if (!(surface_cell_m >= 0.02 && surface_cell_m <= 5.0))
    os << "surface_cell_m = " << surface_cell_m << ". Violated constraint: 0.02 <= surface_cell_m <= 5";
  else if (!std::isfinite(floor_z_m)) os << "floor_z_m = " << floor_z_m << ". Violated constraint: finite";
  else if (max_attempts < 1) os << "max_attempts = " << max_attempts << ". Violated constraint: max_attempts >= 1";
  if (os.str().empty()) return true;
  if (error) *error = os.str();
  return false;
}

namespace scenegen {

Eigen::Vector2d Pose::ToWorld(double lx, double ly) const {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {x + c * lx - s * ly, y + s * lx + c * ly};
}

bool Overlaps(const Footprint& a, const Footprint& b) {
  if (a.z1 <= b.z0 || b.z1 <= a.z0) return false;
  // Separating-axis test of two rectangles.
  const Eigen::Vector2d axes[4] = {{std::cos(a.yaw), std::sin(a.yaw)}, {-std::sin(a.yaw), std::cos(a.yaw)},
                                   {std::cos(b.yaw), std::sin(b.yaw)}, {-std::sin(b.yaw), std::cos(b.yaw)}};
  const Eigen::Vector2d d = b.c - a.c;
  for (const Eigen::Vector2d& n : axes) {
    const double ra = a.hx * std::fabs(axes[0].dot(n)) + a.hy * std::fabs(axes[1].dot(n));
    const double rb = b.hx * std::fabs(axes[2].dot(n)) + b.hy * std::fabs(axes[3].dot(n));
    if (std::fabs(d.dot(n)) >= ra + rb) return false;
  }
  return true;
}

ApartmentBuilder::ApartmentBuilder(Apartment* apartment, double surface_cell_m)
    : apartment_(apartment), cell_(surface_cell_m) {}

void ApartmentBuilder::AddSurface(const Eigen::Vector3d& o, const Eigen::Vector3d& u, double lu,
                                  const Eigen::Vector3d& v, double lv, Rgb8 color, const FaceTags& tags, int part) {
  if (lu <= 1e-6 || lv <= 1e-6) return;
  // Even division, so no sliver cells at the edges.
  const int nu = std::max(1, int(std::ceil(lu / cell_ - 1e-9))), nv = std::max(1, int(std::ceil(lv / cell_ - 1e-9)));
  const double du = lu / nu, dv = lv / nv;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const Eigen::Vector3d p = o + (i * du) * u + (j * dv) * v;
      mesh_.AddQuad(p, p + du * u, p + du * u + dv * v, p + dv * v, color, tags);
    }
  apartment_->face_part.resize(mesh_.mesh().faces.size(), part);
}

int ApartmentBuilder::AddSolid(const OrientedBox& box, int label, int instance, bool structural) {
  SolidPart p;
  p.box = box;
  p.label = label;
  p.instance = instance;
  p.structural = structural;
  apartment_->parts.push_back(p);
  return int(apartment_->parts.size()) - 1;
}

int ApartmentBuilder::Begin(int label, int room, const Pose& pose, int support_of) {
  current_ = ObjectGt();
  current_.instance = next_instance_++;
  current_.label = label;
  current_.room = room;
  current_.support_of = support_of;
  pose_ = pose;
  support_of_ = support_of;
  local_lo_ = Eigen::Vector3d::Constant(1e9);
  local_hi_ = Eigen::Vector3d::Constant(-1e9);
  return current_.instance;
}

void ApartmentBuilder::Box(double x0, double y0, double z0, double x1, double y1, double z1, Rgb8 color,
                           bool skip_bottom) {
  local_lo_ = local_lo_.cwiseMin(Eigen::Vector3d(x0, y0, z0));
  local_hi_ = local_hi_.cwiseMax(Eigen::Vector3d(x1, y1, z1));
  const Eigen::Vector2d c = pose_.ToWorld(0.5 * (x0 + x1), 0.5 * (y0 + y1));
  const Eigen::Vector3d half(0.5 * (x1 - x0), 0.5 * (y1 - y0), 0.5 * (z1 - z0));
  const Eigen::Vector3d centre(c.x(), c.y(), pose_.z + 0.5 * (z0 + z1));
  SolidPart p;
  p.box = OrientedBox{centre, 2 * half, pose_.yaw};
  p.instance = current_.instance;
  p.label = current_.label;
  p.support_of = support_of_;
  apartment_->parts.push_back(p);
  mesh_.AddBox(centre - half, centre + half, color, FaceTags{current_.label, current_.instance, current_.room},
               pose_.yaw, skip_bottom);
  apartment_->face_part.resize(mesh_.mesh().faces.size(), int(apartment_->parts.size()) - 1);
}

Footprint ApartmentBuilder::CurrentFootprint() const {
  const Eigen::Vector3d c = 0.5 * (local_lo_ + local_hi_);
  Footprint f;
  f.c = pose_.ToWorld(c.x(), c.y());
  f.hx = 0.5 * (local_hi_.x() - local_lo_.x());
  f.hy = 0.5 * (local_hi_.y() - local_lo_.y());
  f.yaw = pose_.yaw;
  f.z0 = pose_.z + local_lo_.z();
  f.z1 = pose_.z + local_hi_.z();
  return f;
}

const ObjectGt& ApartmentBuilder::End() {
  const Eigen::Vector3d c = 0.5 * (local_lo_ + local_hi_);
  const Eigen::Vector2d w = pose_.ToWorld(c.x(), c.y());
  current_.box = OrientedBox{Eigen::Vector3d(w.x(), w.y(), pose_.z + c.z()), local_hi_ - local_lo_, pose_.yaw};
  apartment_->objects.push_back(current_);
  return apartment_->objects.back();
}

void ApartmentBuilder::Finish() {
  apartment_->mesh = mesh_.Take();
  apartment_->bounds = Aabb();
  for (const Eigen::Vector3f& p : apartment_->mesh.vertices) apartment_->bounds.Extend(p);
}

namespace {

// Unit vectors of side s: along the side's axis and the inward normal.
Eigen::Vector3d SideAxis(int s) { return (s == kSouth || s == kNorth) ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY(); }
Eigen::Vector3d Inward(int s) {
  switch (s) {
    case kSouth: return Eigen::Vector3d::UnitY();
    case kEast: return -Eigen::Vector3d::UnitX();
    case kNorth: return -Eigen::Vector3d::UnitY();
    default: return Eigen::Vector3d::UnitX();
  }
}
double SideLineOf(const Rect& r, int s) { return s == kSouth ? r.y0 : s == kEast ? r.x1 : s == kNorth ? r.y1 : r.x0; }
double AxisLo(const Rect& r, int s) { return (s == kSouth || s == kNorth) ? r.x0 : r.y0; }
double AxisHi(const Rect& r, int s) { return (s == kSouth || s == kNorth) ? r.x1 : r.y1; }
// World point at distance `along` on side s's axis, `perp` from the wall centre line into room, height z.
Eigen::Vector3d SidePoint(const Rect& cell, int s, double along, double perp, double z) {
  const Eigen::Vector3d n = Inward(s);
  Eigen::Vector3d p = (s == kSouth || s == kNorth) ? Eigen::Vector3d(along, SideLineOf(cell, s), z)
                                                   : Eigen::Vector3d(SideLineOf(cell, s), along, z);
  return p + perp * n;
}

struct Span {
  double a, b, bottom, top;
  bool door;
  int window = -1;  // Index into plan.windows.
};

Rgb8 Vary(Rgb8 c, Rng* rng, int amount) {
  auto v = [&](uint8_t x) { return uint8_t(std::clamp(int(x) + rng->UniformInt(-amount, amount), 0, 255)); };
  return Rgb8{v(c.r), v(c.g), v(c.b)};
}

// Walls, floors, ceilings, door leaves and window panes.
void BuildStructure(const FloorPlan& plan, double floor_z, Rng* rng, ApartmentBuilder* b) {
  using namespace nyu40;
  const double H = plan.ceiling;
  const std::vector<Rgb8> wall_colors = {{236, 232, 222}, {245, 245, 240}, {222, 226, 230}, {238, 228, 210}, {215, 225, 215}};
  const std::vector<Rgb8> floor_colors = {{164, 118, 76}, {190, 150, 105}, {140, 100, 70}, {200, 200, 195}, {120, 110, 100}};
  const Rgb8 ceiling_color{248, 248, 246}, tile{205, 210, 214};
  const RoomTypeIds& t = RoomTypeIds::Get();
  const Rgb8 wood_floor = Vary(rng->Pick(floor_colors), rng, 8);
  for (int i = 0; i < int(plan.rooms.size()); ++i) {
    const PlanRoom& r = plan.rooms[size_t(i)];
    const int room_id = i + 1;
    const Rgb8 wall_c = Vary(rng->Pick(wall_colors), rng, 6);
    const Rgb8 floor_c = (r.type == t.bathroom || r.type == t.laundry || r.type == t.kitchen) ? Vary(tile, rng, 10) : wood_floor;
    const Rect& in = r.interior;
    // Floor (facing up) and ceiling (facing down).
    b->AddSurface({in.x0, in.y0, floor_z}, Eigen::Vector3d::UnitX(), in.w(), Eigen::Vector3d::UnitY(), in.h(), floor_c,
                  FaceTags{kFloor, -1, room_id}, -1);
    b->AddSurface({in.x0, in.y0, floor_z + H}, Eigen::Vector3d::UnitY(), in.h(), Eigen::Vector3d::UnitX(), in.w(),
                  ceiling_color, FaceTags{kCeiling, -1, room_id}, -1);
    for (int s = 0; s < 4; ++s) {
      const double shrink = r.shrink[s];
      if (shrink <= 0) continue;  // Open side.
      const Eigen::Vector3d axis = SideAxis(s), n = Inward(s);
      // The room-facing surface faces into the room (normal +n).
      const double in_lo = AxisLo(in, s), in_hi = AxisHi(in, s);
      for (const SideSegment& seg : r.sides[s]) {
        if (seg.open) continue;
        std::vector<Span> spans;
        for (const PlanDoor& d : plan.doors) {
          const bool mine = (d.room_a == i && d.side_a == s) || (d.room_b == i && (d.side_a + 2) % 4 == s);
          if (mine && d.a >= seg.a - 1e-9 && d.b <= seg.b + 1e-9) spans.push_back({d.a, d.b, 0.0, d.height, true});
        }
        for (size_t w = 0; w < plan.windows.size(); ++w) {
          const PlanWindow& win = plan.windows[w];
          if (win.room == i && win.side == s && win.a >= seg.a - 1e-9 && win.b <= seg.b + 1e-9)
            spans.push_back({win.a, win.b, win.sill, win.top, false, int(w)});
        }
        std::sort(spans.begin(), spans.end(), [](const Span& x, const Span& y) { return x.a < y.a; });
        const double outer = seg.neighbor < 0 ? -plan.exterior_wall / 2 : 0.0;
        // Solid pieces of this half wall: [along0, along1] x [z0, z1].
        auto piece = [&](double a0, double a1, double z0, double z1) {
          if (a1 - a0 < 1e-6 || z1 - z0 < 1e-6) return;
          const Eigen::Vector3d lo = SidePoint(r.cell, s, a0, outer, floor_z + z0), hi = SidePoint(r.cell, s, a1, shrink, floor_z + z1);
          const Eigen::Vector3d c = 0.5 * (lo + hi);
          const Eigen::Vector3d size = (hi - lo).cwiseAbs();
          const int part = b->AddSolid(OrientedBox{c, size, 0.0}, kWall, -1, true);
          // Visible face, clipped to the room's clear interior along the side.
          const double f0 = std::max(a0, in_lo), f1 = std::min(a1, in_hi);
          if (f1 - f0 < 1e-6) return;
          // Orientation: u along the axis or against it so that u x z = n.
          const bool forward = axis.cross(Eigen::Vector3d::UnitZ()).dot(n) > 0;
          const Eigen::Vector3d o = SidePoint(r.cell, s, forward ? f0 : f1, shrink, floor_z + z0);
          b->AddSurface(o, forward ? axis : -axis, f1 - f0, Eigen::Vector3d::UnitZ(), z1 - z0, wall_c,
                        FaceTags{kWall, -1, room_id}, part);
        };
        double at = seg.a;
        for (const Span& sp : spans) {
          piece(at, sp.a, 0, H);
          piece(sp.a, sp.b, 0, sp.bottom);
          piece(sp.a, sp.b, sp.top, H);
          at = sp.b;
          // Reveals: jambs, sill top, lintel underside, from the wall centre line to the room face.
          const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
          const FaceTags wt{kWall, -1, room_id};
          const double depth = shrink;  // From the centre line (where leaves and panes sit) to the room face.
          // Jamb at sp.a faces +axis; jamb at sp.b faces -axis. Surface (u = n, v = z) faces n x z.
          const bool nz_pos = n.cross(z).dot(axis) > 0;
          for (int k = 0; k < 2; ++k) {
            const double along = k == 0 ? sp.a : sp.b;
            const bool want_pos = k == 0;
            const Eigen::Vector3d o0 = SidePoint(r.cell, s, along, 0, floor_z + sp.bottom);
            if (want_pos == nz_pos) b->AddSurface(o0, n, depth, z, sp.top - sp.bottom, wall_c, wt, -1);
            else b->AddSurface(o0, z, sp.top - sp.bottom, n, depth, wall_c, wt, -1);
          }
          // Lintel underside faces down, sill top faces up. Surface (u = axis, v = n) faces axis x n.
          const bool up = axis.cross(n).z() > 0;
          const Eigen::Vector3d lin = SidePoint(r.cell, s, sp.a, 0, floor_z + sp.top);
          if (up) b->AddSurface(lin, n, depth, axis, sp.b - sp.a, wall_c, wt, -1);
          else b->AddSurface(lin, axis, sp.b - sp.a, n, depth, wall_c, wt, -1);
          if (!sp.door) {
            const Eigen::Vector3d sill = SidePoint(r.cell, s, sp.a, 0, floor_z + sp.bottom);
            if (up) b->AddSurface(sill, axis, sp.b - sp.a, n, depth, wall_c, wt, -1);
            else b->AddSurface(sill, n, depth, axis, sp.b - sp.a, wall_c, wt, -1);
          } else {
            // Threshold floor under the door, this room's half.
            const Eigen::Vector3d th = SidePoint(r.cell, s, sp.a, 0, floor_z);
            if (up) b->AddSurface(th, axis, sp.b - sp.a, n, depth, floor_c, FaceTags{kFloor, -1, room_id}, -1);
            else b->AddSurface(th, n, depth, axis, sp.b - sp.a, floor_c, FaceTags{kFloor, -1, room_id}, -1);
          }
        }
        piece(at, seg.b, 0, H);
      }
    }
  }
  // Window panes (in the wall's centre line) and door leaves.
  for (const PlanWindow& w : plan.windows) {
    const PlanRoom& r = plan.rooms[size_t(w.room)];
    const double yaw = w.side * M_PI / 2;
    const Eigen::Vector3d c = SidePoint(r.cell, w.side, 0.5 * (w.a + w.b), 0, floor_z);
    Pose pose{c.x(), c.y(), yaw, floor_z};
    b->Begin(kWindow, w.room + 1, pose);
    b->Box(-(w.b - w.a) / 2, -0.01, w.sill, (w.b - w.a) / 2, 0.01, w.top, Rgb8{170, 200, 225});
    b->End();
  }
  for (const PlanDoor& d : plan.doors) {
    const PlanRoom& ra = plan.rooms[size_t(d.room_a)];
    const Rgb8 leaf = Vary(Rgb8{225, 220, 210}, rng, 20);
    const double width = d.b - d.a, thick = 0.04;
    if (d.room_b < 0) {  // Entrance: closed, in the wall's centre line.
      const Eigen::Vector3d c = SidePoint(ra.cell, d.side_a, 0.5 * (d.a + d.b), 0, floor_z);
      b->Begin(kDoor, d.room_a + 1, Pose{c.x(), c.y(), d.side_a * M_PI / 2, floor_z});
      b->Box(-width / 2, -thick / 2, 0.005, width / 2, thick / 2, d.height - 0.005, Vary(Rgb8{120, 90, 60}, rng, 20));
      b->End();
      continue;
    }
    // Interior door: open by 90 degrees into room a or b, hinged at one jamb, flat against nothing.
    const bool into_a = rng->Bernoulli(0.5);
    const int room = into_a ? d.room_a : d.room_b;
    const int side = into_a ? d.side_a : (d.side_a + 2) % 4;
    const PlanRoom& r = plan.rooms[size_t(room)];
    const double hinge = rng->Bernoulli(0.5) ? d.a + thick / 2 : d.b - thick / 2;
    const Eigen::Vector3d c = SidePoint(r.cell, side, hinge, r.shrink[side] + width / 2, floor_z);
    b->Begin(kDoor, room + 1, Pose{c.x(), c.y(), side * M_PI / 2, floor_z});
    b->Box(-thick / 2, -width / 2 + 0.005, 0.01, thick / 2, width / 2 - 0.005, d.height - 0.01, leaf);
    b->End();
  }
}

}  // namespace
}  // namespace scenegen

Result<Apartment> GenerateApartment(const ApartmentOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("apartment options: " + error);
  using namespace scenegen;
  Rng rng(SplitMix64(options.seed));
  // Rooms per flat, weighted towards the common 3-6 (weights for 1..8 rooms; restricted to the range).
  const double kRoomCountWeight[8] = {0.05, 0.09, 0.14, 0.16, 0.17, 0.15, 0.13, 0.11};
  double total = 0;
  for (int k = options.min_rooms; k <= options.max_rooms; ++k) total += kRoomCountWeight[k - 1];
  double pick = rng.Uniform(0, total);
  int num_rooms = options.max_rooms;
  for (int k = options.min_rooms; k <= options.max_rooms; ++k) {
    pick -= kRoomCountWeight[k - 1];
    if (pick < 0) {
      num_rooms = k;
      break;
    }
  }
  const double ceiling = std::round(rng.Uniform(options.min_ceiling_m, options.max_ceiling_m) * 100) / 100;
  const double interior_wall = std::round(rng.Uniform(options.min_wall_m, options.min_wall_m + 0.05) * 100) / 100;
  const double exterior_wall = std::round(rng.Uniform(options.max_wall_m - 0.05, options.max_wall_m) * 100) / 100;
  FloorPlan plan;
  bool ok = false;
  for (int attempt = 0; attempt < options.max_attempts && !ok; ++attempt)
    ok = DrawFloorPlan(num_rooms, ceiling, interior_wall, exterior_wall, &rng, &plan);
  if (!ok)
    return Status::Internal("no plausible layout with " + std::to_string(num_rooms) + " rooms in " +
                            std::to_string(options.max_attempts) + " attempts (hint: raise max_attempts)");
  Apartment apt;
  apt.seed = options.seed;
  apt.floor_z_m = options.floor_z_m;
  apt.ceiling_z_m = options.floor_z_m + ceiling;
  apt.interior_wall_m = interior_wall;
  apt.exterior_wall_m = exterior_wall;
  for (size_t i = 0; i < plan.rooms.size(); ++i) {
    const PlanRoom& r = plan.rooms[i];
    RoomGt g;
    g.id = int(i) + 1;
    g.type_id = r.type;
    g.x0 = r.interior.x0, g.y0 = r.interior.y0, g.x1 = r.interior.x1, g.y1 = r.interior.y1;
    for (int s = 0; s < 4; ++s)
      for (const SideSegment& seg : r.sides[s])
        if (seg.open && std::find(g.open_to.begin(), g.open_to.end(), seg.neighbor + 1) == g.open_to.end())
          g.open_to.push_back(seg.neighbor + 1);
    apt.rooms.push_back(g);
  }
  for (const PlanDoor& d : plan.doors) {
    const PlanRoom& r = plan.rooms[size_t(d.room_a)];
    DoorGt g;
    g.room_a = d.room_a + 1;
    g.room_b = d.room_b < 0 ? -1 : d.room_b + 1;
    g.along_x = d.side_a == kSouth || d.side_a == kNorth;
    const double line = SideLineOf(r.cell, d.side_a), mid = 0.5 * (d.a + d.b);
    g.center = g.along_x ? Eigen::Vector2d(mid, line) : Eigen::Vector2d(line, mid);
    g.width_m = d.b - d.a;
    g.height_m = d.height;
    g.wall_thickness_m = r.shrink[d.side_a] +
                         (d.room_b < 0 ? exterior_wall / 2 : plan.rooms[size_t(d.room_b)].shrink[(d.side_a + 2) % 4]);
    apt.doors.push_back(g);
  }
  for (const PlanWindow& w : plan.windows) {
    const PlanRoom& r = plan.rooms[size_t(w.room)];
    WindowGt g;
    g.room = w.room + 1;
    g.along_x = w.side == kSouth || w.side == kNorth;
    const double line = SideLineOf(r.cell, w.side), mid = 0.5 * (w.a + w.b);
    g.center = g.along_x ? Eigen::Vector2d(mid, line) : Eigen::Vector2d(line, mid);
    g.width_m = w.b - w.a;
    g.sill_m = w.sill;
    g.top_m = w.top;
    apt.windows.push_back(g);
  }
  ApartmentBuilder builder(&apt, options.surface_cell_m);
  BuildStructure(plan, options.floor_z_m, &rng, &builder);
  if (options.furniture) FurnishApartment(plan, options.props, options.shape_variety, &rng, &builder);
  builder.Finish();
  return apt;
}

int RoomIdAt(const Apartment& apt, double x, double y) {
  if (!apt.room_raster.data.empty()) {
    const int c = int(std::floor((x - apt.room_raster_origin.x()) / apt.room_raster_m));
    const int r = int(std::floor((y - apt.room_raster_origin.y()) / apt.room_raster_m));
    if (c < 0 || r < 0 || c >= apt.room_raster.width || r >= apt.room_raster.height) return 0;
    return apt.room_raster.at(c, r);
  }
  for (const RoomGt& room : apt.rooms)
    if (x >= room.x0 && x < room.x1 && y >= room.y0 && y < room.y1) return room.id;
  return 0;
}

}  // namespace semvox
