#include "rooms/room_segmentation.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <map>
#include <numeric>
#include <sstream>

namespace semvox {
namespace {

// The part of the plan the segmentation works on, cropped to the bounding box of the room space.
struct Workspace {
  cv::Rect roi;            // In plan pixels.
  cv::Mat1b space;         // 255: free, door or (fill_clutter) clutter.
  cv::Mat1b door;          // 255: door cells.
  cv::Mat1i label;         // Room label per space cell, 0 = none.
};

Workspace MakeWorkspace(const FloorPlan& plan, bool fill_clutter) {
  const int W = plan.width(), H = plan.height();
  int x0 = W, y0 = H, x1 = -1, y1 = -1;
  auto in_space = [&](int x, int y) {
    const FloorCell c = plan.at(x, y);
    return c == FloorCell::kFree || c == FloorCell::kDoor || (fill_clutter && c == FloorCell::kClutter);
  };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if (in_space(x, y)) x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  Workspace ws;
  if (x1 < 0) return ws;
  // One pixel of margin so that the distance transform sees obstacles around the border.
  x0 = std::max(0, x0 - 1), y0 = std::max(0, y0 - 1), x1 = std::min(W - 1, x1 + 1), y1 = std::min(H - 1, y1 + 1);
  ws.roi = cv::Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1);
  ws.space = cv::Mat1b(ws.roi.height, ws.roi.width, uchar(0));
  ws.door = cv::Mat1b(ws.roi.height, ws.roi.width, uchar(0));
  ws.label = cv::Mat1i(ws.roi.height, ws.roi.width, 0);
  for (int y = 0; y < ws.roi.height; ++y)
    for (int x = 0; x < ws.roi.width; ++x) {
      const int px = x + x0, py = y + y0;
      if (px == 0 || py == 0 || px == W - 1 || py == H - 1) continue;  // Keep a closed border.
      if (in_space(px, py)) ws.space(y, x) = 255;
      if (plan.at(px, py) == FloorCell::kDoor) ws.door(y, x) = 255;
    }
  return ws;
}

// 8-neighbour offsets; a diagonal step is allowed only when one of the two cells beside it is space, so
// regions never leak through a one-pixel diagonal wall.
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};

inline bool Step(const cv::Mat1b& space, int x, int y, int k, int* nx, int* ny) {
  *nx = x + kDx[k], *ny = y + kDy[k];
  if (*nx < 0 || *ny < 0 || *nx >= space.cols || *ny >= space.rows || !space(*ny, *nx)) return false;
  if (k >= 4 && !space(y, *nx) && !space(*ny, x)) return false;
  return true;
}

