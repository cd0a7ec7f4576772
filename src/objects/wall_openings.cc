#include "objects/wall_openings.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/labels.h"

namespace semvox {

bool WallOpeningOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(min_face_m2 > 0 && max_recess_m > 0 && front_m > 0)) return fail("min_face_m2, max_recess_m and front_m must be > 0");
  if (!(pane_tolerance_m >= 0 && pane_behind_m >= 0)) return fail("pane_tolerance_m and pane_behind_m must be >= 0");
  if (!(hole_depth_m > max_recess_m)) return fail("hole_depth_m must be > max_recess_m");
  if (!(min_flat_share >= 0 && min_flat_share <= 1)) return fail("min_flat_share must be in [0, 1]");
  if (!(min_frame_seen_share >= 0 && min_frame_seen_share <= 1)) return fail("min_frame_seen_share must be in [0, 1]");
  if (!(min_fill > 0 && min_fill <= 1 && min_frame_share > 0 && min_frame_share <= 1))
    return fail("min_fill and min_frame_share must be in (0, 1]");
  if (!(door_min_width_m > 0 && door_max_width_m >= door_min_width_m && door_max_bottom_m >= 0 && door_min_top_m > 0 &&
        door_max_top_m >= door_min_top_m))
    return fail("door sizes: need 0 < door_min_width_m <= door_max_width_m, door_max_bottom_m >= 0, 0 < door_min_top_m <= door_max_top_m");
  if (!(window_min_width_m > 0 && window_max_width_m >= window_min_width_m && window_min_bottom_m >= 0 && window_min_height_m > 0))
    return fail("window sizes: need 0 < window_min_width_m <= window_max_width_m, window_min_bottom_m >= 0, window_min_height_m > 0");
  return true;
}

