#include "pipeline/semantic_solve.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <unordered_set>

#include <tbb/parallel_for.h>

#include "core/labels.h"
#include "core/majority.h"
#include "core/log.h"
#include "objects/object_segments.h"
#include "objects/other_labels.h"

namespace semvox {

Status SolveSemantic(const VoxelMap& map, const SemanticEvidence& evidence, const VoxelCrfModel& model,
                     const VoxelCrfOptions& options, SemanticLabels* labels) {
  const auto t0 = std::chrono::steady_clock::now();
  SemanticLabels& s = *labels;
  SEMVOX_RETURN_IF_ERROR(SolveVoxelCrf(map.grid, evidence.nodes, evidence.voxels, map.floor_z, map.ceiling_z, model, options, &s.crf));
  s.map = MakeSemanticMap(map.grid, evidence.nodes, evidence.voxels, s.crf, model);
  s.refined = s.map.RefinedGrid(map.grid, evidence.nodes);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  SEMVOX_INFO("voxel CRF: " << s.map.occupied.size() << " occupied voxels labelled (" << s.map.completed_count()
                            << " completed), " << s.crf.num_planes << " planes, " << s.crf.num_object_cliques
                            << " object cliques, " << s.crf.iterations.size() << " iterations, " << s.seconds << " s");
  return Status::Ok();
}

namespace {

// The building's own labels: wall, floor, ceiling, door and window. Every other label is an object's.
bool StructureLabel(int label) {
  return label == nyu40::kWall || label == nyu40::kFloor || label == nyu40::kCeiling || label == nyu40::kDoor ||
         label == nyu40::kWindow;
}

}  // namespace

void ApplyOtherLabels(const VoxelMap& map, const SemanticEvidence& evidence, const VoxelCrfModel& model,
                      const OtherLabeller& labeller, int min_voxels, SemanticLabels* labels) {
  const auto t0 = std::chrono::steady_clock::now();
  labels->other_segments = 0;
  labels->other_voxels = 0;
  int other_id = -1;
  for (int k = 0; k < model.num_classes(); ++k)
    if (model.class_names[size_t(k)] == "other") other_id = model.nyu40_of_class[size_t(k)];
  if (!evidence.segmentation || other_id <= 0) return;
  const SegmentationResult& seg = *evidence.segmentation;
  // Each segment's "other" voxels and their features (in parallel: the k-NN search), then the labels in
  // segment order.
  std::vector<std::vector<SemanticVoxelRecord*>> mine(seg.segments.size());
  std::vector<int> id(seg.segments.size(), 0);
  tbb::parallel_for(size_t(0), seg.segments.size(), [&](size_t i) {
    std::vector<uint32_t> voxels;
    for (uint32_t v : seg.segments[i].voxels)
      if (SemanticVoxelRecord* r = labels->map.Find(v); r && r->label == other_id) mine[i].push_back(r), voxels.push_back(v);
    if (int(voxels.size()) < min_voxels) return;
    const OtherFeatureVector f = OtherFeatures(map.grid, seg, seg.segments[i], voxels);
    id[i] = labeller.Label({f.data(), f.size()});
  });
  for (size_t i = 0; i < seg.segments.size(); ++i) {
    if (id[i] <= 0) continue;
    for (SemanticVoxelRecord* r : mine[i]) r->label = uint16_t(id[i]);
    ++labels->other_segments;
    labels->other_voxels += mine[i].size();
  }
  labels->seconds_other = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  SEMVOX_INFO("other labels: " << labels->other_voxels << " voxels of " << labels->other_segments << " segments labelled by shape, "
                               << labels->seconds_other << " s");
}

void ApplyItemLabels(const VoxelMap& map, const SemanticEvidence& evidence, const ItemLabeller& labeller, int min_voxels,
                     SemanticLabels* labels) {
  const auto t0 = std::chrono::steady_clock::now();
  labels->item_groups = 0;
  labels->item_voxels = 0;
  if (!evidence.segmentation) return;
  const SegmentationResult& seg = *evidence.segmentation;
  // Each segment's items and their ids (in parallel: the k-NN searches), then the labels in segment order.
  std::vector<std::vector<std::vector<uint32_t>>> items(seg.segments.size());
  std::vector<std::vector<int>> ids(seg.segments.size());
  tbb::parallel_for(size_t(0), seg.segments.size(), [&](size_t i) {
    items[i] = ItemsOnTop(map.grid, seg, seg.segments[i], min_voxels);
    for (const std::vector<uint32_t>& group : items[i]) {
      const OtherFeatureVector f = OtherFeatures(map.grid, seg, seg.segments[i], group);
      ids[i].push_back(labeller.Label({f.data(), f.size()}));
    }
  });
  for (size_t i = 0; i < seg.segments.size(); ++i)
    for (size_t g = 0; g < items[i].size(); ++g) {
      if (ids[i][g] <= 0) continue;
      ++labels->item_groups;
      for (uint32_t v : items[i][g]) {
        SemanticVoxelRecord* it = labels->map.Find(v);
        if (!it) continue;
        const int l = it->label;
        if (StructureLabel(l) || l == ids[i][g]) continue;
        it->label = uint16_t(ids[i][g]);
        ++labels->item_voxels;
      }
    }
  labels->seconds_items = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  SEMVOX_INFO("item labels: " << labels->item_groups << " items on top of furniture, " << labels->item_voxels << " voxels relabelled, "
                              << labels->seconds_items << " s");
}

namespace {

// Calls visit(record) for each labelled voxel among the 26 neighbours of cell c.
template <class Visit>
void ForEachNeighbour(const VoxelGrid& grid, const SemanticMap& map, const std::array<int, 3>& c, const Visit& visit) {
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx | dy | dz) == 0 || !grid.Contains(c[0] + dx, c[1] + dy, c[2] + dz)) continue;
        if (const SemanticVoxelRecord* r = map.Find(uint32_t(grid.Index(c[0] + dx, c[1] + dy, c[2] + dz)))) visit(*r);
      }
}