struct UnionFind {
  std::vector<int> parent;
  int Add() {
    parent.push_back(int(parent.size()));
    return int(parent.size()) - 1;
  }
  int Find(int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
};

// Floods the room space from the maxima of `dist` downwards (a watershed by union-find): a cell joins
// the basins of its processed neighbours; where basins meet, `keep_apart(a, b, level)` decides whether
// they stay separate (the cell then joins the basin with the higher peak). Leaves basin labels in
// ws->label.
struct Basin {
  float peak = 0;    // Highest value of `dist` in the basin.
  int64_t area = 0;  // Cells flooded so far (the basin's area above the current level).
};
template <typename KeepApart>
void Flood(const cv::Mat1f& dist, KeepApart keep_apart, Workspace* ws) {
  const int W = ws->space.cols, H = ws->space.rows;
  // Space cells in order of decreasing distance (counting sort on 1/8 px steps).
  constexpr float kBucketsPerPixel = 8.f;
  double max_d = 0;
  cv::minMaxLoc(dist, nullptr, &max_d);
  const int num_buckets = int(max_d * kBucketsPerPixel) + 2;
  auto bucket = [&](int x, int y) { return num_buckets - 1 - int(dist(y, x) * kBucketsPerPixel); };
  std::vector<int> start(num_buckets + 1, 0);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if (ws->space(y, x)) ++start[bucket(x, y) + 1];
  for (int b = 0; b < num_buckets; ++b) start[b + 1] += start[b];
  std::vector<int> order(start[num_buckets]);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if (ws->space(y, x)) order[start[bucket(x, y)]++] = y * W + x;

  UnionFind uf;
  std::vector<Basin> basin;
  int* label = ws->label.ptr<int>(0);  // Basin index + 1 while flooding.
  for (int p : order) {
    const int x = p % W, y = p / W;
    const float d = dist(y, x);
    int roots[8], n = 0;
    for (int k = 0; k < 8; ++k) {
      int nx, ny;
      if (!Step(ws->space, x, y, k, &nx, &ny)) continue;
      const int l = label[ny * W + nx];
      if (!l) continue;
      const int r = uf.Find(l - 1);
      if (std::find(roots, roots + n, r) == roots + n) roots[n++] = r;
    }
    if (n == 0) {
      const int r = uf.Add();
      basin.push_back({d, 1});
      label[p] = r + 1;
      continue;
    }
    for (int i = 1; i < n; ++i)  // Highest peak first (insertion sort of at most 8).
      for (int j = i; j > 0 && basin[roots[j]].peak > basin[roots[j - 1]].peak; --j) std::swap(roots[j], roots[j - 1]);
    const int main = roots[0];
    for (int i = 1; i < n; ++i)
      if (!keep_apart(basin[main], basin[roots[i]], d, p)) {
        uf.parent[roots[i]] = main;
        basin[main].area += basin[roots[i]].area;
      }
    ++basin[main].area;
    label[p] = main + 1;
  }
  for (int i = 0; i < W * H; ++i)
    if (label[i]) label[i] = uf.Find(label[i] - 1) + 1;
}

// Distance-transform watershed with doorway-aware merging (see the header).
// Wall-gap lines: the end of a thin wall (at most max_wall_px thick, running on for at least
// min_wall_px behind its tip) whose straight continuation meets another obstacle within max_gap_px
// across free space marks that gap as a doorway (door cells), as a drawn floor plan closes a room.
cv::Mat1f WallGapLines(double res, double max_gap_m, const Workspace& ws0) {
  const Workspace* ws = &ws0;
  const int W = ws->space.cols, H = ws->space.rows;
  const int max_gap_px = int(max_gap_m / res), max_wall_px = std::max(1, int(0.3 / res)),
            min_wall_px = std::max(2, int(0.3 / res));
  auto obstacle = [&](int x, int y) { return x < 0 || y < 0 || x >= W || y >= H || !ws->space(y, x); };
  cv::Mat1f lines(H, W, 0.f);  // Half the length of the line through the cell, pixels; 0 = none.
  constexpr int kDirX[4] = {1, -1, 0, 0}, kDirY[4] = {0, 0, 1, -1};
  for (int y = 1; y + 1 < H; ++y)
    for (int x = 1; x + 1 < W; ++x) {
      if (!obstacle(x, y)) continue;
      for (int k = 0; k < 4; ++k) {
        const int dx = kDirX[k], dy = kDirY[k], px = -dy, py = dx;  // Direction and its perpendicular.
        if (obstacle(x + dx, y + dy)) continue;                     // Not a tip in this direction.
        bool wall_behind = true;
        for (int i = 1; i <= min_wall_px && wall_behind; ++i) wall_behind = obstacle(x - i * dx, y - i * dy);
        if (!wall_behind) continue;
        // Thin: free space on both sides of the tip within max_wall_px.
        auto side_free = [&](int sign) {
          for (int j = 1; j <= max_wall_px; ++j)
            if (!obstacle(x + sign * j * px, y + sign * j * py)) return true;
          return false;
        };
        if (!side_free(1) || !side_free(-1)) continue;
        int m = 1;
        while (m <= max_gap_px && !obstacle(x + m * dx, y + m * dy)) ++m;
        if (m > max_gap_px) continue;
        for (int i = 1; i < m; ++i) {
          float& v = lines(y + i * dy, x + i * dx);
          v = v > 0 ? std::min(v, 0.5f * m) : 0.5f * m;
        }
      }
    }
  return lines;
}

void SegmentByDistance(const RoomSegmentationOptions& o, double res, Workspace* ws) {
  cv::Mat1b inner = ws->space & ~ws->door;
  cv::Mat1f dist;
  cv::distanceTransform(inner, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  // Wall-gap lines are passes of (almost) zero height (the flood reaches them just before the door openings);
  // whether the rooms on their two sides stay apart depends on the line's half length against the smaller
  // room's inscribed radius.
  cv::Mat1f lines(dist.rows, dist.cols, 0.f);
  if (o.wall_gap_max_m > 0) {
    lines = WallGapLines(res, o.wall_gap_max_m, *ws);
    // Half a cell: below every free cell (at least one cell from an obstacle) and above the door openings
    // (0), which are flooded last. A door's rooms then meet at the door, where the door rule decides, not at
    // a line the flood reached through the door's cells.
    dist.setTo(0.5f, (lines > 0) & (ws->door == 0));
  }
  const float door_half_px = float(0.5 * o.max_opening_width_m / res);
  const float min_radius_px = float(o.min_room_radius_m / res);
  const float door_min_radius_px = float(std::min(o.door_min_room_radius_m, o.min_room_radius_m) / res);
  const float ratio = float(o.saddle_ratio), ratio_larger = float(o.saddle_ratio_larger);
  const float line_ratio = float(o.wall_gap_ratio);
  const float* line_half = lines.ptr<float>(0);
  // Door openings and the cells within kDoorZoneM of them: the pass or a wall-gap line through the doorway
  // may run a cell or two beside the lintel's cells (a sparse scan sees a lintel in patches).
  constexpr double kDoorZoneM = 0.15;
  const int zone_px = std::max(1, int(std::lround(kDoorZoneM / res)));
  cv::Mat1b door_zone;
  cv::dilate(ws->door, door_zone, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * zone_px + 1, 2 * zone_px + 1)));
  const uchar* door = door_zone.ptr<uchar>(0);
  Flood(dist,
        [&](const Basin& a, const Basin& b, float d, int p) {  // a.peak >= b.peak; d: the pass at cell p.
          // A door opening (under a lintel) is a room border whatever else the pass looks like: the rooms
          // stay apart when the smaller is room-sized, and a closet or WC behind a door is room-sized down to
          // door_min_room_radius_m. A wall-gap line through a door does not decide.
          if (door[p]) return b.peak >= door_min_radius_px;
          if (b.peak < min_radius_px) return false;
          if (line_half[p] > 0) return line_half[p] < line_ratio * b.peak;
          return d <= door_half_px && (d < ratio * b.peak || d < ratio_larger * a.peak);
        },
        ws);
}

