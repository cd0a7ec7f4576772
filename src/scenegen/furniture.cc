// Furniture by room type, built from boxes with real-world sizes, and small props on support surfaces.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <utility>

#include "core/hash.h"
#include "core/labels.h"
#include "scenegen/apartment_builder.h"

namespace semvox {
namespace scenegen {
namespace {

using namespace nyu40;

Rgb8 Vary(Rgb8 c, Rng* rng, int amount = 14) {
  auto v = [&](uint8_t x) { return uint8_t(std::clamp(int(x) + rng->UniformInt(-amount, amount), 0, 255)); };
  return Rgb8{v(c.r), v(c.g), v(c.b)};
}
const std::vector<Rgb8> kWood = {{164, 118, 76}, {120, 85, 55}, {190, 150, 100}, {90, 60, 40}, {210, 180, 140}, {235, 230, 220}};
const std::vector<Rgb8> kFabric = {{70, 90, 140}, {140, 60, 60}, {90, 120, 90}, {120, 120, 120}, {180, 160, 120},
                                   {60, 60, 70}, {200, 190, 170}, {150, 110, 160}};
const std::vector<Rgb8> kBright = {{220, 60, 50}, {240, 200, 60}, {60, 140, 200}, {90, 170, 90}, {240, 240, 240},
                                   {40, 40, 40}, {200, 120, 60}};
const Rgb8 kWhite{240, 240, 238}, kSteel{185, 188, 192}, kBlack{25, 25, 28};

constexpr double kGap = 0.01;       // Gap between furniture and walls, metres.
constexpr double kFlatMat = 0.01;   // Thickness of floor mats (rugs), metres.

// Furnishing one room: its clear interior, what is already there, and where props may go.
class RoomFurnisher {
 public:
  RoomFurnisher(const FloorPlan& plan, int room_index, bool variety, Rng* rng, ApartmentBuilder* b)
      : plan_(plan), r_(plan.rooms[size_t(room_index)]), room_(room_index + 1), variety_(variety), rng_(rng), b_(b) {
    H_ = plan.ceiling;
    z_ = b->apartment()->floor_z_m;
    // Door swing squares (both sides of every door) and window slabs are kept clear.
    for (const PlanDoor& d : plan.doors) {
      for (int k = 0; k < 2; ++k) {
        const int room = k == 0 ? d.room_a : d.room_b;
        if (room != room_index) continue;
        const int side = k == 0 ? d.side_a : (d.side_a + 2) % 4;
        const double w = d.b - d.a;
        keep_.push_back(WallFootprint(side, 0.5 * (d.a + d.b), w + 0.1, std::min(w, plan.max_door_swing) + 0.1, 0, H_));
        passages_.push_back(WallFootprint(side, 0.5 * (d.a + d.b), w + 0.1, kDoorPassage, 0, H_));
      }
    }
    for (const PlanWindow& w : plan.windows)
      if (w.room == room_index) {
        keep_.push_back(WallFootprint(w.side, 0.5 * (w.a + w.b), w.b - w.a + 0.1, 0.06, w.sill, w.top));
        passages_.push_back(keep_.back());
      }
  }

  int room() const { return room_; }
  // ApartmentOptions::shape_variety; `Maybe(p)` draws only when it is on, so apartments without it keep
  // their random sequence.
  bool variety() const { return variety_; }
  bool Maybe(double p) { return variety_ && rng_->Bernoulli(p); }
  double ceiling() const { return H_; }
  const Rect& in() const { return r_.interior; }
  Rng* rng() { return rng_; }
  ApartmentBuilder* b() { return b_; }
  std::vector<Support>& supports() { return supports_; }

  bool HasWall(int s) const { return r_.shrink[s] > 0; }
  double SideLength(int s) const { return (s == kSouth || s == kNorth) ? r_.interior.w() : r_.interior.h(); }
  // Pose of an object of depth d standing with its back against side s at `along` (axis coordinate).
  Pose AgainstWall(int s, double along, double depth, double off = kGap) const {
    const Rect& in = r_.interior;
    Pose p;
    p.yaw = s * M_PI / 2;
    p.z = z_;
    const double perp = off + depth / 2;
    switch (s) {
      case kSouth: p.x = along, p.y = in.y0 + perp; break;
      case kEast: p.x = in.x1 - perp, p.y = along; break;
      case kNorth: p.x = along, p.y = in.y1 - perp; break;
      default: p.x = in.x0 + perp, p.y = along; break;
    }
    return p;
  }
  Footprint WallFootprint(int s, double along, double width, double depth, double z0, double z1) const {
    return FootprintAt(AgainstWall(s, along, depth, 0.0), width, depth, z0, z1);
  }
  Footprint FootprintAt(const Pose& p, double w, double d, double z0, double z1, double dx = 0, double dy = 0) const {
    Footprint f;
    f.c = p.ToWorld(dx, dy);
    f.hx = w / 2, f.hy = d / 2, f.yaw = p.yaw;
    f.z0 = z_ + z0, f.z1 = z_ + z1;
    return f;
  }
  bool Inside(const Footprint& f) const {
    const Rect& in = r_.interior;
    const double c = std::fabs(std::cos(f.yaw)), s = std::fabs(std::sin(f.yaw));
    const double ex = f.hx * c + f.hy * s, ey = f.hx * s + f.hy * c;
    return f.c.x() - ex >= in.x0 - 1e-6 && f.c.x() + ex <= in.x1 + 1e-6 && f.c.y() - ey >= in.y0 - 1e-6 &&
           f.c.y() + ey <= in.y1 + 1e-6;
  }
  bool Free(const Footprint& f, bool check_keep_out = true) const { return FreeOf(f, check_keep_out ? &keep_ : nullptr); }
  // Free of the walls, the furniture and of `keep_out` (when given).
  bool FreeOf(const Footprint& f, const std::vector<Footprint>* keep_out) const {
    if (!Inside(f)) return false;
    for (const Footprint& o : taken_)
      if (Overlaps(f, o)) return false;
    if (keep_out)
      for (const Footprint& o : *keep_out)
        if (Overlaps(f, o)) return false;
    return true;
  }
  void Take(const Footprint& f) { taken_.push_back(f); }