// Whether cell c lies on the span of a door or window found in the walls, or within kWallUnitOpeningMarginCells of
// it (its frame), and two cells more across the wall (a fused cloud's wall band is up to four cells thick).
bool FramesOpening(const std::vector<WallOpening>& openings, const std::array<int, 3>& c) {
  constexpr int m = kWallUnitOpeningMarginCells;
  for (const WallOpening& o : openings) {
    const int along = o.axis == 0 ? c[0] : c[1], across = o.axis == 0 ? c[1] : c[0];
    if (along >= o.along0 - m && along <= o.along1 + m && std::abs(across - o.line) <= m + 2 && c[2] >= o.z0 - m && c[2] <= o.z1 + m)
      return true;
  }
  return false;
}

// A part's lowest and highest layer, its footprint (cells), and whether it lies on a door's or window's span.
struct PartExtent {
  int zlo = std::numeric_limits<int>::max(), zhi = std::numeric_limits<int>::min();
  size_t columns = 0;
  bool frames_opening = false;
};

PartExtent MeasurePart(const VoxelGrid& grid, const std::vector<WallOpening>& openings, const std::vector<uint32_t>& part) {
  PartExtent e;
  std::unordered_set<size_t> columns;
  for (uint32_t u : part) {
    const auto c = grid.Cell(u);
    e.zlo = std::min(e.zlo, c[2]), e.zhi = std::max(e.zhi, c[2]);
    e.frames_opening = e.frames_opening || FramesOpening(openings, c);
    columns.insert(size_t(c[1]) * size_t(grid.dims()[0]) + size_t(c[0]));
  }
  e.columns = columns.size();
  return e;
}

// The 26-connected parts of `members` (labelled voxels), each in the order a search from its first voxel in the
// map's order reaches them; parts in that order too.
std::vector<std::vector<uint32_t>> ConnectedParts(const VoxelGrid& grid, const SemanticMap& map,
                                                  const std::unordered_set<uint32_t>& members) {
  std::vector<std::vector<uint32_t>> parts;
  std::unordered_set<uint32_t> done;
  for (const SemanticVoxelRecord& v0 : map.occupied) {
    if (!members.count(v0.voxel) || !done.insert(v0.voxel).second) continue;
    std::vector<uint32_t> part{v0.voxel};
    for (size_t i = 0; i < part.size(); ++i)
      ForEachNeighbour(grid, map, grid.Cell(part[i]), [&](const SemanticVoxelRecord& r) {
        if (members.count(r.voxel) && done.insert(r.voxel).second) part.push_back(r.voxel);
      });
    parts.push_back(std::move(part));
  }
  return parts;
}