// Morphological segmentation (after Bormann et al. 2016, Sec. III-A): erosion with a 3x3 square k
// times keeps the cells whose chessboard distance to an obstacle exceeds k, so flooding the chessboard
// distance downwards replays the erosion backwards. Two parts that the erosion separates stay separate
// rooms when both still cover min_seed_area_m2 at the level where they separate; the rest merge. The
// seeds then grow back over the space level by level, which is the watershed growth.
void SegmentByErosion(const RoomSegmentationOptions& o, double res, Workspace* ws) {
  cv::Mat1b inner = ws->space & ~ws->door;
  cv::Mat1f dist;
  cv::distanceTransform(inner, dist, cv::DIST_C, 3);
  const int64_t min_seed_px = int64_t(std::ceil(o.min_seed_area_m2 / (res * res)));
  Flood(dist, [&](const Basin& a, const Basin& b, float, int) { return std::min(a.area, b.area) >= min_seed_px; }, ws);
}

// Merges rooms smaller than min_px into the neighbour with the longest shared border; rooms without a
// neighbour that are still too small are dropped (set to 0). Returns labels 1..K in raster order.
int MergeSmallRooms(int min_px, Workspace* ws) {
  const int W = ws->label.cols, H = ws->label.rows;
  int* label = ws->label.ptr<int>(0);
  // Compact labels.
  std::map<int, int> remap;
  for (int i = 0; i < W * H; ++i)
    if (label[i]) {
      auto it = remap.emplace(label[i], int(remap.size()) + 1).first;
      label[i] = it->second;
    }
  const int n = int(remap.size());
  std::vector<int64_t> area(n + 1, 0);
  std::map<std::pair<int, int>, int> border;  // (a < b) -> shared 4-neighbour edges.
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int a = label[y * W + x];
      if (!a) continue;
      ++area[a];
      if (x + 1 < W && label[y * W + x + 1] && label[y * W + x + 1] != a)
        ++border[{std::min(a, label[y * W + x + 1]), std::max(a, label[y * W + x + 1])}];
      if (y + 1 < H && label[(y + 1) * W + x] && label[(y + 1) * W + x] != a)
        ++border[{std::min(a, label[(y + 1) * W + x]), std::max(a, label[(y + 1) * W + x])}];
    }
  std::vector<int> parent(n + 1);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  std::vector<std::map<int, int>> adj(n + 1);
  for (const auto& [k, c] : border) adj[k.first][k.second] += c, adj[k.second][k.first] += c;
  // Smallest first; a merged room may still be small and is revisited.
  std::vector<uint8_t> dropped(n + 1, 0);
  while (true) {
    int smallest = 0;
    for (int a = 1; a <= n; ++a)
      if (find(a) == a && !dropped[a] && area[a] < min_px && (!smallest || area[a] < area[smallest])) smallest = a;
    if (!smallest) break;
    int best = 0, best_len = 0;
    for (const auto& [b, len] : adj[smallest])
      if (len > best_len) best = b, best_len = len;
    if (!best) {
      dropped[smallest] = 1;
      continue;
    }
    // Merge smallest into best.
    parent[smallest] = best;
    area[best] += area[smallest];
    for (const auto& [b, len] : adj[smallest]) {
      adj[b].erase(smallest);
      if (b != best) adj[b][best] += len, adj[best][b] += len;
    }
    adj[best].erase(smallest);
    adj[smallest].clear();
  }
  std::vector<int> final_id(n + 1, 0);
  int k = 0;
  for (int i = 0; i < W * H; ++i) {
    if (!label[i]) continue;
    const int r = find(label[i]);
    if (dropped[r]) {
      label[i] = 0;
      continue;
    }
    if (!final_id[r]) final_id[r] = ++k;
    label[i] = final_id[r];
  }
  return k;
}

}  // namespace