namespace {

// What a wall line's elevation cell shows, looking from the room at the wall.
enum Look : uint8_t {
  kUnseen = 0,  // The face position was never observed.
  kFace,        // The first surface is at the face (or up to a cell in front of it).
  kRecess,      // The first surface lies 1 to max_recess cells behind the face.
  kHole,        // Free space reaches past the face: nothing there (an open door, unrecorded glass).
  kHidden,      // Something stands in front of the face.
  kDeep,        // Free past the deepest recess, but something behind before hole_depth.
};

// The grid seen along one wall direction: (along, across, z) cells, across = the axis the wall faces.
struct WallAxes {
  const VoxelGrid& grid;
  int axis;  // 0: walls along x, across = y; 1: walls along y, across = x.
  int along_size() const { return grid.dims()[axis == 0 ? 0 : 1]; }
  int across_size() const { return grid.dims()[axis == 0 ? 1 : 0]; }
  bool Contains(int a, int l, int z) const { return axis == 0 ? grid.Contains(a, l, z) : grid.Contains(l, a, z); }
  size_t Index(int a, int l, int z) const { return axis == 0 ? grid.Index(a, l, z) : grid.Index(l, a, z); }
  VoxelState State(int a, int l, int z) const { return Contains(a, l, z) ? grid.state(Index(a, l, z)) : VoxelState::kUnknown; }
  bool Occupied(int a, int l, int z) const { return State(a, l, z) == VoxelState::kOccupied; }
};

struct Elevation {
  int width = 0, z_lo = 0, height = 0;
  std::vector<uint8_t> look;   // width x height, row-major by z.
  std::vector<int8_t> depth;   // kRecess: cells behind the face of the first surface.
  uint8_t at(int a, int z) const {
    return a < 0 || a >= width || z < z_lo || z >= z_lo + height ? uint8_t(kUnseen) : look[size_t(z - z_lo) * width + a];
  }
};

Elevation LookAtWall(const WallAxes& w, int facing, int line, int z_lo, int z_hi, int front, int recess, int hole) {
  Elevation e;
  e.width = w.along_size(), e.z_lo = z_lo, e.height = std::max(0, z_hi - z_lo + 1);
  e.look.assign(size_t(e.width) * e.height, kUnseen);
  e.depth.assign(e.look.size(), 0);
  for (int z = z_lo; z <= z_hi; ++z)
    for (int a = 0; a < e.width; ++a) {
      const size_t i = size_t(z - z_lo) * e.width + a;
      bool hidden = false;
      for (int k = 2; k <= front && !hidden; ++k) hidden = w.Occupied(a, line + facing * k, z);
      if (hidden) {
        e.look[i] = kHidden;
        continue;
      }
      uint8_t look = kUnseen;
      int k = 1;
      for (; k >= -recess; --k) {
        const VoxelState s = w.State(a, line + facing * k, z);
        if (s == VoxelState::kFree) continue;
        if (s == VoxelState::kOccupied) {
          look = k >= 0 ? kFace : kRecess;
          e.depth[i] = int8_t(-k);
        } else if (k < 0) {
          look = kHole;  // Unknown past the face: the view went through the face's plane.
        }
        break;
      }
      if (k < -recess || look == kHole) {
        // Free (or unseen) past the deepest recess: a hole only when nothing is occupied up to hole_depth behind
        // the face (the next room, the outside); a surface there is a deep niche (the wall under wall cabinets).
        look = kHole;
        for (int kk = k; kk >= -hole && look == kHole; --kk)
          if (w.Occupied(a, line + facing * kk, z)) look = kDeep;
      }
      e.look[i] = look;
    }
  return e;
}

// Rows (across index) of one facing whose face cells (occupied, free on the room side) cover at least
// min_cells, local maxima within 2 rows.
std::vector<int> WallLines(const WallAxes& w, int facing, int z_lo, int z_hi, int min_cells) {
  const int L = w.across_size(), A = w.along_size();
  std::vector<int> count(size_t(L), 0);
  for (int l = 0; l < L; ++l)
    for (int z = z_lo; z <= z_hi; ++z)
      for (int a = 0; a < A; ++a)
        count[size_t(l)] += w.Occupied(a, l, z) && w.State(a, l + facing, z) == VoxelState::kFree;
  std::vector<int> lines;
  for (int l = 0; l < L; ++l) {
    if (count[size_t(l)] < min_cells) continue;
    bool peak = true;
    for (int d = -2; d <= 2 && peak; ++d) {
      const int m = l + d;
      if (d == 0 || m < 0 || m >= L) continue;
      peak = d < 0 ? count[size_t(l)] > count[size_t(m)] : count[size_t(l)] >= count[size_t(m)];
    }
    if (peak) lines.push_back(l);
  }
  return lines;
}

// A 4-connected region of recessed or missing cells of an elevation, or (recess_only) of recessed cells alone
// (cells: row-major indices).
struct Region {
  std::vector<int> cells;
  int a0 = 0, a1 = -1, r0 = 0, r1 = -1;  // Bounding box: along, rows of the elevation.
  int recessed = 0;                      // Of the cells, how many are kRecess.
  bool mostly_recessed() const { return 2 * recessed >= int(cells.size()); }
};

std::vector<Region> OpeningRegions(const Elevation& e, bool recess_only) {
  auto open = [&](size_t i) { return e.look[i] == kRecess || (!recess_only && e.look[i] == kHole); };
  std::vector<Region> out;
  std::vector<uint8_t> done(e.look.size(), 0);
  std::vector<int> stack;
  for (size_t s = 0; s < e.look.size(); ++s) {
    if (done[s] || !open(s)) continue;
    Region g;
    g.a0 = e.width, g.r0 = e.height;
    stack.assign(1, int(s));
    done[s] = 1;
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      g.cells.push_back(i);
      const int a = i % e.width, r = i / e.width;
      g.a0 = std::min(g.a0, a), g.a1 = std::max(g.a1, a), g.r0 = std::min(g.r0, r), g.r1 = std::max(g.r1, r);
      g.recessed += e.look[size_t(i)] == kRecess;
      const int na[4] = {a - 1, a + 1, a, a}, nr[4] = {r, r, r - 1, r + 1};
      for (int k = 0; k < 4; ++k) {
        if (na[k] < 0 || nr[k] < 0 || na[k] >= e.width || nr[k] >= e.height) continue;
        const size_t j = size_t(nr[k]) * e.width + na[k];
        if (!done[j] && open(j)) done[j] = 1, stack.push_back(int(j));
      }
    }
    out.push_back(std::move(g));
  }
  return out;
}