// The labels of the labelled 26 neighbours of cell c that `usable` accepts (ApplyFloorSurface, ApplyWallMargin).
template <class Usable>
std::vector<int> NeighbourLabels(const VoxelGrid& grid, const SemanticMap& map, const std::array<int, 3>& c, const Usable& usable) {
  std::vector<int> around;
  ForEachNeighbour(grid, map, c, [&](const SemanticVoxelRecord& r) {
    if (usable(int(r.label))) around.push_back(r.label);
  });
  return around;
}

// Per-channel median of colours gathered channel by channel (each channel non-empty); reorders them.
std::array<uint8_t, 3> MedianColour(std::array<std::vector<uint8_t>, 3>* channels) {
  std::array<uint8_t, 3> m{};
  for (size_t k = 0; k < 3; ++k) {
    std::vector<uint8_t>& c = (*channels)[k];
    std::nth_element(c.begin(), c.begin() + ptrdiff_t(c.size() / 2), c.end());
    m[k] = c[c.size() / 2];
  }
  return m;
}

// The per-channel median colour of voxel v and those of its 26 neighbours that `keep` accepts (v itself whether or
// not it does); `channels` is scratch space.
template <class Keep>
std::array<uint8_t, 3> NeighbourhoodMedianColour(const VoxelGrid& grid, const SemanticMap& map, const SemanticVoxelRecord& v,
                                                 const Keep& keep, std::array<std::vector<uint8_t>, 3>* channels) {
  for (auto& ch : *channels) ch.clear();
  auto add = [&](const SemanticVoxelRecord& r) {
    for (size_t k = 0; k < 3; ++k) (*channels)[k].push_back(r.rgb[k]);
  };
  add(v);
  ForEachNeighbour(grid, map, grid.Cell(v.voxel), [&](const SemanticVoxelRecord& r) {
    if (keep(r)) add(r);
  });
  return MedianColour(channels);
}

// Euclidean distance of two RGB colours (0-441).
double ColourDistance(const std::array<uint8_t, 3>& a, const std::array<uint8_t, 3>& b) {
  double d = 0;
  for (size_t k = 0; k < 3; ++k) d += double(int(a[k]) - int(b[k])) * double(int(a[k]) - int(b[k]));
  return std::sqrt(d);
}

}  // namespace

void ApplyFloorSurface(const VoxelMap& map, double margin_m, SemanticLabels* labels) {
  const VoxelGrid& grid = map.grid;
  const double res = grid.resolution();
  auto usable = [](int label) { return label != 0 && label != nyu40::kFloor && label != nyu40::kCeiling; };
  // The label of what stands on voxel c: the first usable of the two voxels above it, else the most frequent
  // usable label of its 26 neighbours (the smallest id on a tie), else 0.
  auto standing_label = [&](const std::array<int, 3>& c) {
    for (int dz = 1; dz <= 2; ++dz) {
      if (!grid.Contains(c[0], c[1], c[2] + dz)) continue;
      const SemanticVoxelRecord* r = labels->map.Find(uint32_t(grid.Index(c[0], c[1], c[2] + dz)));
      if (r && usable(int(r->label))) return int(r->label);
    }
    std::vector<int> around = NeighbourLabels(grid, labels->map, c, usable);
    return around.empty() ? 0 : Majority(&around);
  };
  std::vector<uint32_t> lifted;  // Floor voxels wholly above the floor's surface, visited top down.
  for (const SemanticVoxelRecord& v : labels->map.occupied)
    if (v.label == nyu40::kFloor && double(v.centre.z()) - 0.5 * res >= map.floor_z + margin_m) lifted.push_back(v.voxel);
  std::stable_sort(lifted.begin(), lifted.end(), [&](uint32_t a, uint32_t b) { return grid.Cell(a)[2] > grid.Cell(b)[2]; });
  labels->floor_surface_voxels = 0;
  for (uint32_t voxel : lifted)
    if (const int label = standing_label(grid.Cell(voxel))) {
      labels->map.Find(voxel)->label = uint16_t(label);
      ++labels->floor_surface_voxels;
    }
  SEMVOX_INFO("floor surface: " << labels->floor_surface_voxels << " of " << lifted.size() << " floor voxels "
                                << margin_m << " m or more above the floor relabelled");
}