const char* RoomSegmentationMethodName(RoomSegmentationMethod method) {
  switch (method) {
    case RoomSegmentationMethod::kDistanceWatershed: return "distance";
    case RoomSegmentationMethod::kMorphological: return "morphological";
  }
  return "?";
}

std::vector<std::string> RoomSegmentationMethodNames() { return {"distance", "morphological"}; }

bool ParseRoomSegmentationMethod(const std::string& name, RoomSegmentationMethod* method) {
  for (RoomSegmentationMethod m : {RoomSegmentationMethod::kDistanceWatershed, RoomSegmentationMethod::kMorphological})
    if (name == RoomSegmentationMethodName(m)) return *method = m, true;
  return false;
}

bool RoomSegmentationOptions::Check(std::string* error) const { return CheckOptions(*this, Options(), error); }

RoomSegmentation SegmentRooms(const FloorPlan& plan, const RoomSegmentationOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  RoomSegmentation out;
  const int W = plan.width(), H = plan.height();
  out.room_ids = ImageU16(W, H, 1, 0);
  out.room_extent_ids = ImageU16(W, H, 1, 0);
  Workspace ws = MakeWorkspace(plan, options.fill_clutter);
  const double res = plan.resolution_m;
  if (!ws.space.empty()) {
    if (options.method == RoomSegmentationMethod::kMorphological) SegmentByErosion(options, res, &ws);
    else SegmentByDistance(options, res, &ws);
    const int min_px = int(std::ceil(options.min_room_area_m2 / (res * res)));
    out.num_rooms = std::min(MergeSmallRooms(min_px, &ws), 65535);

    // Floor cells left without a room (specks cut off by furniture) join the nearest room nearby.
    const int w = ws.roi.width, h = ws.roi.height;
    cv::Mat1b unlabelled(h, w, uchar(255));
    std::vector<int> room_of_seed(1, 0);  // DIST_LABEL_PIXEL numbers zero pixels in raster order from 1.
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (ws.label(y, x)) unlabelled(y, x) = 0, room_of_seed.push_back(ws.label(y, x));
    if (room_of_seed.size() > 1) {
      cv::Mat1f dist;
      cv::Mat1i nearest;
      cv::distanceTransform(unlabelled, dist, nearest, cv::DIST_L2, cv::DIST_MASK_5, cv::DIST_LABEL_PIXEL);
      const float max_px = float(options.max_speck_distance_m / res);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const FloorCell c = plan.at(x + ws.roi.x, y + ws.roi.y);
          const bool floor = c == FloorCell::kFree || c == FloorCell::kDoor;
          if (!ws.label(y, x) && floor && dist(y, x) <= max_px) ws.label(y, x) = room_of_seed[nearest(y, x)];
        }
    }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int id = std::min(ws.label(y, x), 65535);
        if (!id) continue;
        const int px = x + ws.roi.x, py = y + ws.roi.y;
        const FloorCell c = plan.at(px, py);
        if (c == FloorCell::kFree || c == FloorCell::kDoor || c == FloorCell::kClutter) out.room_extent_ids.at(px, py) = id;
        if (c == FloorCell::kFree || c == FloorCell::kDoor) out.room_ids.at(px, py) = id;
      }
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