// Rectangular: the region fills min_fill of its box, the box's hidden cells not counted.
bool Rectangular(const Elevation& e, const Region& g, const WallOpeningOptions& o) {
  int hidden = 0;
  for (int r = g.r0; r <= g.r1; ++r)
    for (int a = g.a0; a <= g.a1; ++a) hidden += e.look[size_t(r) * e.width + a] == kHidden;
  const int box = (g.a1 - g.a0 + 1) * (g.r1 - g.r0 + 1) - hidden;
  return box > 0 && double(g.cells.size()) >= o.min_fill * box;
}

// Framed by the wall: both jambs, the lintel, and (`sill`) the sill. Shares count the cells the scan saw (a sparse
// scan often misses the wall above a window), when it saw at least min_frame_seen_share of them. With
// `blank_lintel`, a lintel whose two rows show no face (unseen, missing or recessed cells only) passes too.
bool Framed(const Elevation& e, const Region& g, bool sill, bool blank_lintel, const WallOpeningOptions& o) {
  const int z0 = g.r0 + e.z_lo, z1 = g.r1 + e.z_lo;
  auto frame = [&](int a, int z) { const uint8_t l = e.at(a, z); return l == kFace || l == kHidden; };
  auto seen = [&](int a, int z) { return e.at(a, z) != kUnseen; };
  auto share = [&](int framed, int looked, int total) {
    return looked > 0 && looked >= o.min_frame_seen_share * total ? double(framed) / double(looked) : 0.0;
  };
  auto jamb = [&](int a_near, int step) {  // Rows with face within two cells beside the opening.
    int n = 0, s = 0;
    for (int z = z0; z <= z1; ++z) {
      n += frame(a_near, z) || frame(a_near + step, z);
      s += seen(a_near, z) || seen(a_near + step, z);
    }
    return share(n, s, z1 - z0 + 1);
  };
  auto across = [&](int z) {  // The row over the opening's width.
    int n = 0, s = 0;
    for (int a = g.a0; a <= g.a1; ++a) n += frame(a, z), s += seen(a, z);
    return share(n, s, g.a1 - g.a0 + 1);
  };
  auto blank = [&](int z) {  // No face (nor anything hiding it) over the opening's width.
    for (int a = g.a0; a <= g.a1; ++a)
      if (frame(a, z)) return false;
    return true;
  };
  return jamb(g.a0 - 1, -1) >= o.min_frame_share && jamb(g.a1 + 1, 1) >= o.min_frame_share &&
         (std::max(across(z1 + 1), across(z1 + 2)) >= o.min_frame_share || (blank_lintel && blank(z1 + 1) && blank(z1 + 2))) &&
         (!sill || std::max(across(z0 - 1), across(z0 - 2)) >= o.min_frame_share);
}

// The recessed cells' commonest depth (the pane's), and whether 0.8 (min_flat_share) of them lie within a cell of it.
std::pair<int, bool> PaneDepth(const Elevation& e, const Region& g, int recess, const WallOpeningOptions& o) {
  std::vector<int> count(size_t(recess) + 2, 0);  // Depths are at most recess.
  for (int i : g.cells)
    if (e.look[size_t(i)] == kRecess) ++count[size_t(e.depth[size_t(i)])];
  const int pane = int(std::max_element(count.begin(), count.end()) - count.begin());
  const int flat = count[size_t(pane)] + (pane > 0 ? count[size_t(pane - 1)] : 0) + count[size_t(pane + 1)];
  return {pane, double(flat) >= o.min_flat_share * g.recessed};
}