void ApplyFurnitureFeet(const VoxelMap& map, SemanticLabels* labels) {
  const VoxelGrid& grid = map.grid;
  std::vector<std::pair<uint32_t, uint16_t>> changes;  // Decided on the labels before this step.
  for (const SemanticVoxelRecord& v : labels->map.occupied) {
    if (v.label != nyu40::kFloor || double(v.centre.z()) <= map.floor_z) continue;
    const auto c = grid.Cell(v.voxel);
    if (!grid.Contains(c[0], c[1], c[2] + 1)) continue;
    const SemanticVoxelRecord* up = labels->map.Find(uint32_t(grid.Index(c[0], c[1], c[2] + 1)));
    if (up && up->label != 0 && !StructureLabel(up->label)) changes.emplace_back(v.voxel, up->label);
  }
  for (const auto& [voxel, label] : changes) labels->map.Find(voxel)->label = label;
  labels->furniture_feet_voxels = changes.size();
  SEMVOX_INFO("furniture feet: " << changes.size() << " floor voxels under furniture relabelled");
}

void ApplyWallMargin(const VoxelMap& map, const SegmentationResult& segmentation, int min_neighbours, SemanticLabels* labels) {
  const VoxelGrid& grid = map.grid;
  const auto& d = grid.dims();
  labels->wall_margin_voxels = 0;
  if (segmentation.wall_margin.size() != size_t(d[0]) * size_t(d[1])) return;
  auto usable = [](int label) { return label != 0 && label != nyu40::kWall && label != nyu40::kFloor && label != nyu40::kCeiling; };
  std::vector<std::pair<uint32_t, uint16_t>> changes;  // Decided on the labels before this step.
  for (const SemanticVoxelRecord& v : labels->map.occupied) {
    if (v.label != nyu40::kWall) continue;
    const auto c = grid.Cell(v.voxel);
    if (!segmentation.wall_margin[size_t(c[1]) * size_t(d[0]) + size_t(c[0])]) continue;
    const std::vector<int> around = NeighbourLabels(grid, labels->map, c, usable);
    if (int(around.size()) < min_neighbours) continue;
    std::vector<int> votes = around;
    const int label = Majority(&votes);
    if (std::count(around.begin(), around.end(), label) >= min_neighbours) changes.emplace_back(v.voxel, uint16_t(label));
  }
  for (const auto& [voxel, label] : changes) labels->map.Find(voxel)->label = label;
  labels->wall_margin_voxels = changes.size();
  SEMVOX_INFO("wall margin: " << changes.size() << " wall voxels beside objects relabelled");
}

