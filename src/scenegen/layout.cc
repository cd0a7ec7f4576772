#include "scenegen/layout.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/labels.h"

namespace semvox {
namespace scenegen {
namespace {

constexpr double kSnap = 0.05;  // Plan coordinates are multiples of the rooms_gt grid.
double Snap(double v) { return std::round(v / kSnap) * kSnap; }
long Units(double v) { return std::lround(v / kSnap); }

int TypeId(const char* name) {
  const int id = RoomTypeIdByName(name);
  if (id < 0) throw std::logic_error(std::string("room_types table lacks ") + name);
  return id;
}

}  // namespace

const RoomTypeIds& RoomTypeIds::Get() {
  static const RoomTypeIds ids{TypeId("bathroom"), TypeId("bedroom"),  TypeId("childs_room"), TypeId("corridor"),
                               TypeId("dining_room"), TypeId("kitchen"), TypeId("laundry"), TypeId("living_room"),
                               TypeId("office"), TypeId("storage")};
  return ids;
}

namespace {

// Target cell areas (m², walls included) by room type, drawn uniformly in [lo, hi].
struct AreaRange { double lo, hi; };
AreaRange TargetArea(int type, bool studio) {
  const RoomTypeIds& t = RoomTypeIds::Get();
  if (studio) return {22, 34};
  if (type == t.living_room) return {17, 30};
  if (type == t.kitchen) return {7, 13};
  if (type == t.bathroom) return {4, 7.5};
  if (type == t.bedroom) return {10, 17};
  if (type == t.childs_room) return {9, 13};
  if (type == t.office) return {7.5, 11};
  if (type == t.storage) return {3.2, 5};
  if (type == t.laundry) return {3.5, 6};
  if (type == t.dining_room) return {9, 14};
  if (type == t.corridor) return {3.5, 6};  // A hall; corridors proper are sized by the layout.
  return {8, 12};
}

// Smallest side of a room's cell by type, metres.
double MinSide(int type) {
  const RoomTypeIds& t = RoomTypeIds::Get();
  if (type == t.corridor) return 1.2;
  if (type == t.storage) return 1.4;
  if (type == t.bathroom || type == t.laundry) return 1.7;
  if (type == t.kitchen) return 2.2;
  return 2.5;
}

PlanRoom MakeRoom(int type, Rng* rng, bool studio = false) {
  PlanRoom r;
  r.type = type;
  r.studio = studio;
  const AreaRange a = TargetArea(type, studio);
  r.target_area = rng->Uniform(a.lo, a.hi);
  return r;
}

// The rooms of an n-room flat, and whether it is laid out around a corridor.
std::vector<PlanRoom> DrawProgram(int n, Rng* rng, bool* corridor_layout) {
  const RoomTypeIds& t = RoomTypeIds::Get();
  std::vector<PlanRoom> rooms;
  *corridor_layout = false;
  if (n == 1) return {MakeRoom(t.living_room, rng, true)};
  if (n == 2) return {MakeRoom(t.living_room, rng, true), MakeRoom(t.bathroom, rng)};
  if (n == 3) {
    if (rng->Bernoulli(0.5)) {
      rooms = {MakeRoom(t.living_room, rng), MakeRoom(t.kitchen, rng), MakeRoom(t.bathroom, rng)};
      rooms[0].open_group = rooms[1].open_group = 0;
      return rooms;
    }
    return {MakeRoom(t.living_room, rng, true), MakeRoom(t.bathroom, rng), MakeRoom(t.corridor, rng)};
  }
  rooms = {MakeRoom(t.living_room, rng), MakeRoom(t.kitchen, rng), MakeRoom(t.bathroom, rng)};
  if (rng->Bernoulli(0.5)) rooms[0].open_group = rooms[1].open_group = 0;
  bool corridor = n >= 5 || rng->Bernoulli(0.4);
  if (corridor) {
    rooms.push_back(MakeRoom(t.corridor, rng));
    *corridor_layout = n >= 5;
  }
  rooms.push_back(MakeRoom(t.bedroom, rng));
  int bedrooms = 1, bathrooms = 1;
  const std::vector<int> extras = {t.bedroom, t.bedroom, t.office, t.childs_room, t.storage,
                                   t.laundry, t.dining_room, t.bathroom};
  while (int(rooms.size()) < n) {
    const int type = rng->Pick(extras);
    if (type == t.bedroom && bedrooms >= 3) continue;
    if (type == t.bathroom && (bathrooms >= 2 || n < 7)) continue;
    if (type != t.bedroom && type != t.bathroom &&
        std::any_of(rooms.begin(), rooms.end(), [&](const PlanRoom& r) { return r.type == type; }))
      continue;
    bedrooms += type == t.bedroom;
    bathrooms += type == t.bathroom;
    rooms.push_back(MakeRoom(type, rng));
  }
  return rooms;
}

// One leaf of the slicing tree: a room, or two rooms of one open-plan space.
struct Item {
  std::vector<int> rooms;
  double area = 0;
};

void SplitRect(const Rect& r, double fraction, bool along_x, Rect* first, Rect* second) {
  *first = *second = r;
  if (along_x) {
    const double cut = Snap(r.x0 + r.w() * fraction);
    first->x1 = second->x0 = cut;
  } else {
    const double cut = Snap(r.y0 + r.h() * fraction);
    first->y1 = second->y0 = cut;
  }
}

// Recursive slicing: split the items into two groups of about equal area, cut the rectangle across its
// longer side in that proportion, recurse. Gives compact rooms (aspect ratios near those of the targets).
void Slice(const Rect& r, const std::vector<Item>& items, std::vector<PlanRoom>* rooms, Rng* rng) {
  if (items.empty()) return;
  if (items.size() == 1) {
    const Item& it = items[0];
    if (it.rooms.size() == 1) {
      (*rooms)[size_t(it.rooms[0])].cell = r;
      return;
    }
    const double fa = (*rooms)[size_t(it.rooms[0])].target_area / it.area;
    Rect a, b;
    SplitRect(r, fa, r.w() >= r.h(), &a, &b);
    (*rooms)[size_t(it.rooms[0])].cell = a;
    (*rooms)[size_t(it.rooms[1])].cell = b;
    return;
  }
  double total = 0;
  for (const Item& it : items) total += it.area;
  size_t best_k = 1;
  double best = 1e9, acc = 0;
  for (size_t k = 1; k < items.size(); ++k) {
    acc += items[k - 1].area;
    const double score = std::fabs(acc / total - 0.5) + rng->Uniform(0, 0.05);
    if (score < best) best = score, best_k = k;
  }
  std::vector<Item> left(items.begin(), items.begin() + long(best_k)), right(items.begin() + long(best_k), items.end());
  double la = 0;
  for (const Item& it : left) la += it.area;
  const bool along_x = r.w() >= r.h();
  // A single small room whose strip across the whole side would be too thin gets a compact corner block
  // instead; the rest of its strip stays outside the flat (a notch in the outline, as real plans have).
  for (int k = 0; k < 2; ++k) {
    const std::vector<Item>& grp = k == 0 ? left : right;
    if (grp.size() != 1 || grp[0].rooms.size() != 1) continue;
    const PlanRoom& room = (*rooms)[size_t(grp[0].rooms[0])];
    const double side = along_x ? r.h() : r.w();
    const double strip = grp[0].area / side;
    if (strip >= MinSide(room.type) + 0.2) continue;
    const double width = Snap(std::max(MinSide(room.type) + 0.3, std::sqrt(grp[0].area) * rng->Uniform(0.85, 1.1)));
    const double length = Snap(std::min(side, grp[0].area / width));
    Rect block = r, rest = r;
    const bool at_start = rng->Bernoulli(0.5);
    if (along_x) {
      if (k == 0) block.x1 = rest.x0 = r.x0 + width;
      else block.x0 = rest.x1 = r.x1 - width;
      if (at_start) block.y1 = block.y0 + length;
      else block.y0 = block.y1 - length;
    } else {
      if (k == 0) block.y1 = rest.y0 = r.y0 + width;
      else block.y0 = rest.y1 = r.y1 - width;
      if (at_start) block.x1 = block.x0 + length;
      else block.x0 = block.x1 - length;
    }
    (*rooms)[size_t(grp[0].rooms[0])].cell = block;
    Slice(rest, k == 0 ? right : left, rooms, rng);
    return;
  }
  Rect a, b;
  SplitRect(r, la / total, along_x, &a, &b);
  Slice(a, left, rooms, rng);
  Slice(b, right, rooms, rng);
}

std::vector<Item> MakeItems(const std::vector<PlanRoom>& rooms, const std::vector<int>& ids) {
  std::vector<Item> items;
  for (int id : ids) {
    const PlanRoom& r = rooms[size_t(id)];
    if (r.open_group >= 0) {
      auto it = std::find_if(items.begin(), items.end(), [&](const Item& x) {
        return rooms[size_t(x.rooms[0])].open_group == r.open_group;
      });
      if (it != items.end()) {
        it->rooms.push_back(id);
        it->area += r.target_area;
        continue;
      }
    }
    items.push_back(Item{{id}, r.target_area});
  }
  return items;
}

// Lays the rooms out: around a corridor (living space at one end, rooms in two bands along the corridor)
// or as one sliced rectangle.
void Layout(bool corridor_layout, std::vector<PlanRoom>* rooms, Rng* rng) {
  const RoomTypeIds& t = RoomTypeIds::Get();
  std::vector<int> order(rooms->size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = int(i);
  if (!corridor_layout) {
    rng->Shuffle(&order);
    const std::vector<Item> items = MakeItems(*rooms, order);
    double total = 0;
    for (const Item& it : items) total += it.area;
    const double aspect = rng->Uniform(1.0, 1.7);
    double w = std::sqrt(total * aspect), h = total / w;
    if (rng->Bernoulli(0.5)) std::swap(w, h);
    Slice(Rect{0, 0, Snap(w), Snap(h)}, items, rooms, rng);
    return;
  }
  // Corridor layout. The living block (living room, with the kitchen when open plan) spans the whole
  // depth at the west end; the corridor runs east from it between a south and a north band of rooms.
  std::vector<int> block, bands;
  int corridor = -1;
  for (int i : order) {
    const PlanRoom& r = (*rooms)[size_t(i)];
    if (r.type == t.corridor) corridor = i;
    else if (r.type == t.living_room || (r.open_group >= 0 && r.open_group == (*rooms)[0].open_group)) block.push_back(i);
    else bands.push_back(i);
  }
  rng->Shuffle(&bands);
  std::vector<int> south, north;
  double as = 0, an = 0;
  for (int i : bands) {
    const double a = (*rooms)[size_t(i)].target_area;
    if (as <= an) south.push_back(i), as += a;
    else north.push_back(i), an += a;
  }
  const double corridor_w = Snap(rng->Uniform(1.1, 1.6));
  const double ds = Snap(rng->Uniform(3.0, 4.4)), dn = Snap(rng->Uniform(3.0, 4.4));
  const double depth = ds + corridor_w + dn;
  double block_area = 0;
  for (int i : block) block_area += (*rooms)[size_t(i)].target_area;
  const double block_w = Snap(std::max(3.0, block_area / depth));
  const double ls = Snap(as / ds), ln = Snap(an / dn);
  const double lc = std::max({ls, ln, 2.0});
  Slice(Rect{0, 0, block_w, depth}, MakeItems(*rooms, block), rooms, rng);
  Slice(Rect{block_w, 0, block_w + ls, ds}, MakeItems(*rooms, south), rooms, rng);
  Slice(Rect{block_w, ds + corridor_w, block_w + ln, depth}, MakeItems(*rooms, north), rooms, rng);
  (*rooms)[size_t(corridor)].cell = Rect{block_w, ds, block_w + lc, ds + corridor_w};
}

// Side geometry: the fixed coordinate of side s of a rectangle and its extent along the side's axis.
double SideLine(const Rect& r, int s) { return s == kSouth ? r.y0 : s == kEast ? r.x1 : s == kNorth ? r.y1 : r.x0; }
double SideLo(const Rect& r, int s) { return (s == kSouth || s == kNorth) ? r.x0 : r.y0; }
double SideHi(const Rect& r, int s) { return (s == kSouth || s == kNorth) ? r.x1 : r.y1; }

void ComputeSides(FloorPlan* plan) {
  std::vector<PlanRoom>& rooms = plan->rooms;
  for (size_t i = 0; i < rooms.size(); ++i) {
    for (int s = 0; s < 4; ++s) {
      const Rect& c = rooms[i].cell;
      const long line = Units(SideLine(c, s)), lo = Units(SideLo(c, s)), hi = Units(SideHi(c, s));
      std::vector<SideSegment> shared;
      for (size_t j = 0; j < rooms.size(); ++j) {
        if (j == i) continue;
        const Rect& o = rooms[j].cell;
        const int os = (s + 2) % 4;
        if (Units(SideLine(o, os)) != line) continue;
        const long a = std::max(lo, Units(SideLo(o, os))), b = std::min(hi, Units(SideHi(o, os)));
        if (b <= a) continue;
        const bool open = rooms[i].open_group >= 0 && rooms[i].open_group == rooms[j].open_group;
        shared.push_back(SideSegment{a * kSnap, b * kSnap, int(j), open});
      }
      std::sort(shared.begin(), shared.end(), [](const SideSegment& x, const SideSegment& y) { return x.a < y.a; });
      std::vector<SideSegment>& out = rooms[i].sides[s];
      out.clear();
      double at = lo * kSnap;
      for (const SideSegment& seg : shared) {
        if (Units(seg.a) > Units(at)) out.push_back(SideSegment{at, seg.a, -1, false});
        out.push_back(seg);
        at = seg.b;
      }
      if (Units(at) < hi) out.push_back(SideSegment{at, hi * kSnap, -1, false});
      double shrink = 0;
      for (const SideSegment& seg : out)
        shrink = std::max(shrink, seg.neighbor < 0 ? plan->exterior_wall / 2 : seg.open ? 0.0 : plan->interior_wall / 2);
      rooms[i].shrink[s] = shrink;
    }
    PlanRoom& r = rooms[i];
    r.interior = Rect{r.cell.x0 + r.shrink[kWest], r.cell.y0 + r.shrink[kSouth], r.cell.x1 - r.shrink[kEast],
                      r.cell.y1 - r.shrink[kNorth]};
  }
}

bool LayoutIsPlausible(const FloorPlan& plan) {
  const RoomTypeIds& t = RoomTypeIds::Get();
  for (const PlanRoom& r : plan.rooms) {
    const double lo = std::min(r.cell.w(), r.cell.h()), hi = std::max(r.cell.w(), r.cell.h());
    if (lo < MinSide(r.type)) return false;
    if (r.type != t.corridor && hi / lo > 2.6) return false;
    const double area = r.interior.area();
    if (area < 3.0 || area > 35.0) return false;
  }
  return true;
}

// Interval along side s of room i usable for an opening: the shared segment clipped to the clear interior
// of both rooms, minus `margin` at each end.
bool UsableInterval(const FloorPlan& plan, int i, int s, const SideSegment& seg, double margin, double* a, double* b) {
  const Rect& in = plan.rooms[size_t(i)].interior;
  double lo = std::max(seg.a, SideLo(in, s)), hi = std::min(seg.b, SideHi(in, s));
  if (seg.neighbor >= 0) {
    const Rect& on = plan.rooms[size_t(seg.neighbor)].interior;
    const int os = (s + 2) % 4;
    lo = std::max(lo, SideLo(on, os));
    hi = std::min(hi, SideHi(on, os));
  }
  *a = lo + margin;
  *b = hi - margin;
  return *b > *a;
}

// Cost of joining two room types by a door (lower = more usual).
double DoorCost(int from, int to) {
  const RoomTypeIds& t = RoomTypeIds::Get();
  auto is = [&](int a, int b) { return (from == a && to == b) || (from == b && to == a); };
  auto hub = [&](int x) { return x == t.corridor || x == t.living_room; };
  if (hub(from) || hub(to)) return is(t.living_room, t.bathroom) ? 3.0 : 1.0;
  if (is(t.bedroom, t.bathroom) || is(t.bedroom, t.storage)) return 3.0;
  if (is(t.kitchen, t.dining_room) || is(t.kitchen, t.laundry) || is(t.kitchen, t.storage)) return 2.0;
  if (is(t.kitchen, t.bathroom)) return 12.0;
  return 5.0;
}
bool IsDeadEnd(int type) {
  const RoomTypeIds& t = RoomTypeIds::Get();
  return type == t.bathroom || type == t.storage || type == t.laundry;
}

bool PlaceDoors(FloorPlan* plan, Rng* rng) {
  const RoomTypeIds& t = RoomTypeIds::Get();
  std::vector<PlanRoom>& rooms = plan->rooms;
  const int n = int(rooms.size());
  int hub = 0;
  for (int i = 0; i < n; ++i)
    if (rooms[size_t(i)].type == t.corridor) hub = i;
  std::vector<bool> in_tree(size_t(n), false);
  in_tree[size_t(hub)] = true;
  const double margin = 0.08;
  for (int added = 1; added < n; ++added) {
    double best = 1e18;
    int bu = -1, bs = -1;
    SideSegment bseg;
    for (int u = 0; u < n; ++u) {
      if (!in_tree[size_t(u)]) continue;
      for (int s = 0; s < 4; ++s)
        for (const SideSegment& seg : rooms[size_t(u)].sides[s]) {
          if (seg.neighbor < 0 || in_tree[size_t(seg.neighbor)]) continue;
          double a, b;
          if (!seg.open && (!UsableInterval(*plan, u, s, seg, margin, &a, &b) || b - a < 0.95)) continue;
          const double cost = seg.open ? -1.0
                                       : DoorCost(rooms[size_t(u)].type, rooms[size_t(seg.neighbor)].type) +
                                             (IsDeadEnd(rooms[size_t(u)].type) ? 10.0 : 0.0) + rng->Uniform(0, 0.5);
          if (cost < best) best = cost, bu = u, bs = s, bseg = seg;
        }
    }
    if (bu < 0) return false;  // Some room cannot be reached.
    in_tree[size_t(bseg.neighbor)] = true;
    if (bseg.open) continue;
    double a, b;
    UsableInterval(*plan, bu, bs, bseg, margin, &a, &b);
    const double width = rng->Uniform(0.8, 0.9);
    double start;
    if (rng->Bernoulli(0.6)) {  // Near one end, as most doors are.
      const double off = std::min(rng->Uniform(0.05, 0.25), b - a - width);
      start = rng->Bernoulli(0.5) ? a + off : b - off - width;
    } else {
      start = rng->Uniform(a, b - width);
    }
    plan->doors.push_back(PlanDoor{bu, bseg.neighbor, bs, start, start + width, rng->Uniform(2.0, 2.1)});
  }
  // The entrance: on an exterior wall of the corridor or hall, else of the living space, else anywhere
  // but a bathroom.
  std::vector<int> candidates;
  for (int i = 0; i < n; ++i)
    if (rooms[size_t(i)].type == t.corridor) candidates.push_back(i);
  for (int i = 0; i < n; ++i)
    if (rooms[size_t(i)].type == t.living_room || rooms[size_t(i)].type == t.kitchen) candidates.push_back(i);
  for (int i = 0; i < n; ++i)
    if (rooms[size_t(i)].type != t.bathroom) candidates.push_back(i);
  for (int i : candidates) {
    std::vector<std::pair<int, SideSegment>> ext;
    for (int s = 0; s < 4; ++s)
      for (const SideSegment& seg : rooms[size_t(i)].sides[s]) {
        double a, b;
        if (seg.neighbor < 0 && UsableInterval(*plan, i, s, seg, 0.15, &a, &b) && b - a >= 1.0) ext.push_back({s, seg});
      }
    if (ext.empty()) continue;
    const auto& [s, seg] = rng->Pick(ext);
    double a, b;
    UsableInterval(*plan, i, s, seg, 0.15, &a, &b);
    const double width = rng->Uniform(0.85, 0.9);
    const double start = rng->Uniform(a, b - width);
    plan->doors.push_back(PlanDoor{i, -1, s, start, start + width, rng->Uniform(2.0, 2.1)});
    return true;
  }
  return false;
}

void PlaceWindows(FloorPlan* plan, Rng* rng) {
  const RoomTypeIds& t = RoomTypeIds::Get();
  for (int i = 0; i < int(plan->rooms.size()); ++i) {
    const PlanRoom& r = plan->rooms[size_t(i)];
    if (r.type == t.corridor || r.type == t.storage) continue;
    int want = rng->UniformInt(1, 2);
    if (r.type == t.living_room) want = rng->UniformInt(1, 3);
    if (r.type == t.bathroom || r.type == t.laundry) want = rng->Bernoulli(0.4) ? 1 : 0;
    std::vector<std::pair<int, SideSegment>> ext;
    for (int s = 0; s < 4; ++s)
      for (const SideSegment& seg : r.sides[s])
        if (seg.neighbor < 0) ext.push_back({s, seg});
    rng->Shuffle(&ext);
    for (const auto& [s, seg] : ext) {
      if (want <= 0) break;
      double a, b;
      if (!UsableInterval(*plan, i, s, seg, 0.3, &a, &b) || b - a < 0.7) continue;
      const bool small = r.type == t.bathroom || r.type == t.laundry;
      const double width = small ? std::min(b - a, rng->Uniform(0.5, 0.8)) : rng->Uniform(0.7, std::min(2.0, b - a));
      const double start = rng->Uniform(a, b - width);
      bool clash = false;  // Keep 0.3 m of wall between a window and a door in the same side.
      for (const PlanDoor& d : plan->doors) {
        const bool same = (d.room_a == i && d.side_a == s) || (d.room_b == i && (d.side_a + 2) % 4 == s);
        if (same && start < d.b + 0.3 && start + width > d.a - 0.3) clash = true;
      }
      if (clash) continue;
      PlanWindow w{i, s, start, start + width, 0, 0};
      w.sill = small ? rng->Uniform(1.2, 1.4) : r.type == t.kitchen || r.studio ? rng->Uniform(1.0, 1.1) : rng->Uniform(0.8, 1.0);
      w.top = std::min(plan->ceiling - 0.2, rng->Uniform(2.0, 2.25));
      plan->windows.push_back(w);
      --want;
    }
  }
}

}  // namespace

bool DrawFloorPlan(int num_rooms, double ceiling_m, double interior_wall_m, double exterior_wall_m, Rng* rng,
                   FloorPlan* plan) {
  *plan = FloorPlan();
  plan->ceiling = ceiling_m;
  plan->interior_wall = interior_wall_m;
  plan->exterior_wall = exterior_wall_m;
  bool corridor_layout = false;
  plan->rooms = DrawProgram(num_rooms, rng, &corridor_layout);
  Layout(corridor_layout, &plan->rooms, rng);
  ComputeSides(plan);
  if (!LayoutIsPlausible(*plan)) return false;
  if (!PlaceDoors(plan, rng)) return false;
  PlaceWindows(plan, rng);
  return true;
}

}  // namespace scenegen
}  // namespace semvox