size_t JoinEnclosedUnknown(const FloorPlan& plan, double max_area_m2, ImageU16* extent_ids, ImageU16* pixel_types) {
  const int W = plan.width(), H = plan.height();
  if (max_area_m2 <= 0 || extent_ids->width != W || extent_ids->height != H) return 0;
  const bool typed = pixel_types && pixel_types->width == W && pixel_types->height == H;
  const double cell = plan.resolution_m * plan.resolution_m;
  const size_t max_cells = size_t(std::floor(max_area_m2 / cell + 1e-9));
  std::vector<uint8_t> seen(size_t(W) * size_t(H), 0);
  std::vector<int> pocket, stack;
  size_t joined = 0;
  for (int s = 0; s < W * H; ++s) {
    if (seen[size_t(s)] || FloorCell(plan.cells.data[size_t(s)]) != FloorCell::kUnknown) continue;
    pocket.clear();
    stack.assign(1, s);
    seen[size_t(s)] = 1;
    // A wall's unseen inside, reached through a window or a gap in its face, is a strip one or two cells wide;
    // a pocket of floor holds a cell whose four neighbours are all unknown, i.e. in the pocket.
    bool enclosed = true, thick = false;
    int room = 0, room_cell = -1;
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      pocket.push_back(i);
      const int x = i % W, y = i / W;
      if (x == 0 || y == 0 || x == W - 1 || y == H - 1) enclosed = false;
      const int nbr[4][2] = {{x + 1, y}, {x - 1, y}, {x, y + 1}, {x, y - 1}};
      int unknown_neighbours = 0;
      for (const auto& n : nbr) {
        if (n[0] < 0 || n[1] < 0 || n[0] >= W || n[1] >= H) continue;
        const int q = n[1] * W + n[0];
        const FloorCell c = FloorCell(plan.cells.data[size_t(q)]);
        if (c == FloorCell::kUnknown) {
          ++unknown_neighbours;
          if (!seen[size_t(q)]) seen[size_t(q)] = 1, stack.push_back(q);
        } else if (c != FloorCell::kWall) {
          const int r = extent_ids->data[size_t(q)];
          if (r == 0 || (room != 0 && r != room)) enclosed = false;
          else if (room == 0) room = r, room_cell = q;
        }
      }
      thick = thick || unknown_neighbours == 4;
    }
    if (!enclosed || !thick || room == 0 || pocket.size() > max_cells) continue;
    for (int i : pocket) {
      extent_ids->data[size_t(i)] = uint16_t(room);
      if (typed) pixel_types->data[size_t(i)] = pixel_types->data[size_t(room_cell)];
    }
    joined += pocket.size();
  }
  return joined;
}

}  // namespace semvox