void ApplyWallColour(const VoxelMap& map, double min_distance, int rings, SemanticLabels* labels) {
  const VoxelGrid& grid = map.grid;
  labels->wall_colour_voxels = 0;
  // A completed voxel was never seen: its colour is borrowed from a neighbour of its label (MakeSemanticMap).
  auto coloured = [](const SemanticVoxelRecord& v) { return v.completed == 0; };
  std::array<std::vector<uint8_t>, 3> channels;
  for (const SemanticVoxelRecord& v : labels->map.occupied)
    if (v.label == nyu40::kWall && coloured(v))
      for (int k = 0; k < 3; ++k) channels[size_t(k)].push_back(v.rgb[size_t(k)]);
  if (channels[0].empty()) return;
  labels->wall_colour = MedianColour(&channels);
  auto usable = [](int label) { return label != 0 && label != nyu40::kWall && label != nyu40::kFloor && label != nyu40::kCeiling; };
  for (int ring = 0; ring < rings; ++ring) {
    std::vector<std::pair<uint32_t, uint16_t>> changes;  // Decided on the labels before this ring.
    for (const SemanticVoxelRecord& v : labels->map.occupied) {
      if (v.label != nyu40::kWall || !coloured(v)) continue;
      const double off_wall = ColourDistance(v.rgb, labels->wall_colour);
      if (off_wall < min_distance) continue;
      const auto c = grid.Cell(v.voxel);
      double best = off_wall;
      int label = 0;
      ForEachNeighbour(grid, labels->map, c, [&](const SemanticVoxelRecord& r) {
        if (!usable(int(r.label)) || !coloured(r)) return;
        const double d = ColourDistance(v.rgb, r.rgb);
        if (d < best || (d == best && label != 0 && int(r.label) < label)) best = d, label = int(r.label);
      });
      if (label != 0) changes.emplace_back(v.voxel, uint16_t(label));
    }
    if (changes.empty()) break;
    for (const auto& [voxel, label] : changes) labels->map.Find(voxel)->label = label;
    labels->wall_colour_voxels += changes.size();
  }
  SEMVOX_INFO("wall colour: " << labels->wall_colour_voxels << " wall voxels off the walls' colour relabelled");
}

bool WoodColour(const std::array<int, 3>& rgb, int min_chroma) {
  const int r = rgb[0], g = rgb[1], b = rgb[2];
  if (!(r >= g && g >= b) || r - b < min_chroma) return false;
  const double hue = 60.0 * double(g - b) / double(r - b);  // Degrees; red 0, yellow 60.
  return hue >= kWoodHueMinDeg && hue <= kWoodHueMaxDeg;
}

void ApplyRefrigeratorColour(const VoxelMap& map, int min_chroma, SemanticLabels* labels) {
  const VoxelGrid& grid = map.grid;
  labels->refrigerator_colour_voxels = 0;
  auto fridge = [](const SemanticVoxelRecord& v) { return v.label == nyu40::kRefrigerator && v.completed == 0; };
  std::vector<uint32_t> changes;  // Decided on the labels before this step.
  std::array<std::vector<uint8_t>, 3> channels;
  for (const SemanticVoxelRecord& v : labels->map.occupied) {
    if (!fridge(v)) continue;
    const std::array<uint8_t, 3> m = NeighbourhoodMedianColour(grid, labels->map, v, fridge, &channels);
    if (WoodColour({m[0], m[1], m[2]}, min_chroma)) changes.push_back(v.voxel);
  }
  for (uint32_t voxel : changes) labels->map.Find(voxel)->label = uint16_t(nyu40::kCabinet);
  labels->refrigerator_colour_voxels = changes.size();
  SEMVOX_INFO("refrigerator colour: " << changes.size() << " wood-coloured refrigerator voxels relabelled cabinet");
}

void ApplyDoorsInDoorways(const VoxelMap& map, const SegmentationResult* segmentation, SemanticLabels* labels) {
  labels->doorless_segments = 0;
  labels->doorless_voxels = 0;
  const VoxelGrid& grid = map.grid;
  const double res = grid.resolution();
  std::vector<const WallOpening*> doors;
  for (const WallOpening& o : labels->openings)
    if (o.nyu40 == nyu40::kDoor) doors.push_back(&o);
  if (doors.empty() || !segmentation) return;
  // Horizontal distance (metres) from column (x, y) to a doorway's span on its wall's face.
  auto distance = [&](const WallOpening& o, int x, int y) {
    const int along = o.axis == 0 ? x : y, across = o.axis == 0 ? y : x;
    const int off_along = along < o.along0 ? o.along0 - along : along > o.along1 ? along - o.along1 : 0;
    return res * std::hypot(double(off_along), double(across - o.line));
  };
  std::vector<uint32_t> door_voxels;
  for (const ObjectSegment& s : segmentation->segments) {
    door_voxels.clear();
    for (uint32_t v : s.voxels) {
      const SemanticVoxelRecord* r = labels->map.Find(v);
      if (r && r->label == nyu40::kDoor) door_voxels.push_back(v);
    }
    if (int(door_voxels.size()) < kDoorlessMinVoxels) continue;
    bool in_doorway = false;
    for (const WallOpening* o : doors) {
      const double reach = o->width_m(res) + kDoorwayReachMarginM;
      for (uint32_t v : door_voxels) {
        const auto c = grid.Cell(v);
        if (distance(*o, c[0], c[1]) <= reach) {
          in_doorway = true;
          break;
        }
      }
      if (in_doorway) break;
    }
    if (in_doorway) continue;
    const int label = s.features[kSegThickness] <= kDoorlessThinMaxM ? nyu40::kCurtain : nyu40::kCabinet;
    for (uint32_t v : door_voxels) labels->map.Find(v)->label = uint16_t(label);
    ++labels->doorless_segments;
    labels->doorless_voxels += door_voxels.size();
  }
  SEMVOX_INFO("doors in doorways: " << labels->doorless_voxels << " door voxels of " << labels->doorless_segments
                                    << " segments away from every doorway relabelled");
}

