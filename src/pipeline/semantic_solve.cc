#include "pipeline/semantic_solve.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

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

// The labels of the labelled 26 neighbours of cell c that `usable` accepts (ApplyFloorSurface).
template <class Usable>
std::vector<int> NeighbourLabels(const VoxelGrid& grid, const SemanticMap& map, const std::array<int, 3>& c, const Usable& usable) {
  std::vector<int> around;
  ForEachNeighbour(grid, map, c, [&](const SemanticVoxelRecord& r) {
    if (usable(int(r.label))) around.push_back(r.label);
  });
  return around;
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