// The elevation with each face or recessed cell's depth replaced by the lower median of the depths of the face
// and recessed cells in its 3x3 neighbourhood (face as 0), where there are at least five, and a median of one
// cell taken as face: a fused cloud's wall face reads as face and one-cell recess mixed (point noise, spacing),
// and its pane as one to three cells deep.
Elevation Smoothed(const Elevation& e) {
  Elevation s = e;
  std::vector<int> v;
  for (int r = 0; r < e.height; ++r)
    for (int a = 0; a < e.width; ++a) {
      const size_t i = size_t(r) * e.width + a;
      if (e.look[i] != kFace && e.look[i] != kRecess) continue;
      v.clear();
      for (int dr = -1; dr <= 1; ++dr)
        for (int da = -1; da <= 1; ++da) {
          const int rr = r + dr, aa = a + da;
          if (rr < 0 || aa < 0 || rr >= e.height || aa >= e.width) continue;
          const size_t j = size_t(rr) * e.width + aa;
          if (e.look[j] == kFace) v.push_back(0);
          else if (e.look[j] == kRecess) v.push_back(e.depth[j]);
        }
      if (v.size() < 5) continue;
      std::nth_element(v.begin(), v.begin() + (v.size() - 1) / 2, v.end());
      const int m = v[(v.size() - 1) / 2];
      s.look[i] = m <= 1 ? kFace : kRecess;
      s.depth[i] = int8_t(m <= 1 ? 0 : m);
    }
  return s;
}

// The region without its ragged top and bottom: rows holding under half as many cells as its fullest row (a
// reveal's strip of recess beside a jamb, a sill's few cells) are cut off.
Region TrimRows(const Elevation& e, const Region& g) {
  std::vector<int> count(size_t(g.r1 - g.r0 + 1), 0);
  for (int i : g.cells) ++count[size_t(i / e.width - g.r0)];
  const int full = *std::max_element(count.begin(), count.end());
  int r0 = g.r0, r1 = g.r1;
  while (r0 < r1 && 2 * count[size_t(r0 - g.r0)] < full) ++r0;
  while (r1 > r0 && 2 * count[size_t(r1 - g.r0)] < full) --r1;
  Region t;
  t.a0 = e.width, t.r0 = r0, t.r1 = r1;
  for (int i : g.cells) {
    const int r = i / e.width, a = i % e.width;
    if (r < r0 || r > r1) continue;
    t.cells.push_back(i);
    t.a0 = std::min(t.a0, a), t.a1 = std::max(t.a1, a);
    t.recessed += e.look[size_t(i)] == kRecess;
  }
  return t;
}

// An open door's leaf in front of the wall: a thin panel at one jamb (the columns within a cell of either edge),
// occupied over half the door's height, running from the wall out into the room for at least 0.6 of the opening's
// width (the opening seen from the room is narrower by the leaf's own column) and then ending, the columns three
// cells to either side not occupied (a scanned leaf is up to three cells thick), and nothing much above it or
// within two cells of it (a wall meeting the doorway goes on up to the ceiling). Adds its voxels; false when there is none.
bool AddOpenLeaf(const WallAxes& w, int facing, int line, const Region& g, int z_lo, int z_hi, std::vector<uint32_t>* voxels) {
  const int z0 = g.r0 + z_lo, z1 = g.r1 + z_lo, length = g.a1 - g.a0 + 1, rows = z1 - z0 + 1;
  auto panel = [&](int a, int k) {  // Column (a, line + facing k) occupied over half the door's height.
    int n = 0;
    for (int z = z0; z <= z1; ++z) n += w.Occupied(a, line + facing * k, z);
    return 2 * n >= rows;
  };
  int best_a = -1, best = 0;
  for (int a : {g.a0 - 1, g.a0, g.a0 + 1, g.a1 - 1, g.a1, g.a1 + 1}) {
    int run = 0;
    while (run < length + 6 && panel(a, run + 1)) ++run;
    int flank = 0;
    for (int k = 1; k <= run; ++k) flank += panel(a - 3, k) + panel(a + 3, k);
    const bool ends = run < length + 6 && !panel(a, run + 2);
    // A leaf ends with the door; a wall at the jamb (a partition meeting the doorway, or a perpendicular wall
    // whose window pane looks like a leaf) goes on up: its column, or one within two cells, is occupied above.
    bool stops = true;
    for (int c = a - 2; c <= a + 2 && stops; ++c) {
      int above = 0, looked = 0;
      for (int k = 1; k <= run; ++k)
        for (int z = z1 + 3; z <= z_hi; ++z) above += w.Occupied(c, line + facing * k, z), ++looked;
      stops = c == a ? 10 * above <= 3 * looked : 2 * above <= looked;
    }
    if (ends && stops && 10 * run >= 6 * length && 10 * flank <= 3 * 2 * run && run > best) best = run, best_a = a;
  }
  if (best_a < 0) return false;
  for (int a = best_a - 1; a <= best_a + 1; ++a)
    for (int k = 1; k <= best + 1; ++k)
      for (int z = z0; z <= std::min(z1 + 1, z_hi); ++z)
        if (w.Occupied(a, line + facing * k, z)) voxels->push_back(uint32_t(w.Index(a, line + facing * k, z)));
  return true;
}

}  // namespace