void ApplyWallOpenings(const VoxelMap& map, const WallOpeningOptions& options, SemanticLabels* labels) {
  const auto t0 = std::chrono::steady_clock::now();
  const VoxelGrid& grid = map.grid;
  // Up to the ceiling's underside, or the scan's top.
  const int top_cell = grid.TopOccupiedLayer();
  const double top_z = map.ceiling_found ? map.ceiling_z - 0.1 : top_cell >= 0 ? grid.CellCenter(0, 0, top_cell).z() : map.floor_z;
  labels->openings = FindWallOpenings(grid, map.floor_z, top_z, options);
  labels->opening_voxels = 0;
  for (const WallOpening& o : labels->openings) {
    // A pane or closed leaf is part of the wall's surface: only voxels the CRF took for wall (or the other
    // opening class) change. An open leaf stands free, so it changes whatever it was taken for.
    for (uint32_t v : o.voxels) {
      SemanticVoxelRecord* it = labels->map.Find(v);
      if (!it || it->label == o.nyu40) continue;
      const bool structural = it->label == nyu40::kWall || it->label == nyu40::kDoor || it->label == nyu40::kWindow;
      if (!structural && !(o.open_leaf && it->label != nyu40::kFloor && it->label != nyu40::kCeiling)) continue;
      it->label = uint16_t(o.nyu40);
      ++labels->opening_voxels;
    }
  }
  labels->seconds_openings = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  int doors = 0;
  for (const WallOpening& o : labels->openings) doors += o.nyu40 == nyu40::kDoor;
  SEMVOX_INFO("wall openings: " << doors << " doors, " << labels->openings.size() - size_t(doors) << " windows, "
                                << labels->opening_voxels << " voxels relabelled, " << labels->seconds_openings << " s");
}

void ApplyTallObjectWalls(const SemanticEvidence& evidence, const VoxelCrfModel& model, SemanticLabels* labels) {
  labels->tall_object_wall_segments = 0;
  labels->tall_object_wall_voxels = 0;
  const SegmentationResult* seg = evidence.segmentation.get();
  const int K = model.num_classes();
  if (!seg || K <= 0 || evidence.voxels.segment.size() != evidence.nodes.size() * size_t(K)) return;
  for (const ObjectSegment& s : seg->segments) {
    if (s.features[kSegTopSurface] < kTallObjectMinTopM || s.features[kSegCeilingGap] < kTallObjectMinCeilingGapM) continue;
    // Every node of a segment carries the segment's probabilities (after the pipeline's adjustments).
    int32_t node = -1;
    for (uint32_t v : s.voxels)
      if ((node = evidence.nodes.node_of_voxel[v]) >= 0) break;
    if (node < 0) continue;
    const float* p = &evidence.voxels.segment[size_t(node) * size_t(K)];
    const int k = int(std::max_element(p, p + K) - p);
    const int id = model.nyu40_of_class[size_t(k)];
    if (p[k] < kTallObjectMinProbability || id <= 0 || StructureLabel(id) || model.class_names[size_t(k)] == "other")
      continue;
    size_t n = 0;
    for (uint32_t v : s.voxels) {
      SemanticVoxelRecord* r = labels->map.Find(v);
      if (r && r->label == nyu40::kWall) r->label = uint16_t(id), ++n;
    }
    labels->tall_object_wall_voxels += n;
    labels->tall_object_wall_segments += n > 0;
  }
  SEMVOX_INFO("tall object walls: " << labels->tall_object_wall_voxels << " wall voxels of " << labels->tall_object_wall_segments
                                    << " tall object segments relabelled");
}