  // `sides`, or when empty every side with a wall (not the open side of an open-plan space).
  std::vector<int> SidesOrWalls(std::vector<int> sides) const {
    if (sides.empty())
      for (int s = 0; s < 4; ++s)
        if (HasWall(s)) sides.push_back(s);
    return sides;
  }
  // The interior's extent along side s (x for south and north, y for east and west).
  std::pair<double, double> SideExtent(int s) const {
    const Rect& in = r_.interior;
    return (s == kSouth || s == kNorth) ? std::pair<double, double>(in.x0, in.x1) : std::pair<double, double>(in.y0, in.y1);
  }
  // The walkway `front` metres deep in front of an object w x d at pose p, up to knee height.
  Footprint FrontFootprint(const Pose& p, double w, double d, double front) const {
    return FootprintAt(p, w, front, 0, 0.5, 0, d / 2 + front / 2 + 1e-3);
  }
  // Finds a spot against one of `sides` for an object w x d x h (plus `front` metres kept free in front of
  // it, up to knee height), optionally at `mount_z` above the floor. False when nothing fits.
  // An empty `sides` means every side with a wall (not the open side of an open-plan space).
  bool PlaceAgainstWall(double w, double d, double h, std::vector<int> sides, double front, Pose* out,
                        double mount_z = 0.0, int attempts = 40) {
    front *= plan_.front_clearance_scale;
    sides = SidesOrWalls(std::move(sides));
    if (sides.empty()) return false;
    for (int k = 0; k < attempts; ++k) {
      const int s = rng_->Pick(sides);
      const auto [lo, hi] = SideExtent(s);
      if (hi - lo < w + 2 * kGap) continue;
      // Corners are popular: a third of the draws go flush to one end.
      double along;
      const double u = rng_->Uniform01();
      if (u < 0.17) along = lo + kGap + w / 2;
      else if (u < 0.34) along = hi - kGap - w / 2;
      else along = rng_->Uniform(lo + kGap + w / 2, hi - kGap - w / 2);
      const Pose p = AgainstWall(s, along, d);
      const Footprint f = FootprintAt(p, w, d, mount_z, mount_z + h);
      if (!Free(f)) continue;
      if (front > 0 && !Free(FrontFootprint(p, w, d, front))) continue;
      *out = p;
      return true;
    }
    return false;
  }
  // PlaceAgainstWall for a room's defining furniture: when the random draws find nothing and the plan asks for
  // it (FloorPlan::place_defining_furniture), every spot along the walls in 5 cm steps, first with the walkway
  // in front, then without it, then with only the doors' passages kept clear, then standing in as few door
  // passages as possible; one of the spots of the first pass that finds any is drawn.
  bool PlaceDefining(double w, double d, double h, std::vector<int> sides, double front, Pose* out) {
    if (PlaceAgainstWall(w, d, h, sides, front, out)) return true;
    if (!plan_.place_defining_furniture) return false;
    front *= plan_.front_clearance_scale;
    sides = SidesOrWalls(std::move(sides));
    struct Pass {
      double front;
      const std::vector<Footprint>* keep_out;
    };
    // The last pass keeps nothing clear but counts the door passages a spot stands in, and keeps the spots that
    // block the fewest (a room with a door on every wall: a bed before a closet's sliding door).
    const Pass passes[] = {{front, &keep_}, {0.0, &keep_}, {0.0, &passages_}, {0.0, nullptr}};
    for (const Pass& pass : passes) {
      std::vector<Pose> spots;
      size_t fewest = SIZE_MAX;
      for (const int s : sides) {
        const auto [lo, hi] = SideExtent(s);
        for (double along = lo + kGap + w / 2; along <= hi - kGap - w / 2 + 1e-9; along += kScanStep) {
          const Pose p = AgainstWall(s, along, d);
          const Footprint f = FootprintAt(p, w, d, 0, h);
          if (!FreeOf(f, pass.keep_out)) continue;
          if (pass.front > 0 && !FreeOf(FrontFootprint(p, w, d, pass.front), pass.keep_out)) continue;
          const size_t blocked = pass.keep_out ? 0 : size_t(std::count_if(passages_.begin(), passages_.end(), [&](const Footprint& o) { return Overlaps(f, o); }));
          if (blocked > fewest) continue;
          if (blocked < fewest) spots.clear(), fewest = blocked;
          spots.push_back(p);
        }
      }
      if (!spots.empty()) {
        *out = spots[size_t(rng_->UniformInt(0, int(spots.size()) - 1))];
        return true;
      }
    }
    return false;
  }
  // Finds a free spot anywhere for a w x d footprint with `clear` metres around it.
  bool PlaceFree(double w, double d, double h, double clear, bool any_yaw, Pose* out, int attempts = 40) {
    const Rect& in = r_.interior;
    for (int k = 0; k < attempts; ++k) {
      Pose p;
      p.z = z_;
      p.yaw = any_yaw ? rng_->Uniform(0, 2 * M_PI) : rng_->UniformInt(0, 3) * M_PI / 2;
      p.x = rng_->Uniform(in.x0, in.x1);
      p.y = rng_->Uniform(in.y0, in.y1);
      if (!Free(FootprintAt(p, w + 2 * clear, d + 2 * clear, 0, h))) continue;
      *out = p;
      return true;
    }
    return false;
  }

  void AddSupport(const Pose& p, double lx, double ly, double hx, double hy, double top, double max_h, int instance) {
    Support s;
    s.pose = p;
    const Eigen::Vector2d c = p.ToWorld(lx, ly);
    s.pose.x = c.x(), s.pose.y = c.y(), s.pose.z = z_ + top;
    s.hx = hx, s.hy = hy, s.max_height = max_h, s.instance = instance;
    supports_.push_back(s);
  }

  const FloorPlan& plan() const { return plan_; }
  const PlanRoom& plan_room() const { return r_; }