std::vector<WallOpening> FindWallOpenings(const VoxelGrid& grid, double floor_z, double top_z, const WallOpeningOptions& o) {
  std::vector<WallOpening> out;
  const double res = grid.resolution();
  const auto& d = grid.dims();
  if (d[0] <= 0 || d[1] <= 0 || d[2] <= 0) return out;
  const double z_min = grid.MinCorner().z();
  auto cell_z = [&](double z) { return int(std::floor((z - z_min) / res)); };
  auto height_of = [&](int z) { return z_min + (z + 0.5) * res - floor_z; };  // Centre above the floor.
  const int z_lo = std::max(0, cell_z(floor_z) + 1);  // The first cell above the floor's.
  const int z_hi = std::min(d[2] - 1, int(std::floor((top_z - z_min) / res - 0.5)));
  if (z_hi - z_lo < 4) return out;
  const int band_lo = std::max(z_lo, cell_z(floor_z + 0.3)), band_hi = std::min(z_hi, cell_z(floor_z + 2.2));
  const int front = std::max(2, int(std::lround(o.front_m / res)));
  const int recess = std::clamp(int(std::lround(o.max_recess_m / res)), 1, 100);  // Depths fit in int8_t.
  const int hole = std::max(recess + 1, int(std::lround(o.hole_depth_m / res)));
  const int pane_slack = int(std::lround(o.pane_tolerance_m / res));
  const int behind = int(std::lround(o.pane_behind_m / res));
  const int min_face_cells = std::max(1, int(std::lround(o.min_face_m2 / (res * res))));
  for (int axis = 0; axis < 2; ++axis) {
    const WallAxes w{grid, axis};
    for (int facing : {1, -1})
      for (int line : WallLines(w, facing, band_lo, band_hi, min_face_cells)) {
        const Elevation e = LookAtWall(w, facing, line, z_lo, z_hi, front, recess, hole);
        // Three looks at the wall, the later ones only where the earlier found nothing:
        //  kPlain: regions of recessed and missing cells;
        //  kPaneOnly: a region of recessed cells alone, cut from a larger region of recessed and missing cells
        //    that was no opening: a window pane whose lintel the scan never saw joins the unseen wall above it.
        //    It can only be a window, and its lintel may be blank;
        //  kSmoothed: the regions of the Smoothed elevation: a fused cloud's noisy face joins every pane to the
        //    whole wall through its one-cell recesses.
        // The later two are trimmed of ragged rows. `te` is the elevation the region and its tests read; the
        // voxels are always taken from the scan's own first surfaces (`e`).
        enum Pass { kPlain, kPaneOnly, kSmoothed };
        auto accept = [&](const Region& region, Pass pass, const Elevation& te) {
          const bool pane_only = pass == kPaneOnly;
          const Region g = pass == kPlain ? region : TrimRows(te, region);
          if (g.cells.empty()) return false;
          const int z0 = g.r0 + e.z_lo, z1 = g.r1 + e.z_lo;
          const double width = (g.a1 - g.a0 + 1) * res, bottom = height_of(z0) - 0.5 * res, top = height_of(z1) + 0.5 * res;
          const bool door = !pane_only && bottom <= o.door_max_bottom_m && top >= o.door_min_top_m && top <= o.door_max_top_m &&
                            width >= o.door_min_width_m && width <= o.door_max_width_m;
          const bool window = !door && bottom >= o.window_min_bottom_m && top - bottom >= o.window_min_height_m &&
                              width >= o.window_min_width_m && width <= o.window_max_width_m;
          if ((!door && !window) || !Rectangular(te, g, o) || !Framed(te, g, window, pane_only, o)) return false;
          // A pane or a closed leaf is flat. An open doorway's few recessed cells are whatever the next room
          // holds: no test, and none of them are its voxels.
          const auto [pane_depth, flat] = PaneDepth(te, g, recess, o);
          if (g.mostly_recessed() && !flat) return false;
          WallOpening op;
          op.nyu40 = door ? nyu40::kDoor : nyu40::kWindow;
          op.axis = axis, op.facing = facing, op.line = line;
          op.along0 = g.a0, op.along1 = g.a1, op.z0 = z0, op.z1 = z1;
          // The pane or closed leaf: the first surface of each recessed cell at the pane's depth (or
          // pane_tolerance in front: shallower first surfaces are the sill's top and the reveals, the wall's),
          // and the cells up to pane_behind_m behind it.
          if (window || g.mostly_recessed())
            for (int i : g.cells) {
              if (e.look[size_t(i)] != kRecess || e.depth[size_t(i)] < pane_depth - pane_slack) continue;
              const int a = i % e.width, z = i / e.width + e.z_lo, k = -int(e.depth[size_t(i)]);
              for (int kk = k; kk >= k - behind; --kk)
                if (w.Occupied(a, line + facing * kk, z)) op.voxels.push_back(uint32_t(w.Index(a, line + facing * kk, z)));
            }
          // A smoothed window whose cells hold no first surface at its pane's depth is the median's, not the scan's.
          if (pass == kSmoothed && window && op.voxels.empty()) return false;
          if (door) op.open_leaf = AddOpenLeaf(w, facing, line, g, e.z_lo, z_hi, &op.voxels);
          std::sort(op.voxels.begin(), op.voxels.end());
          op.voxels.erase(std::unique(op.voxels.begin(), op.voxels.end()), op.voxels.end());
          out.push_back(std::move(op));
          return true;
        };
        std::vector<uint8_t> taken(e.look.size(), 0);  // Cells of the openings found.
        // Cells of rejected regions that mix recessed and missing cells, a tenth of them or more missing (a
        // recessed surface with a few holes is a wall seen past something standing in front of it, not glass).
        std::vector<uint8_t> retry(e.look.size(), 0);
        for (const Region& g : OpeningRegions(e, false)) {
          if (accept(g, kPlain, e)) {
            for (int i : g.cells) taken[size_t(i)] = 1;
          } else if (g.recessed > 0 && 10 * (int(g.cells.size()) - g.recessed) >= int(g.cells.size())) {
            for (int i : g.cells) retry[size_t(i)] = 1;
          }
        }
        for (const Region& g : OpeningRegions(e, true))
          if (retry[size_t(g.cells.front())] && g.cells.size() >= 2 && accept(g, kPaneOnly, e))
            for (int i : g.cells) taken[size_t(i)] = 1;
        const Elevation smooth = Smoothed(e);
        for (const Region& g : OpeningRegions(smooth, false)) {
          bool free = g.cells.size() >= 2;
          for (size_t k = 0; k < g.cells.size() && free; ++k) free = !taken[size_t(g.cells[k])];
          if (free) accept(g, kSmoothed, smooth);
        }
      }
  }
  return out;
}

}  // namespace semvox