void ApplyWoodenWallUnits(const VoxelMap& map, SemanticLabels* labels) {
  labels->wall_unit_components = 0;
  labels->wall_unit_voxels = 0;
  const VoxelGrid& grid = map.grid;
  const double res = grid.resolution();
  auto wall = [](const SemanticVoxelRecord& v) { return v.label == nyu40::kWall && v.completed == 0; };
  // Wall voxels in wood's colour: the per-channel median over the voxel and its 26 neighbours labelled wall.
  std::unordered_set<uint32_t> wood;
  std::array<std::vector<uint8_t>, 3> channels;
  for (const SemanticVoxelRecord& v : labels->map.occupied) {
    if (!wall(v)) continue;
    const std::array<uint8_t, 3> m = NeighbourhoodMedianColour(grid, labels->map, v, wall, &channels);
    if (WoodColour({m[0], m[1], m[2]}, kWallUnitWoodChroma)) wood.insert(v.voxel);
  }
  std::vector<uint32_t> changes;
  // The 26-connected parts of wood-coloured wall voxels.
  for (const std::vector<uint32_t>& comp : ConnectedParts(grid, labels->map, wood)) {
    if (int(comp.size()) < kWallUnitMinVoxels) continue;
    const PartExtent e = MeasurePart(grid, labels->openings, comp);
    // Hung on the wall, no taller than a wall unit, and no door's or window's frame.
    const double bottom = grid.CellCenter(0, 0, e.zlo).z() - map.floor_z, height = (e.zhi - e.zlo + 1) * res;
    if (bottom < kWallUnitMinBottomM || height > kWallUnitMaxHeightM || e.frames_opening) continue;
    // Another colour than the wall around it (the wall voxels not in wood's colour within two cells): a wall painted
    // in a wood tone, its light parts split from its shaded ones, is its own colour around them.
    std::array<std::vector<uint8_t>, 3> in, around;
    std::unordered_set<uint32_t> seen;
    for (uint32_t u : comp) {
      const SemanticVoxelRecord* r = labels->map.Find(u);
      for (size_t k = 0; k < 3; ++k) in[k].push_back(r->rgb[k]);
      const auto c = grid.Cell(u);
      for (int dz = -2; dz <= 2; ++dz)
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            if (!grid.Contains(c[0] + dx, c[1] + dy, c[2] + dz)) continue;
            const uint32_t w = uint32_t(grid.Index(c[0] + dx, c[1] + dy, c[2] + dz));
            const SemanticVoxelRecord* q = labels->map.Find(w);
            if (!q || !wall(*q) || wood.count(w) || !seen.insert(w).second) continue;
            for (size_t k = 0; k < 3; ++k) around[k].push_back(q->rgb[k]);
          }
    }
    if (int(around[0].size()) < kWallUnitMinAroundVoxels) continue;  // No wall around to tell it from.
    if (ColourDistance(MedianColour(&in), MedianColour(&around)) < kWallUnitMinContrast) continue;
    changes.insert(changes.end(), comp.begin(), comp.end());
    ++labels->wall_unit_components;
  }
  for (uint32_t u : changes) labels->map.Find(u)->label = uint16_t(nyu40::kCabinet);
  labels->wall_unit_voxels = changes.size();
  SEMVOX_INFO("wooden wall units: " << changes.size() << " wall voxels of " << labels->wall_unit_components
                                    << " hung wood-coloured parts relabelled cabinet");
}