 private:
  const FloorPlan& plan_;
  const PlanRoom& r_;
  int room_;
  bool variety_ = false;
  Rng* rng_;
  ApartmentBuilder* b_;
  double H_ = 2.6, z_ = 0;
  static constexpr double kDoorPassage = 0.3;  // Metres kept clear in front of a door when placing defining furniture.
  static constexpr double kScanStep = 0.05;    // Step along a wall when looking for a spot for defining furniture.
  // taken_: placed furniture; keep_: doors' swing squares and window slabs; passages_: doors' passages (shallow)
  // and window slabs.
  std::vector<Footprint> taken_, keep_, passages_;
  std::vector<Support> supports_;
};

// ---------------------------------------------------------------------------------------------------
// Composed objects. Each builds in the object frame (front +y, back against the wall at -d/2), records the
// object and its footprint and returns its instance, or -1 when it did not fit.

int Finish(RoomFurnisher* f) {
  const Footprint fp = f->b()->CurrentFootprint();
  f->Take(fp);
  return f->b()->End().instance;
}

int Bed(RoomFurnisher* f, bool dbl) {
  Rng* r = f->rng();
  const double w = dbl ? r->Uniform(1.4, 1.8) : r->Uniform(0.9, 1.0), d = r->Uniform(1.95, 2.1);
  const double top = r->Uniform(0.45, 0.6), head = top + r->Uniform(0.35, 0.6);
  Pose p;
  if (!f->PlaceDefining(w, d, head, {}, 0.6, &p)) return -1;
  ApartmentBuilder* b = f->b();
  const int id = b->Begin(kBed, f->room(), p);
  const Rgb8 frame = Vary(r->Pick(kWood), r), sheet = Vary(r->Pick(kFabric), r, 25);
  b->Box(-w / 2, -d / 2 + 0.06, 0, w / 2, d / 2, 0.3, frame, true);
  b->Box(-w / 2 + 0.02, -d / 2 + 0.07, 0.3, w / 2 - 0.02, d / 2 - 0.02, top, sheet);
  b->Box(-w / 2, -d / 2, 0, w / 2, -d / 2 + 0.06, head, frame, true);
  Finish(f);
  // Pillows at the head.
  const int n = dbl ? 2 : 1;
  for (int i = 0; i < n; ++i) {
    const double pw = std::min(0.6, w / n - 0.1), cx = -w / 2 + (i + 0.5) * w / n;
    b->Begin(kPillow, f->room(), p, id);
    b->Box(cx - pw / 2, -d / 2 + 0.12, top, cx + pw / 2, -d / 2 + 0.5, top + r->Uniform(0.1, 0.15), Vary(kWhite, r, 15));
    b->End();
  }
  f->AddSupport(p, 0, 0.3, w / 2 - 0.1, d / 2 - 0.55, top, 0.3, id);
  // Night stands beside the head, a lamp on some.
  for (int side : {-1, 1}) {
    if (!dbl && side > 0) break;
    const double nw = r->Uniform(0.4, 0.55), nd = r->Uniform(0.35, 0.45), nh = r->Uniform(0.45, 0.6);
    Pose np = p;
    const Eigen::Vector2d c = p.ToWorld(side * (w / 2 + nw / 2 + 0.04), -d / 2 + nd / 2);
    np.x = c.x(), np.y = c.y();
    if (!f->Free(f->FootprintAt(np, nw, nd, 0, nh))) continue;
    const int ns = b->Begin(kNightStand, f->room(), np);
    b->Box(-nw / 2, -nd / 2, 0, nw / 2, nd / 2, nh, Vary(r->Pick(kWood), r), true);
    Finish(f);
    if (r->Bernoulli(0.7)) {
      b->Begin(kLamp, f->room(), Pose{np.x, np.y, np.yaw, np.z + nh}, ns);
      b->Box(-0.06, -0.06, 0, 0.06, 0.06, 0.25, Vary(kSteel, r));
      b->Box(-0.14, -0.14, 0.25, 0.14, 0.14, 0.45, Vary(Rgb8{240, 225, 170}, r));
      b->End();
    } else {
      f->AddSupport(np, 0, 0, nw / 2 - 0.04, nd / 2 - 0.04, nh, 0.35, ns);
    }
  }
  return id;
}

int Wardrobe(RoomFurnisher* f) {
  Rng* r = f->rng();
  const double w = r->Uniform(0.9, 2.0), d = r->Uniform(0.55, 0.62), h = std::min(f->ceiling() - 0.1, r->Uniform(1.9, 2.2));
  Pose p;
  if (!f->PlaceAgainstWall(w, d, h, {}, 0.6, &p)) return -1;
  f->b()->Begin(kOtherFurniture, f->room(), p);
  const Rgb8 c = Vary(r->Pick(kWood), r);
  f->b()->Box(-w / 2, -d / 2, 0, w / 2, d / 2 - 0.02, h, c, true);
  f->b()->Box(-w / 2 + 0.02, d / 2 - 0.02, 0.05, w / 2 - 0.02, d / 2, h - 0.02, Vary(c, r, 8));  // Doors.
  return Finish(f);
}

int Dresser(RoomFurnisher* f) {
  Rng* r = f->rng();
  const double w = r->Uniform(0.8, 1.4), d = r->Uniform(0.42, 0.52), h = r->Uniform(0.75, 1.0);
  Pose p;
  if (!f->PlaceAgainstWall(w, d, h, {}, 0.5, &p)) return -1;
  const int id = f->b()->Begin(kDresser, f->room(), p);
  const Rgb8 c = Vary(r->Pick(kWood), r);
  f->b()->Box(-w / 2, -d / 2, 0, w / 2, d / 2, h, c, true);
  Finish(f);
  f->AddSupport(p, 0, 0, w / 2 - 0.04, d / 2 - 0.04, h, 0.4, id);
  return id;
}

// Open shelves (label shelves) or a bookshelf with a back and sides (label bookshelf); every board is a
// support for books and boxes.
int ShelfUnit(RoomFurnisher* f, int label, double min_h = 1.2) {
  Rng* r = f->rng();
  const double w = r->Uniform(0.7, 1.2), d = r->Uniform(0.3, 0.4);
  const double h = std::min(f->ceiling() - 0.2, r->Uniform(std::max(min_h, 1.0), 2.0));
  Pose p;
  if (!f->PlaceAgainstWall(w, d, h, {}, 0.4, &p)) return -1;
  ApartmentBuilder* b = f->b();
  const int id = b->Begin(label, f->room(), p);
  const Rgb8 c = Vary(r->Pick(kWood), r);
  const double t = 0.02;
  b->Box(-w / 2, -d / 2, 0, -w / 2 + t, d / 2, h, c, true);
  b->Box(w / 2 - t, -d / 2, 0, w / 2, d / 2, h, c, true);
  if (label == kBookshelf) b->Box(-w / 2 + t, -d / 2, 0, w / 2 - t, -d / 2 + t, h, c, true);
  const int boards = std::max(2, int(h / 0.38));
  const double step = (h - t) / boards;
  for (int i = 0; i <= boards; ++i) {
    const double z = i * step;
    b->Box(-w / 2 + t, -d / 2 + (label == kBookshelf ? t : 0), z, w / 2 - t, d / 2, z + t, c);
    if (i < boards) f->AddSupport(p, 0, t / 2, w / 2 - t - 0.01, d / 2 - t - 0.01, z + t, step - t - 0.03, id);
  }
  return Finish(f);
}

int Table(RoomFurnisher* f, const Pose& p, double w, double d, double h, int label, Rgb8 c) {
  ApartmentBuilder* b = f->b();
  const int id = b->Begin(label, f->room(), p);
  const double top = 0.035, leg = 0.05;
  b->Box(-w / 2, -d / 2, h - top, w / 2, d / 2, h, c);
  for (int i = 0; i < 4; ++i) {
    const double lx = (i & 1 ? 1 : -1) * (w / 2 - leg), ly = (i & 2 ? 1 : -1) * (d / 2 - leg);
    b->Box(lx - leg / 2, ly - leg / 2, 0, lx + leg / 2, ly + leg / 2, h - top, c, true);
  }
  Finish(f);
  f->AddSupport(p, 0, 0, w / 2 - 0.05, d / 2 - 0.05, h, 0.4, id);
  return id;
}

// A chair facing local +y (seat front) at pose p; false when it does not fit.
bool Chair(RoomFurnisher* f, const Pose& p, Rgb8 c) {
  const double w = 0.44, d = 0.46, seat = 0.45, back = 0.9;
  if (!f->Free(f->FootprintAt(p, w, d, 0, back))) return false;
  ApartmentBuilder* b = f->b();
  b->Begin(kChair, f->room(), p);
  const double leg = 0.035;
  b->Box(-w / 2, -d / 2, seat - 0.04, w / 2, d / 2, seat, c);
  for (int i = 0; i < 4; ++i) {
    const double lx = (i & 1 ? 1 : -1) * (w / 2 - leg), ly = (i & 2 ? 1 : -1) * (d / 2 - leg);
    b->Box(lx - leg / 2, ly - leg / 2, 0, lx + leg / 2, ly + leg / 2, seat - 0.04, c, true);
  }
  b->Box(-w / 2, -d / 2, seat, w / 2, -d / 2 + 0.04, back, c);
  Finish(f);
  return true;
}

// A table standing free with chairs on its long sides (and ends when there is room).
void TableWithChairs(RoomFurnisher* f, double wmin, double wmax, double dmin, double dmax, int max_chairs) {
  Rng* r = f->rng();
  const double w = r->Uniform(wmin, wmax), d = r->Uniform(dmin, dmax), h = r->Uniform(0.72, 0.77);
  Pose p;
  if (!f->PlaceFree(w, d, h, 0.55, false, &p)) return;
  const Rgb8 c = Vary(r->Pick(kWood), r);
  Table(f, p, w, d, h, kTable, c);
  const Rgb8 cc = Vary(r->Pick(kWood), r);
  const double off = 0.05 + 0.46 / 2;
  std::vector<Pose> seats;
  const int per_side = std::max(1, int((w + 0.1) / 0.6));
  for (int side : {-1, 1})
    for (int i = 0; i < per_side; ++i) {
      Pose s = p;
      const Eigen::Vector2d c2 = p.ToWorld(-w / 2 + (i + 0.5) * w / per_side, side * (d / 2 + off));
      s.x = c2.x(), s.y = c2.y();
      s.yaw = p.yaw + (side > 0 ? M_PI : 0.0);
      seats.push_back(s);
    }
  for (int side : {-1, 1}) {
    Pose s = p;
    const Eigen::Vector2d c2 = p.ToWorld(side * (w / 2 + off), 0);
    s.x = c2.x(), s.y = c2.y();
    s.yaw = p.yaw + (side > 0 ? M_PI / 2 : -M_PI / 2);
    seats.push_back(s);
  }
  int placed = 0;
  for (const Pose& s : seats)
    if (placed < max_chairs && r->Bernoulli(0.85) && Chair(f, s, cc)) ++placed;
}

int Sofa(RoomFurnisher* f, Pose* pose, double* depth) {
  Rng* r = f->rng();
  const double w = r->Uniform(1.6, 2.4), d = r->Uniform(0.85, 0.95), seat = 0.43, back = r->Uniform(0.78, 0.9);
  // Shape variety: a corner sofa (a chaise of the same seat height along one end, reaching forward) and
  // seat cushions with gaps between them.
  const bool corner = f->Maybe(0.45);
  const double wide = corner ? w + r->Uniform(0.0, 0.8) : w;
  const double chaise = corner ? r->Uniform(0.6, 1.6) : 0.0, chaise_w = corner ? r->Uniform(0.75, 1.0) : 0.0;
  const int chaise_side = corner && r->Bernoulli(0.5) ? 1 : -1;
  const bool cushions = f->Maybe(0.6);
  const double D = d + chaise;
  Pose p;
  std::vector<int> sides = {0, 1, 2, 3};
  if (!f->PlaceDefining(wide, D, back, sides, 1.0, &p)) return -1;
  ApartmentBuilder* b = f->b();
  const int id = b->Begin(kSofa, f->room(), p);
  const Rgb8 c = Vary(r->Pick(kFabric), r, 20);
  // Shape variety: upholstered sofas with wide, high arms and a deep back and back cushions (a real scan sees
  // their tops as a broad band at 0.65-0.8 m around the seat), and sectionals: a corner sofa whose back runs
  // on along the chaise's outer side instead of an arm (an L of backs around an L-shaped seat). Drawn from a
  // generator of their own, seeded by the sofa's size, so that the rest of the apartment is the same as
  // without them.
  double arm = 0.15, arm_h = 0.6, back_d = 0.2, cushion_d = 0.14, cushion_top = back - 0.05;
  bool sectional = false;  // A corner sofa whose chaise has a back along its outer side: an L of backs.
  if (f->variety()) {
    uint64_t h = 0x9e3779b97f4a7c15ull;
    for (double v : {w, d, back}) h = (h ^ std::hash<double>{}(v)) * 0x100000001b3ull;
    Rng u(h);
    if (u.Bernoulli(0.6)) {
      arm = u.Uniform(0.15, 0.35), arm_h = u.Uniform(0.55, 0.72);
      back_d = u.Uniform(0.2, 0.3), cushion_d = u.Uniform(0.18, 0.35), cushion_top = back - u.Uniform(0.05, 0.15);
    }
    sectional = corner && u.Bernoulli(0.6);
  }
  const double y0 = -D / 2, hw = wide / 2;
  const double base = cushions ? seat - 0.12 : seat;
  // A sectional's chaise side has its back, not an arm (below); left / right: how far the seat starts inside.
  const bool back_left = sectional && chaise_side < 0, back_right = sectional && chaise_side > 0;
  const double left = back_left ? back_d : arm, right = back_right ? back_d : arm;
  b->Box(-hw + left, y0 + back_d, 0, hw - right, y0 + d, base, c, true);
  b->Box(-hw, y0, 0, hw, y0 + back_d, back, c, true);
  if (!back_left) b->Box(-hw, y0 + back_d, 0, -hw + arm, y0 + d, arm_h, c, true);
  if (!back_right) b->Box(hw - arm, y0 + back_d, 0, hw, y0 + d, arm_h, c, true);
  if (corner) {  // The chaise: seat and an arm along its outer side (a sectional's: its back), no back of its own.
    const double x0 = chaise_side > 0 ? hw - chaise_w : -hw, x1 = chaise_side > 0 ? hw : -hw + chaise_w;
    const double ax0 = chaise_side > 0 ? x1 - arm : x0, ax1 = chaise_side > 0 ? x1 : x0 + arm;
    b->Box(x0, y0 + d, 0, x1, D / 2, base, c, true);
    if (sectional) {  // The outer side's back runs on along the chaise, as deep as the main back.
      const double bx0 = chaise_side > 0 ? hw - back_d : -hw, bx1 = chaise_side > 0 ? hw : -hw + back_d;
      b->Box(bx0, y0 + back_d, 0, bx1, D / 2, back, c, true);
    } else {
      b->Box(ax0, y0 + d, 0, ax1, D / 2, arm_h, c, true);
    }
  }
  if (cushions) {  // Seat cushions, 2-4 of them, with 2 cm gaps, slightly lighter or darker.
    const Rgb8 cc = Vary(c, r, 12);
    const int n = r->UniformInt(2, 4);
    const double x0 = -hw + left, step = (wide - left - right) / n;
    for (int i = 0; i < n; ++i) b->Box(x0 + i * step + 0.01, y0 + back_d + 0.02, base, x0 + (i + 1) * step - 0.01, y0 + d, seat, cc);
    if (corner) {
      const double cx0 = chaise_side > 0 ? hw - chaise_w : -hw + left, cx1 = chaise_side > 0 ? hw - right : -hw + chaise_w;
      b->Box(cx0 + 0.01, y0 + d + 0.01, base, cx1 - 0.01, D / 2, seat, cc);
      if (sectional) {  // Back cushions leaning on the chaise's back.
        const double kx0 = chaise_side > 0 ? hw - back_d - cushion_d : -hw + back_d, kx1 = chaise_side > 0 ? hw - back_d : -hw + back_d + cushion_d;
        b->Box(kx0, y0 + d + 0.02, seat, kx1, D / 2 - 0.02, cushion_top, cc);
      }
    }
    for (int i = 0; i < n; ++i)  // Back cushions leaning on the back.
      b->Box(x0 + i * step + 0.02, y0 + back_d, seat, x0 + (i + 1) * step - 0.02, y0 + back_d + cushion_d, cushion_top, cc);
  }
  Finish(f);
  for (int i = 0, n = r->UniformInt(0, 2); i < n; ++i) {
    const double cx = (i == 0 ? -1 : 1) * (hw - (i == 0 ? left : right) - 0.3);
    b->Begin(kPillow, f->room(), p, id);
    const double py = y0 + back_d + (cushions ? cushion_d + 0.01 : 0.0);  // In front of the back cushions.
    b->Box(cx - 0.22, py, seat, cx + 0.22, py + 0.15, seat + 0.4, Vary(r->Pick(kBright), r));
    b->End();
  }
  *pose = p;
  *depth = D;
  return id;
}

// Shape variety: a bar table (high and narrow, on legs or on a solid panel), against a wall or free in the
// room, with a stool or two (chairs without backs).
void BarTable(RoomFurnisher* f) {
  Rng* r = f->rng();
  const double w = r->Uniform(1.0, 2.6), d = r->Uniform(0.4, 0.65), h = r->Uniform(0.9, 1.15);
  Pose p;
  const bool free_standing = r->Bernoulli(0.5);
  if (free_standing ? !f->PlaceFree(w, d, h, 0.5, false, &p) : !f->PlaceAgainstWall(w, d, h, {}, 0.8, &p)) return;
  const Rgb8 c = Vary(r->Pick(kWood), r);
  if (r->Bernoulli(0.5)) {
    Table(f, p, w, d, h, kTable, c);
  } else {
    ApartmentBuilder* b = f->b();
    const int id = b->Begin(kTable, f->room(), p);
    b->Box(-w / 2, -d / 2, h - 0.04, w / 2, d / 2, h, c);
    b->Box(-w / 2 + 0.1, -0.04, 0, w / 2 - 0.1, 0.04, h - 0.04, Vary(c, r, 20), true);  // Panel.
    Finish(f);
    f->AddSupport(p, 0, 0, w / 2 - 0.05, d / 2 - 0.05, h, 0.4, id);
  }
  const Rgb8 sc = Vary(r->Pick(kWood), r);
  for (int i = 0, n = r->UniformInt(0, 2); i < n; ++i) {
    Pose s = p;
    const Eigen::Vector2d c2 = p.ToWorld((i == 0 ? -0.25 : 0.25) * w, d / 2 + 0.3);
    s.x = c2.x(), s.y = c2.y();
    const double sw = 0.36, sh = h - r->Uniform(0.28, 0.35);
    if (!f->Free(f->FootprintAt(s, sw, sw, 0, sh))) continue;
    f->b()->Begin(kChair, f->room(), s);
    f->b()->Box(-sw / 2, -sw / 2, sh - 0.05, sw / 2, sw / 2, sh, sc);
    f->b()->Box(-0.03, -0.03, 0, 0.03, 0.03, sh - 0.05, Vary(kSteel, r), true);
    f->b()->Box(-0.17, -0.17, 0, 0.17, 0.17, 0.02, Vary(kSteel, r), true);
    Finish(f);
  }
}

// Shape variety: a waste bin (ScanNet: garbage bin -> otherfurniture) against a wall.
void Bin(RoomFurnisher* f) {
  Rng* r = f->rng();
  const double w = r->Uniform(0.22, 0.45), d = r->Uniform(0.22, 0.45), h = r->Uniform(0.27, 0.7);
  Pose p;
  if (!f->PlaceAgainstWall(w, d, h, {}, 0.2, &p, 0.0, 15)) return;
  f->b()->Begin(kOtherFurniture, f->room(), p);
  const Rgb8 c = r->Bernoulli(0.5) ? Vary(r->Pick(kBright), r, 30) : Vary(r->Bernoulli(0.5) ? kSteel : kBlack, r, 20);
  f->b()->Box(-w / 2, -d / 2, 0, w / 2, d / 2, h, c, true);
  Finish(f);
}

// Something hung on a wall at [z0, z1] above the floor: picture, mirror, towel, clothes on a hook.
bool WallItem(RoomFurnisher* f, int label, double w, double h, double z0, double thick, Rgb8 c, std::vector<int> sides = {}) {
  Pose p;
  if (!f->PlaceAgainstWall(w, thick, h, sides, 0, &p, z0, 30)) return false;
  // Flush with the wall surface (no gap behind a hung item).
  const Eigen::Vector2d back = p.ToWorld(0, -kGap);
  p.x = back.x(), p.y = back.y();
  f->b()->Begin(label, f->room(), p);
  f->b()->Box(-w / 2, -thick / 2, z0, w / 2, thick / 2, z0 + h, c);
  Finish(f);
  return true;
}

void Pictures(RoomFurnisher* f, int n) {
  Rng* r = f->rng();
  for (int i = 0; i < n; ++i) {
    const double w = r->Uniform(0.3, 1.0), h = r->Uniform(0.3, 0.7);
    WallItem(f, kPicture, w, h, r->Uniform(1.2, std::min(1.7, f->ceiling() - 0.3 - h)), 0.025, Vary(r->Pick(kBright), r, 40));
  }
}

// Curtains (label curtain) either side of the room's windows, or blinds over them.
void WindowDressing(RoomFurnisher* f, bool curtains) {
  Rng* r = f->rng();
  const FloorPlan& plan = f->plan();
  const Rgb8 c = Vary(r->Pick(kFabric), r, 25);
  for (const PlanWindow& w : plan.windows) {
    if (w.room + 1 != f->room()) continue;
    const double mid = 0.5 * (w.a + w.b), width = w.b - w.a;
    if (!curtains) {
      const Pose p = f->AgainstWall(w.side, mid, 0.03, 0.0);
      f->b()->Begin(kBlinds, f->room(), p);
      f->b()->Box(-width / 2, -0.015, w.top - r->Uniform(0.3, 0.8), width / 2, 0.015, w.top, Vary(kWhite, r, 20));
      Finish(f);
      continue;
    }
    const double pw = r->Uniform(0.25, 0.45), top = std::min(f->ceiling() - 0.05, w.top + 0.15), bottom = 0.02;
    for (int side : {-1, 1}) {
      const double along = mid + side * (width / 2 + pw / 2 - 0.1);
      const Pose p = f->AgainstWall(w.side, along, 0.05, 0.06);
      const Footprint fp = f->FootprintAt(p, pw, 0.05, bottom, top);
      if (!f->Free(fp, false)) continue;
      f->b()->Begin(kCurtain, f->room(), p);
      f->b()->Box(-pw / 2, -0.025, bottom, pw / 2, 0.025, top, c);
      Finish(f);
    }
  }
}

void FloorMat(RoomFurnisher* f, double w, double d, const Pose& p) {
  // Rugs lie flat under other furniture, so they are not obstacles; they stay inside the room.
  if (!f->Inside(f->FootprintAt(p, w, d, 0, kFlatMat))) return;
  f->b()->Begin(kFloorMat, f->room(), p);
  f->b()->Box(-w / 2, -d / 2, 0, w / 2, d / 2, kFlatMat, Vary(f->rng()->Pick(kFabric), f->rng(), 30), true);
  f->b()->End();
}

void Counters(RoomFurnisher* f, bool full_kitchen) {
  Rng* r = f->rng();
  ApartmentBuilder* b = f->b();
  const double d = 0.62, h = 0.9;
  const Rgb8 body = Vary(r->Pick(kWood), r), top_c = Vary(r->Pick(std::vector<Rgb8>{{60, 60, 62}, {220, 220, 215}, {150, 130, 110}}), r);
  int runs = full_kitchen && r->Bernoulli(0.6) ? 2 : 1;
  bool sink_done = false, stove_done = false;
  for (int run = 0; run < runs; ++run) {
    Pose p;
    double L = 0;
    bool ok = false;
    for (int k = 0; k < 12 && !ok; ++k) {
      const int s = r->UniformInt(0, 3);
      if (!f->HasWall(s)) continue;
      const double avail = f->SideLength(s) - 2 * kGap;
      if (avail < 1.2) continue;
      L = std::min(avail, full_kitchen ? r->Uniform(1.8, 3.6) : r->Uniform(1.2, 2.0));
      ok = f->PlaceAgainstWall(L, d, h, {s}, 0.8, &p, 0.0, 6);
    }
    if (!ok) continue;
    const int id = b->Begin(kCounter, f->room(), p);
    b->Box(-L / 2, -d / 2, 0.1, L / 2, d / 2 - 0.03, h - 0.04, body, true);
    b->Box(-L / 2, -d / 2, 0, L / 2, d / 2 - 0.08, 0.1, Vary(body, r, 10), true);  // Plinth.
    b->Box(-L / 2, -d / 2, h - 0.04, L / 2, d / 2, h, top_c);
    Finish(f);
    // Sink and stove on the top, the rest is a support.
    double free_lo = -L / 2 + 0.05;
    if (!sink_done && L >= 1.2) {
      const double sx = -L / 2 + r->Uniform(0.35, std::max(0.36, L / 2 - 0.35));
      b->Begin(kSink, f->room(), p, id);
      b->Box(sx - 0.25, -0.2, h, sx + 0.25, 0.2, h + 0.03, Vary(kSteel, r));
      b->Box(sx - 0.02, -0.28, h, sx + 0.02, -0.22, h + 0.3, Vary(kSteel, r));  // Tap.
      b->End();
      sink_done = true;
      free_lo = sx + 0.3;
    }
    if (!stove_done && L - (free_lo + L / 2) >= 0.65) {
      const double sx = free_lo + 0.31;
      b->Begin(kOtherStructure, f->room(), p, id);  // Stove / hob (ScanNet: stove -> otherstructure).
      b->Box(sx - 0.29, -0.26, h, sx + 0.29, 0.26, h + 0.02, kBlack);
      b->End();
      stove_done = true;
      free_lo = sx + 0.32;
    }
    if (L / 2 - free_lo > 0.3) f->AddSupport(p, 0.5 * (free_lo + L / 2), 0.02, 0.5 * (L / 2 - free_lo) - 0.03, d / 2 - 0.08, h, 0.45, id);
    // Wall cabinets above the run, where no window is.
    const double cz0 = 1.45, cz1 = std::min(f->ceiling() - 0.05, 2.2);
    if (full_kitchen && cz1 - cz0 > 0.4) {
      Pose up = f->AgainstWall(int(std::lround(p.yaw / (M_PI / 2))) % 4, 0, 0.35);
      const Eigen::Vector2d back = p.ToWorld(0, -d / 2 + 0.35 / 2 + 0.0);
      up.x = back.x(), up.y = back.y(), up.yaw = p.yaw;
      const Footprint fp = f->FootprintAt(up, L, 0.35, cz0, cz1);
      if (f->Free(fp)) {
        b->Begin(kCabinet, f->room(), up);
        b->Box(-L / 2, -0.175, cz0, L / 2, 0.175, cz1, body);
        Finish(f);
      }
    }
  }
  // Refrigerator.
  const double fw = r->Uniform(0.6, 0.75), fh = std::min(f->ceiling() - 0.1, r->Uniform(1.7, 2.0));
  Pose p;
  if (f->PlaceAgainstWall(fw, 0.66, fh, {}, 0.7, &p)) {
    b->Begin(kRefrigerator, f->room(), p);
    b->Box(-fw / 2, -0.33, 0, fw / 2, 0.33, fh, Vary(r->Bernoulli(0.6) ? kWhite : kSteel, r, 8), true);
    Finish(f);
  }
}

int Cabinet(RoomFurnisher* f, double wmin, double wmax, double d, double hmin, double hmax, double front = 0.5) {
  Rng* r = f->rng();
  const double w = r->Uniform(wmin, wmax), h = r->Uniform(hmin, hmax);
  Pose p;
  if (!f->PlaceAgainstWall(w, d, h, {}, front, &p)) return -1;
  const int id = f->b()->Begin(kCabinet, f->room(), p);
  f->b()->Box(-w / 2, -d / 2, 0, w / 2, d / 2, h, Vary(r->Pick(kWood), r), true);
  Finish(f);
  f->AddSupport(p, 0, 0, w / 2 - 0.03, d / 2 - 0.03, h, 0.5, id);
  return id;
}

void Desk(RoomFurnisher* f) {
  Rng* r = f->rng();
  const double w = r->Uniform(1.0, 1.6), d = r->Uniform(0.6, 0.75), h = r->Uniform(0.72, 0.76);
  Pose p;
  if (!f->PlaceAgainstWall(w, d, h, {}, 0.8, &p)) return;
  ApartmentBuilder* b = f->b();
  const Rgb8 c = Vary(r->Pick(kWood), r);
  const int id = b->Begin(kDesk, f->room(), p);
  b->Box(-w / 2, -d / 2, h - 0.03, w / 2, d / 2, h, c);
  if (f->Maybe(0.5)) {  // Shape variety: a drawer pedestal on one side instead of a panel.
    const double pw = r->Uniform(0.35, 0.45), side = r->Bernoulli(0.5) ? 1.0 : -1.0;
    const double px0 = side > 0 ? w / 2 - pw : -w / 2, px1 = side > 0 ? w / 2 : -w / 2 + pw;
    b->Box(px0, -d / 2, 0, px1, d / 2 - 0.02, h - 0.03, Vary(c, r, 12), true);
    if (side > 0) b->Box(-w / 2, -d / 2, 0, -w / 2 + 0.03, d / 2, h - 0.03, c, true);
    else b->Box(w / 2 - 0.03, -d / 2, 0, w / 2, d / 2, h - 0.03, c, true);
  } else {
    b->Box(-w / 2, -d / 2, 0, -w / 2 + 0.03, d / 2, h - 0.03, c, true);
    b->Box(w / 2 - 0.03, -d / 2, 0, w / 2, d / 2, h - 0.03, c, true);
  }
  Finish(f);
  // Monitor (ScanNet: monitor -> otherprop) at the back of the desk.
  const double mw = r->Uniform(0.5, 0.7);
  b->Begin(kOtherProp, f->room(), p, id);
  b->Box(-0.1, -d / 2 + 0.05, h, 0.1, -d / 2 + 0.2, h + 0.12, kBlack);
  b->Box(-mw / 2, -d / 2 + 0.1, h + 0.12, mw / 2, -d / 2 + 0.13, h + 0.12 + mw * 0.6, kBlack);
  b->End();
  f->AddSupport(p, 0, 0.12, w / 2 - 0.05, d / 2 - 0.2, h, 0.35, id);
  Pose cp = p;
  const Eigen::Vector2d cc = p.ToWorld(r->Uniform(-0.2, 0.2), d / 2 + 0.28);
  cp.x = cc.x(), cp.y = cc.y(), cp.yaw = p.yaw + M_PI + r->Uniform(-0.3, 0.3);
  Chair(f, cp, Vary(r->Pick(kFabric), r));
}

// ---------------------------------------------------------------------------------------------------
// Rooms by type.

void Bedroom(RoomFurnisher* f, bool child) {
  Rng* r = f->rng();
  const bool dbl = !child && f->in().area() > 8.5;
  if (Bed(f, dbl) < 0 && dbl && f->plan().single_bed_fallback) Bed(f, false);
  if (r->Bernoulli(0.75)) Wardrobe(f);
  if (r->Bernoulli(child ? 0.6 : 0.5)) Dresser(f);
  if (child) {
    if (r->Bernoulli(0.7)) ShelfUnit(f, kShelves);
    if (r->Bernoulli(0.4)) Desk(f);
    Pose p;
    if (r->Bernoulli(0.6) && f->PlaceFree(1.2, 0.8, kFlatMat, 0.0, false, &p)) FloorMat(f, 1.2, 0.8, p);
  } else if (r->Bernoulli(0.25)) {
    Desk(f);
  }
  if (f->Maybe(0.3)) Bin(f);
  Pictures(f, r->UniformInt(0, 2));
  WindowDressing(f, r->Bernoulli(0.5));
}

void LivingRoom(RoomFurnisher* f, bool studio, bool open_kitchen) {
  Rng* r = f->rng();
  ApartmentBuilder* b = f->b();
  if (studio) {
    Bed(f, r->Bernoulli(0.6));
    Counters(f, false);
  }
  Pose sofa;
  double sofa_d = 0;
  if (Sofa(f, &sofa, &sofa_d) >= 0) {
    // Coffee table in front of the sofa, a rug under it.
    const double cw = r->Uniform(0.8, 1.2), cd = r->Uniform(0.45, 0.6), ch = r->Uniform(0.38, 0.46);
    Pose cp = sofa;
    const Eigen::Vector2d c = sofa.ToWorld(0, sofa_d / 2 + 0.4 + cd / 2);
    cp.x = c.x(), cp.y = c.y();
    if (f->Free(f->FootprintAt(cp, cw, cd, 0, ch))) {
      if (r->Bernoulli(0.6)) FloorMat(f, cw + r->Uniform(0.6, 1.0), cd + r->Uniform(0.8, 1.2), cp);
      Table(f, cp, cw, cd, ch, kTable, Vary(r->Pick(kWood), r));
    }
    // TV on a low cabinet, facing the sofa where possible.
    const int sofa_side = int(std::lround(sofa.yaw / (M_PI / 2))) % 4;
    const double tw = r->Uniform(1.2, 1.8), td = r->Uniform(0.38, 0.45), th = r->Uniform(0.42, 0.55);
    Pose tp;
    if ((f->HasWall((sofa_side + 2) % 4) && f->PlaceAgainstWall(tw, td, th, {(sofa_side + 2) % 4}, 0.5, &tp)) || f->PlaceAgainstWall(tw, td, th, {}, 0.5, &tp)) {
      const int cab = b->Begin(kCabinet, f->room(), tp);
      b->Box(-tw / 2, -td / 2, 0, tw / 2, td / 2, th, Vary(r->Pick(kWood), r), true);
      Finish(f);
      const double vw = r->Uniform(0.9, std::min(1.45, tw - 0.1)), vh = vw * 0.58;
      b->Begin(kTelevision, f->room(), Pose{tp.x, tp.y, tp.yaw, tp.z + th}, cab);
      b->Box(-0.12, -0.1, 0, 0.12, 0.05, 0.05, kBlack);
      b->Box(-vw / 2, -0.04, 0.05, vw / 2, 0.0, 0.05 + vh, kBlack);
      b->End();
    }
  }
  if (r->Bernoulli(0.6)) ShelfUnit(f, kBookshelf, 1.6);
  if (f->in().area() > 18 && r->Bernoulli(0.5)) Cabinet(f, 0.8, 1.6, 0.42, 0.7, 0.9);  // Sideboard.
  if (r->Bernoulli(f->in().area() > 18 ? 0.6 : 0.3)) {
    Pose p;
    if (f->PlaceAgainstWall(0.75, 0.75, 0.85, {}, 0.5, &p)) Chair(f, p, Vary(r->Pick(kFabric), r));
  }
  if (r->Bernoulli(0.4)) {  // Floor lamp.
    Pose p;
    if (f->PlaceAgainstWall(0.35, 0.35, 1.7, {}, 0, &p)) {
      b->Begin(kLamp, f->room(), p);
      b->Box(-0.15, -0.15, 0, 0.15, 0.15, 0.03, Vary(kSteel, r), true);
      b->Box(-0.02, -0.02, 0.03, 0.02, 0.02, 1.4, Vary(kSteel, r));
      b->Box(-0.17, -0.17, 1.4, 0.17, 0.17, 1.7, Vary(Rgb8{240, 225, 170}, r));
      Finish(f);
    }
  }
  if (r->Bernoulli(0.35)) {  // Potted plant (otherprop).
    Pose p;
    if (f->PlaceAgainstWall(0.4, 0.4, 1.1, {}, 0, &p)) {
      b->Begin(kOtherProp, f->room(), p);
      b->Box(-0.15, -0.15, 0, 0.15, 0.15, 0.35, Vary(Rgb8{170, 90, 60}, r), true);
      b->Box(-0.2, -0.2, 0.35, 0.2, 0.2, r->Uniform(0.8, 1.1), Vary(Rgb8{60, 120, 50}, r, 20));
      Finish(f);
    }
  }
  if (open_kitchen || (!studio && f->in().area() > 24 && r->Bernoulli(0.5))) TableWithChairs(f, 1.0, 1.6, 0.75, 0.9, 4);
  if (studio) {
    if (r->Bernoulli(0.6)) Wardrobe(f);
    TableWithChairs(f, 0.7, 1.0, 0.6, 0.8, 2);
  }
  if ((studio || open_kitchen) && f->Maybe(0.5)) BarTable(f);
  if (f->Maybe(studio ? 0.6 : 0.3)) Bin(f);
  Pictures(f, r->UniformInt(1, 3));
  WindowDressing(f, r->Bernoulli(0.7));
}

void Kitchen(RoomFurnisher* f, bool open_plan) {
  Counters(f, true);
  if (!open_plan) TableWithChairs(f, 0.7, 1.3, 0.6, 0.85, 4);
  if (f->Maybe(0.35)) BarTable(f);
  for (int i = 0; i < 2; ++i)
    if (f->Maybe(0.5)) Bin(f);
  if (f->rng()->Bernoulli(0.3)) WindowDressing(f, false);
}

void Bathroom(RoomFurnisher* f) {
  Rng* r = f->rng();
  ApartmentBuilder* b = f->b();
  Pose p;
  bool tub = f->in().area() > 4.2 && r->Bernoulli(0.65);
  if (tub) {
    const double w = r->Uniform(1.5, 1.75), d = r->Uniform(0.7, 0.8);
    if (f->PlaceAgainstWall(w, d, 0.58, {}, 0.5, &p)) {
      b->Begin(kBathtub, f->room(), p);
      b->Box(-w / 2, -d / 2, 0, w / 2, d / 2, 0.58, Vary(kWhite, r, 6), true);
      Finish(f);
    } else {
      tub = false;
    }
  }
  if (!tub) {  // Shower tray (ScanNet: shower -> otherstructure) with a curtain along its front.
    const double s = r->Uniform(0.8, 0.95);
    if (f->PlaceAgainstWall(s, s, 2.0, {}, 0.5, &p)) {
      b->Begin(kOtherStructure, f->room(), p);
      b->Box(-s / 2, -s / 2, 0, s / 2, s / 2, 0.06, Vary(kWhite, r, 6), true);
      b->End();
      b->Begin(kShowerCurtain, f->room(), p);
      b->Box(-s / 2, s / 2 - 0.02, 0.15, s / 2, s / 2, 2.0, Vary(r->Pick(kBright), r));
      b->End();
      f->Take(f->FootprintAt(p, s, s, 0, 2.0));
    }
  }
  // Toilet: bowl and tank.
  if (f->PlaceAgainstWall(0.4, 0.68, 0.8, {}, 0.5, &p)) {
    b->Begin(kToilet, f->room(), p);
    if (f->variety()) {
      // Shape variety: a bowl on a narrower pedestal (a real scan sees the bowl's rim overhang it) or hung on
      // the wall with a low cistern, seats 0.38-0.45 m high, tanks of several sizes, the lid up on a quarter.
      // Drawn from a generator of its own, seeded by the toilet's pose, so that the rest of the apartment is
      // the same as without it. Everything stays inside the placed 0.4 x 0.68 x 0.8 m.
      uint64_t h = 0x70113e7ull;
      for (double v : {p.x, p.y, p.yaw}) h = HashCombine(h, std::bit_cast<uint64_t>(v));
      Rng u(h);
      const double bw = u.Uniform(0.34, 0.4), front = u.Uniform(0.26, 0.34), seat = u.Uniform(0.38, 0.45);
      const double tank_d = u.Uniform(0.13, 0.18), tank_w = u.Uniform(0.32, 0.4);
      const bool hung = u.Bernoulli(0.3), lid_up = u.Bernoulli(0.25);
      const double back = -0.34 + tank_d;  // Where the bowl meets the tank.
      if (hung) {
        b->Box(-bw / 2, back, seat - u.Uniform(0.2, 0.26), bw / 2, front, seat, kWhite, true);
        b->Box(-tank_w / 2, -0.34, seat + 0.05, tank_w / 2, back, seat + u.Uniform(0.2, 0.3), kWhite, true);
      } else {
        const double pw = u.Uniform(0.18, 0.26), rim = u.Uniform(0.08, 0.14);
        b->Box(-pw / 2, back, 0, pw / 2, front - u.Uniform(0.08, 0.14), seat - rim, kWhite, true);
        b->Box(-bw / 2, back, seat - rim, bw / 2, front, seat, kWhite, true);
        b->Box(-tank_w / 2, -0.34, 0, tank_w / 2, back, u.Uniform(0.68, 0.8), kWhite, true);
      }
      if (lid_up) b->Box(-bw / 2 + 0.02, back, seat, bw / 2 - 0.02, back + 0.04, std::min(0.8, seat + 0.38), kWhite, true);
    } else {
      b->Box(-0.19, -0.16, 0, 0.19, 0.34, 0.42, kWhite, true);
      b->Box(-0.2, -0.34, 0.0, 0.2, -0.16, 0.8, kWhite, true);
    }
    Finish(f);
  }
  // Vanity with a sink, a mirror above it.
  const double vw = r->Uniform(0.5, 0.9), vd = 0.46, vh = 0.82;
  if (f->PlaceAgainstWall(vw, vd, vh, {}, 0.6, &p)) {
    const int cab = b->Begin(kCabinet, f->room(), p);
    b->Box(-vw / 2, -vd / 2, 0, vw / 2, vd / 2, vh, Vary(r->Pick(kWood), r), true);
    Finish(f);
    b->Begin(kSink, f->room(), p, cab);
    b->Box(-0.22, -0.15, vh, 0.22, 0.2, vh + 0.12, kWhite);
    b->End();
    const double mw = std::min(vw, r->Uniform(0.4, 0.8)), mh = r->Uniform(0.5, 0.8);
    Pose mp = p;
    const Eigen::Vector2d mc = p.ToWorld(0, -vd / 2 - kGap + 0.01);
    mp.x = mc.x(), mp.y = mc.y();
    const Footprint mf = f->FootprintAt(mp, mw, 0.02, 1.05, 1.05 + mh);
    if (f->Free(mf)) {
      b->Begin(kMirror, f->room(), mp);
      b->Box(-mw / 2, -0.01, 1.05, mw / 2, 0.01, 1.05 + mh, Rgb8{200, 215, 225});
      Finish(f);
    }
  }
  if (f->Maybe(0.6)) Bin(f);
  for (int i = 0, n = r->UniformInt(1, 2); i < n; ++i)
    WallItem(f, kTowel, r->Uniform(0.3, 0.5), r->Uniform(0.4, 0.7), r->Uniform(0.8, 1.0), 0.05, Vary(r->Pick(kBright), r, 30));
  if (r->Bernoulli(0.6) && f->PlaceFree(0.6, 0.4, kFlatMat, 0, false, &p)) FloorMat(f, 0.6, 0.4, p);
}

void Office(RoomFurnisher* f) {
  Desk(f);
  ShelfUnit(f, f->rng()->Bernoulli(0.5) ? kBookshelf : kShelves);
  if (f->rng()->Bernoulli(0.5)) ShelfUnit(f, kShelves);
  if (f->rng()->Bernoulli(0.3)) Cabinet(f, 0.4, 0.8, 0.5, 0.6, 0.75);
  if (f->Maybe(0.6)) Bin(f);
  Pictures(f, f->rng()->UniformInt(0, 2));
  WindowDressing(f, false);
}

void Storage(RoomFurnisher* f) {
  for (int i = 0, n = f->rng()->UniformInt(1, 3); i < n; ++i) ShelfUnit(f, kShelves);
}

void Laundry(RoomFurnisher* f) {
  Rng* r = f->rng();
  ApartmentBuilder* b = f->b();
  Pose p;
  // Washer (ScanNet: washing machine -> otherfurniture), a dryer stacked on it sometimes.
  if (f->PlaceAgainstWall(0.6, 0.6, 1.75, {}, 0.6, &p)) {
    const int washer = b->Begin(kOtherFurniture, f->room(), p);
    b->Box(-0.3, -0.3, 0, 0.3, 0.3, 0.85, kWhite, true);
    b->Box(-0.16, 0.3, 0.3, 0.16, 0.32, 0.62, Vary(kSteel, r));
    if (r->Bernoulli(0.5)) {
      b->End();
      f->Take(f->FootprintAt(p, 0.6, 0.6, 0, 1.75));
      b->Begin(kOtherFurniture, f->room(), Pose{p.x, p.y, p.yaw, p.z + 0.85}, washer);
      b->Box(-0.3, -0.3, 0, 0.3, 0.3, 0.85, kWhite);
      b->End();
    } else {
      Finish(f);
      f->AddSupport(p, 0, 0, 0.26, 0.26, 0.85, 0.4, washer);
    }
  }
  ShelfUnit(f, kShelves);
}

void DiningRoom(RoomFurnisher* f) {
  TableWithChairs(f, 1.4, 2.0, 0.8, 1.0, 6);
  Cabinet(f, 1.0, 1.8, 0.45, 0.75, 0.95);
  Pictures(f, f->rng()->UniformInt(1, 2));
  WindowDressing(f, true);
}

void Corridor(RoomFurnisher* f) {
  Rng* r = f->rng();
  const double width = std::min(f->in().w(), f->in().h());
  if (width > 1.15) Cabinet(f, 0.6, 1.2, 0.35, 0.5, 1.0, 0.7);
  if (r->Bernoulli(0.6)) WallItem(f, kClothes, r->Uniform(0.4, 0.7), r->Uniform(0.6, 0.9), 0.9, 0.15, Vary(r->Pick(kFabric), r, 30));
  Pose p;
  if (r->Bernoulli(0.6) && f->PlaceFree(0.8, 0.5, kFlatMat, 0, false, &p)) FloorMat(f, 0.8, 0.5, p);
  Pictures(f, r->UniformInt(0, 2));
}

// ---------------------------------------------------------------------------------------------------
// Props on supports and on the floor.

struct PropKind {
  int label;
  double wmin, wmax, dmin, dmax, hmin, hmax;
};

void Props(RoomFurnisher* f, int count) {
  Rng* r = f->rng();
  ApartmentBuilder* b = f->b();
  const PropKind kinds[] = {{kBooks, 0.12, 0.35, 0.15, 0.25, 0.04, 0.25},  {kBox, 0.15, 0.5, 0.15, 0.4, 0.1, 0.4},
                            {kBag, 0.25, 0.45, 0.12, 0.25, 0.2, 0.45},    {kClothes, 0.3, 0.5, 0.2, 0.4, 0.03, 0.1},
                            {kPaper, 0.21, 0.3, 0.21, 0.3, 0.004, 0.02},  {kOtherProp, 0.06, 0.15, 0.06, 0.15, 0.08, 0.3}};
  for (int i = 0; i < count; ++i) {
    std::vector<Support>& sup = f->supports();
    const bool on_floor = sup.empty() || r->Bernoulli(0.25);
    const PropKind& k = on_floor ? kinds[r->Pick(std::vector<int>{1, 1, 2, 2, 3})] : kinds[r->UniformInt(0, 5)];
    const double w = r->Uniform(k.wmin, k.wmax), d = r->Uniform(k.dmin, k.dmax), h = r->Uniform(k.hmin, k.hmax);
    const Rgb8 c = Vary(r->Pick(kBright), r, 30);
    if (on_floor) {
      Pose p;
      if (!f->PlaceAgainstWall(w, d, h, {}, 0, &p, 0.0, 10)) continue;
      b->Begin(k.label, f->room(), p);
      b->Box(-w / 2, -d / 2, 0, w / 2, d / 2, h, c, true);
      Finish(f);
      continue;
    }
    Support& s = sup[size_t(r->UniformInt(0, int(sup.size()) - 1))];
    if (h > s.max_height || w > 2 * s.hx || d > 2 * s.hy) continue;
    for (int attempt = 0; attempt < 8; ++attempt) {
      Pose p = s.pose;
      const Eigen::Vector2d c2 = s.pose.ToWorld(r->Uniform(-s.hx + w / 2, s.hx - w / 2), r->Uniform(-s.hy + d / 2, s.hy - d / 2));
      p.x = c2.x(), p.y = c2.y();
      Footprint fp;
      fp.c = c2, fp.hx = w / 2, fp.hy = d / 2, fp.yaw = p.yaw, fp.z0 = p.z, fp.z1 = p.z + h;
      if (std::any_of(s.taken.begin(), s.taken.end(), [&](const Footprint& o) { return Overlaps(fp, o); })) continue;
      s.taken.push_back(fp);
      b->Begin(k.label, f->room(), p, s.instance);
      if (k.label == kBooks) {  // A row of books.
        double x = -w / 2;
        while (x < w / 2 - 0.015) {
          const double t = std::min(w / 2 - x, r->Uniform(0.02, 0.05));
          b->Box(x, -d / 2, 0, x + t, d / 2, h * r->Uniform(0.75, 1.0), Vary(r->Pick(kBright), r, 40));
          x += t;
        }
      } else {
        b->Box(-w / 2, -d / 2, 0, w / 2, d / 2, h, c);
      }
      b->End();
      break;
    }
  }
}

}  // namespace

void FurnishApartment(const FloorPlan& plan, bool props, bool variety, Rng* rng, ApartmentBuilder* builder) {
  const RoomTypeIds& t = RoomTypeIds::Get();
  for (int i = 0; i < int(plan.rooms.size()); ++i) {
    const PlanRoom& pr = plan.rooms[size_t(i)];
    RoomFurnisher f(plan, i, variety, rng, builder);
    const bool open = pr.open_group >= 0;
    if (pr.type == t.living_room) LivingRoom(&f, pr.studio, open);
    else if (pr.type == t.kitchen) Kitchen(&f, open);
    else if (pr.type == t.bedroom) Bedroom(&f, false);
    else if (pr.type == t.childs_room) Bedroom(&f, true);
    else if (pr.type == t.bathroom) Bathroom(&f);
    else if (pr.type == t.office) Office(&f);
    else if (pr.type == t.storage) Storage(&f);
    else if (pr.type == t.laundry) Laundry(&f);
    else if (pr.type == t.dining_room) DiningRoom(&f);
    else if (pr.type == t.corridor) Corridor(&f);
    if (props) Props(&f, int(std::round(pr.interior.area() * rng->Uniform(0.3, 0.7))));
  }
}

}  // namespace scenegen
}  // namespace semvox