void ApplyHungWallCabinets(const VoxelMap& map, SemanticLabels* labels) {
  labels->hung_wall_components = 0;
  labels->hung_wall_voxels = 0;
  const VoxelGrid& grid = map.grid;
  const double res = grid.resolution();
  const int gap = std::max(1, int(std::lround(kHungMinGapM / res)));
  auto wall_at = [&](int x, int y, int z) {
    if (!grid.Contains(x, y, z)) return false;
    const SemanticVoxelRecord* r = labels->map.Find(uint32_t(grid.Index(x, y, z)));
    return r && r->label == nyu40::kWall;
  };
  // The voxels that hang: under their run of wall voxels, `gap` cells unoccupied, half of them or more seen free.
  std::unordered_set<uint32_t> hung;
  for (const SemanticVoxelRecord& v : labels->map.occupied) {
    if (v.label != nyu40::kWall || v.completed) continue;
    const auto c = grid.Cell(v.voxel);
    int z = c[2];
    while (wall_at(c[0], c[1], z - 1)) --z;
    int free = 0;
    bool open = true;
    for (int k = 1; k <= gap && open; ++k) {
      if (!grid.Contains(c[0], c[1], z - k)) open = false;
      else if (labels->map.Find(uint32_t(grid.Index(c[0], c[1], z - k)))) open = false;
      else free += grid.state(grid.Index(c[0], c[1], z - k)) == VoxelState::kFree;
    }
    if (open && 2 * free >= gap) hung.insert(v.voxel);
  }
  std::vector<uint32_t> changes;
  for (const std::vector<uint32_t>& part : ConnectedParts(grid, labels->map, hung)) {
    if (int(part.size()) < kHungMinVoxels) continue;
    const PartExtent e = MeasurePart(grid, labels->openings, part);
    const double bottom = grid.CellCenter(0, 0, e.zlo).z() - 0.5 * res - map.floor_z, height = (e.zhi - e.zlo + 1) * res;
    if (bottom < kHungMinBottomM || bottom > kHungMaxBottomM || height > kHungMaxHeightM || e.frames_opening) continue;
    // Its footprint: a cabinet is deep, a strip of wall is not.
    if (double(e.columns) * res * res < kHungMinFootprintM2) continue;
    changes.insert(changes.end(), part.begin(), part.end());
    ++labels->hung_wall_components;
  }
  for (uint32_t u : changes) labels->map.Find(u)->label = uint16_t(nyu40::kCabinet);
  labels->hung_wall_voxels = changes.size();
  SEMVOX_INFO("hung wall cabinets: " << changes.size() << " wall voxels of " << labels->hung_wall_components
                                     << " parts hung over free space relabelled cabinet");
}

void ApplyBarTables(const VoxelMap& map, const SegmentationResult* segmentation, SemanticLabels* labels) {
  labels->bar_table_segments = 0;
  labels->bar_table_voxels = 0;
  if (!segmentation) return;
  for (const ObjectSegment& s : segmentation->segments) {
    if (s.features[kSegTopSurface] < kBarMinTopM || s.features[kSegWallDistance] < kBarMinWallDistanceM) continue;
    // The segment's counter voxels, and the counter voxels joined to them (the Voxel-CRF's reach past the segment).
    std::vector<uint32_t> bar;
    for (uint32_t v : s.voxels) {
      SemanticVoxelRecord* r = labels->map.Find(v);
      if (r && r->label == nyu40::kCounter) r->label = nyu40::kTable, bar.push_back(v);
    }
    for (size_t i = 0; i < bar.size(); ++i)
      ForEachNeighbour(map.grid, labels->map, map.grid.Cell(bar[i]), [&](const SemanticVoxelRecord& r) {
        if (r.label != nyu40::kCounter) return;
        labels->map.Find(r.voxel)->label = nyu40::kTable;
        bar.push_back(r.voxel);
      });
    labels->bar_table_voxels += bar.size();
    labels->bar_table_segments += !bar.empty();
  }
  SEMVOX_INFO("bar tables: " << labels->bar_table_voxels << " counter voxels of " << labels->bar_table_segments
                             << " free-standing counter-height segments relabelled table");
}

}  // namespace semvox
