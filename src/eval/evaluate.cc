#include "eval/evaluate.h"

#include <nlohmann/json.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <optional>
#include <set>
#include <sstream>

#include "core/file_util.h"
#include "core/labels.h"
#include "core/ply.h"
#include "eval/score_json.h"
#include "core/voxel_key.h"
#include "io/image_io.h"

namespace semvox {
namespace fs = std::filesystem;

namespace {

// Separating-axis test of a triangle against an axis-aligned box centred at the origin with half size h
// (Akenine-Möller, "Fast 3D triangle-box overlap testing", 2001), as the mapping stage's voxeliser uses.
bool TriangleOverlapsBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& h) {
  const Eigen::Vector3d e[3] = {b - a, c - b, a - c};
  for (int i = 0; i < 3; ++i)
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d l = Eigen::Vector3d::Unit(axis).cross(e[i]);
      const double p0 = l.dot(a), p1 = l.dot(b), p2 = l.dot(c);
      const double r = h.x() * std::fabs(l.x()) + h.y() * std::fabs(l.y()) + h.z() * std::fabs(l.z());
      if (std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r) return false;
    }
  for (int axis = 0; axis < 3; ++axis)
    if (std::min({a[axis], b[axis], c[axis]}) > h[axis] || std::max({a[axis], b[axis], c[axis]}) < -h[axis]) return false;
  const Eigen::Vector3d n = e[0].cross(e[1]);
  const double r = h.x() * std::fabs(n.x()) + h.y() * std::fabs(n.y()) + h.z() * std::fabs(n.z());
  return std::fabs(n.dot(a)) <= r;
}

double Ratio(size_t num, size_t den) { return den ? double(num) / double(den) : 0.0; }

Score Present(double v, std::string note = "") { return Score{true, v, std::move(note)}; }
Score Absent(std::string why) { return Score{false, 0.0, std::move(why)}; }

// Value of `img` (on `grid`) at world (x, y); `outside` when the point is off the image.
int Sample(const ImageU16& img, const FloorGrid& grid, double x, double y, int outside = 0) {
  int c, r;
  if (!grid.PixelOf(x, y, &c, &r) || c >= img.width || r >= img.height) return outside;
  return img.at(c, r);
}

FloorGrid GridOf(const OccupancyMap& m) {
  FloorGrid g;
  g.resolution = m.resolution;
  g.origin_x = m.origin_x;
  g.origin_y = m.origin_y;
  g.width = m.image.width;
  g.height = m.image.height;
  return g;
}

}  // namespace

VoxelLabels VoxelizeLabeledMesh(const Mesh& mesh, double res) {
  const auto it = mesh.face_attributes.find("label");
  // Half-open cells as in mapping/voxelizer.cc: a surface on a cell boundary belongs to the cell above it.
  const double eps = 1e-4 * res;
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5 * res);
  std::vector<std::pair<uint64_t, int>> hits;
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    const int label = it == mesh.face_attributes.end() ? 0 : it->second[f];
    const Eigen::Vector3d a = mesh.vertices[size_t(mesh.faces[f][0])].cast<double>(),
                          b = mesh.vertices[size_t(mesh.faces[f][1])].cast<double>(),
                          c = mesh.vertices[size_t(mesh.faces[f][2])].cast<double>();
    if ((b - a).cross(c - a).squaredNorm() <= 0.0) continue;
    const Eigen::Vector3d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    int64_t klo[3], khi[3];
    for (int d = 0; d < 3; ++d) {
      klo[d] = CoordToKeyIndex(lo[d] + eps, res);
      khi[d] = CoordToKeyIndex(hi[d] + eps, res);
    }
    for (int64_t kz = klo[2]; kz <= khi[2]; ++kz)
      for (int64_t ky = klo[1]; ky <= khi[1]; ++ky)
        for (int64_t kx = klo[0]; kx <= khi[0]; ++kx) {
          if (!KeyIndexInRange(kx) || !KeyIndexInRange(ky) || !KeyIndexInRange(kz)) continue;
          const Eigen::Vector3d centre(KeyIndexToCoord(kx, res) - eps, KeyIndexToCoord(ky, res) - eps, KeyIndexToCoord(kz, res) - eps);
          if (!TriangleOverlapsBox(a - centre, b - centre, c - centre, half)) continue;
          hits.emplace_back(VoxelKey{uint16_t(kx), uint16_t(ky), uint16_t(kz)}.Pack(), label);
        }
  }
  std::sort(hits.begin(), hits.end());
  VoxelLabels out;
  for (size_t i = 0; i < hits.size();) {
    size_t j = i;
    int best_label = hits[i].second, best_count = 0;
    while (j < hits.size() && hits[j].first == hits[i].first) {
      size_t k = j;
      while (k < hits.size() && hits[k].first == hits[i].first && hits[k].second == hits[j].second) ++k;
      if (int(k - j) > best_count) best_count = int(k - j), best_label = hits[j].second;  // Ascending labels: ties keep the lower.
      j = k;
    }
    out[hits[i].first] = best_label;
    i = j;
  }
  return out;
}

namespace {

// label -> (correct, total) and (ground truth, other predicted label) -> count, as ClassRecall rows.
std::map<int, ClassRecall> PerClass(const std::map<int, std::pair<size_t, size_t>>& counts,
                                    const std::map<std::pair<int, int>, size_t>& confusion) {
  std::map<int, ClassRecall> out;
  for (const auto& [label, ct] : counts) out[label].count = ct.second, out[label].correct = ct.first;
  for (const auto& [gp, n] : confusion) out[gp.first].confusions.push_back({gp.second, n});
  for (auto& [label, row] : out) {
    // Most pixels first; ascending labels among equals (the map's order, kept by the stable sort).
    std::stable_sort(row.confusions.begin(), row.confusions.end(), [](const auto& x, const auto& y) { return x.second > y.second; });
    if (row.confusions.size() > 3) row.confusions.resize(3);
    if (!row.confusions.empty()) row.most_confused_with = row.confusions.front().first;
  }
  return out;
}

}  // namespace

ImageU16 TopViewFromVoxels(const std::vector<Eigen::Vector3f>& centres, const std::vector<int>& labels,
                           const FloorGrid& grid, double z_lo, double z_hi) {
  ImageU16 img(grid.width, grid.height, 1, 0);
  std::vector<float> top(size_t(grid.width) * grid.height, -1e30f);
  for (size_t i = 0; i < centres.size(); ++i) {
    const Eigen::Vector3f& p = centres[i];
    if (p.z() < z_lo || p.z() >= z_hi) continue;
    int c, r;
    if (!grid.PixelOf(p.x(), p.y(), &c, &r)) continue;
    float& t = top[size_t(r) * grid.width + c];
    if (p.z() > t) t = p.z(), img.at(c, r) = uint16_t(std::clamp(labels[i], 0, 65535));
  }
  return img;
}

TopViewScores ScoreTopView(const ImageU16& gt_topview, const ImageU16& gt_rooms, const FloorGrid& grid,
                           const OccupancyMap* occ, const ImageU16* pred_topview) {
  TopViewScores s;
  FloorGrid occ_grid;
  if (occ) occ_grid = GridOf(*occ);
  size_t n = 0, geo_ok = 0, unknown = 0, sem_ok = 0;
  if (occ) s.geometric_diff = ImageRgb8(grid.width, grid.height, 3, 230);
  std::map<int, std::pair<size_t, size_t>> per_class;  // label -> (correct, total)
  std::map<std::pair<int, int>, size_t> confusion;      // (ground truth, predicted other label) -> pixels
  for (int r = 0; r < grid.height; ++r)
    for (int c = 0; c < grid.width; ++c) {
      const int g = gt_topview.at(c, r);
      if (g == 0 && gt_rooms.at(c, r) == 0) continue;  // Outside the apartment.
      if (g == kTopViewHidden) continue;                // Inside a solid no scanner sees: not scored.
      ++n;
      const double x = grid.CenterX(c), y = grid.CenterY(r);
      if (occ) {
        int oc, orow;
        int v = kPgmUnknown;
        if (occ_grid.PixelOf(x, y, &oc, &orow)) v = occ->image.at(oc, orow);
        unknown += v != kPgmOccupied && v != kPgmFree;
        geo_ok += (v == kPgmOccupied) == (g != 0);
        const bool po = v == kPgmOccupied, go = g != 0;
        const Rgb8 col = po && go ? Rgb8{0, 0, 0} : !po && !go ? Rgb8{255, 255, 255} : go ? Rgb8{220, 40, 40} : Rgb8{40, 80, 220};
        s.geometric_diff.at(c, r, 0) = col.r, s.geometric_diff.at(c, r, 1) = col.g, s.geometric_diff.at(c, r, 2) = col.b;
      }
      if (pred_topview) {
        const int p = pred_topview->at(c, r);
        auto& pc = per_class[g];
        ++pc.second;
        if (p == g) ++pc.first, ++sem_ok;
        else ++confusion[{g, p}];
      }
    }
  s.pixels = n;
  if (n == 0) {
    s.geometric_accuracy = s.semantic_accuracy = s.semantic_global = Absent("empty ground-truth footprint");
    return s;
  }
  s.geometric_accuracy = occ ? Present(Ratio(geo_ok, n)) : Absent("occupancy.pgm/.yaml not found");
  s.predicted_unknown = occ ? Ratio(unknown, n) : 0.0;
  if (pred_topview) {
    double sum = 0;
    for (const auto& [label, ct] : per_class) sum += Ratio(ct.first, ct.second);
    s.per_class = PerClass(per_class, confusion);
    s.semantic_accuracy = Present(sum / double(per_class.size()), std::to_string(per_class.size()) + " classes");
    s.semantic_global = Present(Ratio(sem_ok, n));
  } else {
    s.semantic_accuracy = s.semantic_global = Absent("voxels.ply not found");
  }
  return s;
}

VoxelScores ScoreVoxels(const VoxelLabels& gt, const VoxelLabels& pred) {
  VoxelScores s;
  s.gt_voxels = gt.size();
  std::map<int, size_t> tp, gt_count, pred_count;
  std::map<std::pair<int, int>, size_t> confusion;
  size_t correct = 0, visible = 0;
  size_t n4_tp[5] = {0, 0, 0, 0, 0}, n4_gt[5] = {0, 0, 0, 0, 0}, n4_ok = 0;
  const auto& labels = Nyu40Labels();
  auto nyu4 = [&](int l) { return l > 0 && l < kNumNyu40 ? labels[size_t(l)].nyu4_id : 0; };
  // Deterministic order is not needed for sums of integers.
  for (const auto& [key, g] : gt) {
    const auto it = pred.find(key);
    if (it == pred.end()) continue;
    const int p = it->second;
    ++visible;
    ++gt_count[g];
    ++pred_count[p];
    if (p == g) ++tp[g], ++correct;
    else ++confusion[{g, p}];
    const int g4 = nyu4(g), p4 = nyu4(p);
    ++n4_gt[g4];
    if (g4 == p4) ++n4_tp[g4], ++n4_ok;
  }
  s.visible = visible;
  if (visible == 0) {
    s.accuracy = s.mean_recall = s.mean_iou = s.nyu4_average = s.nyu4_global = Absent("no visible voxel (prediction and ground truth share no voxel)");
    for (auto& r : s.nyu4_recall) r = Absent("no visible voxel");
    return s;
  }
  double iou_sum = 0, recall_sum = 0;
  std::map<int, std::pair<size_t, size_t>> counts;
  for (const auto& [c, n] : gt_count) {
    const size_t t = tp.count(c) ? tp[c] : 0;
    const double iou = double(t) / double(n + (pred_count.count(c) ? pred_count[c] : 0) - t);
    s.iou_per_class[c] = iou;
    iou_sum += iou;
    recall_sum += Ratio(t, n);
    counts[c] = {t, n};
  }
  s.per_class = PerClass(counts, confusion);
  const std::string on = std::to_string(visible) + " of " + std::to_string(gt.size()) + " ground-truth voxels";
  s.accuracy = Present(Ratio(correct, visible), on);
  s.mean_recall = Present(recall_sum / double(gt_count.size()), std::to_string(gt_count.size()) + " classes");
  s.mean_iou = Present(iou_sum / double(gt_count.size()), std::to_string(gt_count.size()) + " classes");
  double avg = 0;
  int present = 0;
  for (int k = 1; k <= 4; ++k) {
    if (n4_gt[k] == 0) {
      s.nyu4_recall[k - 1] = Absent("class not in the visible ground truth");
      continue;
    }
    s.nyu4_recall[k - 1] = Present(Ratio(n4_tp[k], n4_gt[k]));
    avg += s.nyu4_recall[k - 1].value;
    ++present;
  }
  s.nyu4_average = present ? Present(avg / present) : Absent("no NYU-4 class present");
  s.nyu4_global = Present(Ratio(n4_ok, visible));
  return s;
}

RoomSegmentationScores ScoreRoomSegmentation(const ImageU16& gt_rooms, const FloorGrid& gt_grid,
                                             const ImageU16& pred_rooms, const FloorGrid& pred_grid) {
  RoomSegmentationScores s;
  std::map<int, double> gt_area, pred_area;
  std::map<std::pair<int, int>, double> overlap;  // (pred, gt) -> m²
  const double ga = gt_grid.resolution * gt_grid.resolution, pa = pred_grid.resolution * pred_grid.resolution;
  for (int r = 0; r < gt_rooms.height; ++r)
    for (int c = 0; c < gt_rooms.width; ++c)
      if (const int g = gt_rooms.at(c, r)) gt_area[g] += ga;
  for (int r = 0; r < pred_rooms.height; ++r)
    for (int c = 0; c < pred_rooms.width; ++c) {
      const int p = pred_rooms.at(c, r);
      if (!p) continue;
      pred_area[p] += pa;
      if (const int g = Sample(gt_rooms, gt_grid, pred_grid.CenterX(c), pred_grid.CenterY(r))) overlap[{p, g}] += pa;
    }
  s.gt_rooms = int(gt_area.size());
  s.predicted_rooms = int(pred_area.size());
  if (gt_area.empty()) {
    s.recall = s.precision = Absent("no ground-truth room");
    return s;
  }
  double recall = 0, precision = 0;
  for (const auto& [g, area] : gt_area) {
    double best = 0;
    for (const auto& [p, parea] : pred_area) {
      const auto it = overlap.find({p, g});
      if (it != overlap.end()) best = std::max(best, it->second);
    }
    recall += best / area;
  }
  for (const auto& [p, area] : pred_area) {
    double best = 0;
    for (const auto& [g, garea] : gt_area) {
      const auto it = overlap.find({p, g});
      if (it != overlap.end()) best = std::max(best, it->second);
    }
    precision += best / area;
  }
  s.recall = Present(recall / double(gt_area.size()), std::to_string(gt_area.size()) + " ground-truth rooms");
  s.precision = pred_area.empty() ? Absent("no predicted room")
                                  : Present(precision / double(pred_area.size()), std::to_string(pred_area.size()) + " predicted rooms");
  return s;
}

RoomTypeScores ScoreRoomTypes(const ImageU16& gt_rooms, const FloorGrid& gt_grid, const std::map<int, int>& gt_types,
                              const ImageU16& pred_rooms, const FloorGrid& pred_grid, const std::map<int, int>& pred_types) {
  RoomTypeScores s;
  std::map<int, std::pair<size_t, size_t>> per_type;  // type -> (correct, total)
  size_t n = 0, ok = 0;
  auto type_of = [](const std::map<int, int>& m, int id) {
    const auto it = m.find(id);
    return it == m.end() ? 0 : it->second;
  };
  for (int r = 0; r < gt_rooms.height; ++r)
    for (int c = 0; c < gt_rooms.width; ++c) {
      const int g = gt_rooms.at(c, r);
      if (!g) continue;
      const int gt = type_of(gt_types, g);
      if (gt == 0) continue;  // Untyped in the ground truth: nothing to score.
      const int p = Sample(pred_rooms, pred_grid, gt_grid.CenterX(c), gt_grid.CenterY(r));
      const int pt = p ? type_of(pred_types, p) : 0;
      ++n;
      ++s.confusion_pixels[gt][pt];
      auto& e = per_type[gt];
      ++e.second;
      if (pt == gt) ++e.first, ++ok;
    }
  if (n == 0) {
    s.global = s.average = Absent("no ground-truth room pixel");
    return s;
  }
  double sum = 0;
  for (const auto& [t, e] : per_type) {
    s.recall_per_type[t] = Ratio(e.first, e.second);
    sum += s.recall_per_type[t];
  }
  s.global = Present(Ratio(ok, n), std::to_string(n) + " pixels");
  s.average = Present(sum / double(per_type.size()), std::to_string(per_type.size()) + " types");
  return s;
}

namespace {

Result<Mesh> ReadLabeledMesh(const std::string& path) {
  Result<PlyData> ply = ReadPly(path);
  if (!ply.ok()) return ply.status();
  const PlyElement* v = ply->Find("vertex");
  const PlyElement* f = ply->Find("face");
  const PlyProperty *x = v ? v->Find("x") : nullptr, *y = v ? v->Find("y") : nullptr, *z = v ? v->Find("z") : nullptr;
  const PlyProperty* idx = f ? f->Find("vertex_indices") : nullptr;
  const PlyProperty* label = f ? f->Find("label") : nullptr;
  if (!x || !y || !z || !idx || !label)
    return Status::InvalidInput(FileError(path, "expected a labelled mesh (vertex x, y, z; face vertex_indices, label)",
                                          "regenerate the ground truth with `semvox generate --seed N`"));
  Mesh m;
  for (size_t i = 0; i < v->count; ++i) m.vertices.emplace_back(float(x->values[i]), float(y->values[i]), float(z->values[i]));
  auto& labels = m.face_attributes["label"];
  for (size_t i = 0; i < f->count; ++i) {
    const uint32_t b = idx->list_offsets[i], e = idx->list_offsets[i + 1];
    for (uint32_t k = b + 1; k + 1 < e; ++k) {  // Fan-triangulate polygons.
      const Eigen::Vector3i t(int(idx->list_values[b]), int(idx->list_values[k]), int(idx->list_values[k + 1]));
      if ((t.array() < 0).any() || (t.array() >= int(v->count)).any())
        return Status::InvalidInput(FileError(path, "face index out of range", "the mesh file is corrupt"));
      m.faces.push_back(t);
      labels.push_back(int(label->values[i]));
    }
  }
  return m;
}

// voxels.ply (issue: semantic voxel map) -> centres and labels.
// `confidence` receives the voxels' confidence when voxels.ply has one (else it stays empty).
Status ReadPredictedVoxels(const std::string& path, std::vector<Eigen::Vector3f>* centres, std::vector<int>* labels,
                           std::vector<float>* confidence) {
  Result<PlyData> ply = ReadPly(path);
  if (!ply.ok()) return ply.status();
  const PlyElement* v = ply->Find("vertex");
  const PlyProperty *x = v ? v->Find("x") : nullptr, *y = v ? v->Find("y") : nullptr, *z = v ? v->Find("z") : nullptr;
  const PlyProperty* label = v ? v->Find("label") : nullptr;
  if (!x || !y || !z || !label)
    return Status::InvalidInput(FileError(path, "expected one vertex per voxel with x, y, z and label", "see docs/metrics.md"));
  for (size_t i = 0; i < v->count; ++i) {
    centres->emplace_back(float(x->values[i]), float(y->values[i]), float(z->values[i]));
    labels->push_back(int(label->values[i]));
  }
  if (const PlyProperty* c = v->Find("confidence")) confidence->assign(c->values.begin(), c->values.end());
  return Status::Ok();
}

// rooms.geojson -> room id -> type id.
Result<std::map<int, int>> ReadRoomTypes(const std::string& path) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  std::map<int, int> types;
  try {
    const nlohmann::json j = nlohmann::json::parse(bytes);
    for (const auto& f : j.at("features")) {
      const auto& p = f.at("properties");
      types[p.at("id").get<int>()] = p.at("type_id").get<int>();
    }
  } catch (const nlohmann::json::exception& e) {
    return Status::InvalidInput(FileError(path, std::string("expected a FeatureCollection whose features have properties "
                                                            "id and type_id: ") + e.what()));
  }
  return types;
}

}  // namespace

Result<EvalReport> Evaluate(const std::string& pred_dir, const std::string& gt_dir) {
  std::error_code ec;
  if (!fs::is_directory(pred_dir, ec))
    return Status::InvalidInput(FileError(pred_dir, "not a directory", "pass the OUTDIR of `semvox run`"));
  Result<GroundTruth> gt_or = ReadGroundTruth(gt_dir);
  if (!gt_or.ok()) return gt_or.status();
  const GroundTruth& gt = gt_or.value();
  EvalReport rep;
  rep.pred_dir = pred_dir;
  rep.gt_dir = gt_dir;
  const auto path = [&](const char* name) { return (fs::path(pred_dir) / name).string(); };
  const auto exists = [&](const char* name) { return fs::exists(path(name), ec); };

  Result<ImageU16> gt_rooms = ReadImageU16(gt.rooms_image);
  if (!gt_rooms.ok()) return gt_rooms.status();
  Result<ImageU16> gt_top = ReadImageU16(gt.topview_image);
  if (!gt_top.ok()) return gt_top.status();
  if (gt_rooms->width != gt.grid.width || gt_rooms->height != gt.grid.height || gt_top->width != gt.grid.width ||
      gt_top->height != gt.grid.height)
    return Status::InvalidInput(FileError(gt.rooms_image, "image size differs from the grid in gt.json", "regenerate the ground truth"));

  std::optional<OccupancyMap> occ;
  if (exists("occupancy.yaml")) {
    Result<OccupancyMap> m = ReadOccupancyMap(path("occupancy.yaml"));
    if (!m.ok()) return m.status();
    occ = std::move(m.value());
  }
  rep.voxel_size_m = occ ? occ->resolution : 0.05;

  // Voxels (b, c) and the top-view semantics (a).
  std::optional<ImageU16> pred_top;
  if (exists("voxels.ply")) {
    std::vector<Eigen::Vector3f> centres;
    std::vector<int> labels;
    std::vector<float> confidence;
    SEMVOX_RETURN_IF_ERROR(ReadPredictedVoxels(path("voxels.ply"), &centres, &labels, &confidence));
    pred_top = TopViewFromVoxels(centres, labels, gt.grid, gt.floor_z_m + gt.band_min_above_floor_m,
                                 gt.floor_z_m + gt.band_max_above_floor_m);
    Result<Mesh> mesh = ReadLabeledMesh(gt.gt_mesh);
    if (!mesh.ok()) return mesh.status();
    const VoxelLabels gt_voxels = VoxelizeLabeledMesh(*mesh, rep.voxel_size_m);
    VoxelLabels pred;
    std::unordered_map<uint64_t, float> pred_confidence;
    for (size_t i = 0; i < centres.size(); ++i) {
      const Eigen::Vector3f& p = centres[i];
      const int64_t kx = CoordToKeyIndex(p.x(), rep.voxel_size_m), ky = CoordToKeyIndex(p.y(), rep.voxel_size_m),
                    kz = CoordToKeyIndex(p.z(), rep.voxel_size_m);
      if (!KeyIndexInRange(kx) || !KeyIndexInRange(ky) || !KeyIndexInRange(kz)) continue;
      const uint64_t key = VoxelKey{uint16_t(kx), uint16_t(ky), uint16_t(kz)}.Pack();
      pred[key] = labels[i];
      if (i < confidence.size()) pred_confidence[key] = confidence[i];
    }
    rep.voxels = ScoreVoxels(gt_voxels, pred);
    // The visible voxels' confidence, in key order (the sums do not depend on it; the ranks' ties do not either).
    std::vector<std::pair<uint64_t, int>> visible;
    for (const auto& [key, g] : gt_voxels)
      if (pred_confidence.count(key)) visible.emplace_back(key, g);
    std::sort(visible.begin(), visible.end());
    std::vector<float> conf;
    std::vector<uint8_t> right;
    for (const auto& [key, g] : visible) conf.push_back(pred_confidence.at(key)), right.push_back(pred.at(key) == g);
    rep.confidence = ScoreConfidence(conf, right);
  } else {
    const Score none = Absent("voxels.ply not found");
    rep.voxels.accuracy = rep.voxels.mean_recall = rep.voxels.mean_iou = rep.voxels.nyu4_average = rep.voxels.nyu4_global = none;
    for (auto& r : rep.voxels.nyu4_recall) r = none;
  }
  rep.top_view = ScoreTopView(*gt_top, *gt_rooms, gt.grid, occ ? &*occ : nullptr, pred_top ? &*pred_top : nullptr);

  // Rooms (d, e): rooms.png lies on the occupancy grid.
  if (exists("rooms.png") && occ) {
    Result<ImageU16> pred_rooms = ReadImageU16(path("rooms.png"));
    if (!pred_rooms.ok()) return pred_rooms.status();
    const FloorGrid pg = GridOf(*occ);
    if (pred_rooms->width != pg.width || pred_rooms->height != pg.height)
      return Status::InvalidInput(FileError(path("rooms.png"), "size differs from occupancy.pgm", "both must share the occupancy grid"));
    // Segmentation is scored on spaces separated by walls: open-plan partners (a kitchen open to the living
    // room) are one ground-truth segment here; (e) still scores their types apart.
    std::map<int, int> space;
    for (const auto& r : gt.rooms) space[r.id] = r.id;
    for (bool changed = true; changed;) {
      changed = false;
      for (const auto& r : gt.rooms)
        for (int o : r.open_to)
          if (space.count(o) && space[o] != space[r.id]) {
            const int m = std::min(space[o], space[r.id]);
            changed |= space[o] != m || space[r.id] != m;
            space[o] = space[r.id] = m;
          }
    }
    ImageU16 gt_spaces = *gt_rooms;
    for (uint16_t& v : gt_spaces.data)
      if (v && space.count(v)) v = uint16_t(space[v]);
    rep.rooms = ScoreRoomSegmentation(gt_spaces, gt.grid, *pred_rooms, pg);
    rep.rooms_typed = ScoreRoomSegmentation(*gt_rooms, gt.grid, *pred_rooms, pg);
    if (exists("rooms.geojson")) {
      Result<std::map<int, int>> pred_types = ReadRoomTypes(path("rooms.geojson"));
      if (!pred_types.ok()) return pred_types.status();
      std::map<int, int> gt_types;
      for (const auto& r : gt.rooms) gt_types[r.id] = r.type_id;
      rep.room_types = ScoreRoomTypes(*gt_rooms, gt.grid, gt_types, *pred_rooms, pg, *pred_types);
    } else {
      rep.room_types.global = rep.room_types.average = Absent("rooms.geojson not found");
    }
  } else {
    const Score none = Absent(occ ? "rooms.png not found" : "rooms.png or occupancy.yaml not found");
    rep.rooms.recall = rep.rooms.precision = rep.rooms_typed.recall = rep.rooms_typed.precision = none;
    rep.room_types.global = rep.room_types.average = none;
  }
  return rep;
}

namespace {

// {"class name": {count_name: n, "recall": r, "most_confused_with": "name" or null}}; label 0 is "empty".
nlohmann::ordered_json PerClassJson(const std::map<int, ClassRecall>& rows, const char* count_name) {
  auto name_of = [](int c) { return c == 0 ? std::string("empty") : Nyu40Labels()[size_t(std::clamp(c, 0, kNumNyu40 - 1))].name; };
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (const auto& [c, row] : rows)
    out[name_of(c)] = {{count_name, row.count},
                       {"recall", Round6(Ratio(row.correct, row.count))},
                       {"most_confused_with", row.most_confused_with < 0 ? nlohmann::ordered_json() : nlohmann::ordered_json(name_of(row.most_confused_with))}};
  for (const auto& [c, row] : rows) {
    nlohmann::ordered_json conf = nlohmann::ordered_json::object();
    for (const auto& [p, n] : row.confusions) conf[name_of(p)] = n;
    out[name_of(c)]["confused_with"] = conf;
  }
  return out;
}

}  // namespace

std::string EvalReport::ToJson() const {
  nlohmann::ordered_json j;
  j["pred"] = pred_dir;
  j["gt"] = gt_dir;
  j["voxel_size_m"] = voxel_size_m;
  j["a_top_view"] = {{"geometric_accuracy", ScoreJson(top_view.geometric_accuracy)},
                     {"semantic_accuracy", ScoreJson(top_view.semantic_accuracy)},
                     {"semantic_global", ScoreJson(top_view.semantic_global)},
                     {"pixels", top_view.pixels},
                     {"predicted_unknown_fraction", Round6(top_view.predicted_unknown)}};
  j["a_top_view"]["per_class"] = PerClassJson(top_view.per_class, "pixels");
  nlohmann::ordered_json iou = nlohmann::ordered_json::object();
  for (const auto& [c, v] : voxels.iou_per_class) iou[Nyu40Labels()[size_t(std::clamp(c, 0, kNumNyu40 - 1))].name] = Round6(v);
  j["b_visible_voxels"] = {{"accuracy", ScoreJson(voxels.accuracy)}, {"mean_recall", ScoreJson(voxels.mean_recall)},
                           {"mean_iou", ScoreJson(voxels.mean_iou)}, {"visible", voxels.visible},
                           {"gt_voxels", voxels.gt_voxels}, {"iou_per_class", iou},
                           {"per_class", PerClassJson(voxels.per_class, "voxels")}};
  j["c_nyu4"] = {{"ground", ScoreJson(voxels.nyu4_recall[0])}, {"structure", ScoreJson(voxels.nyu4_recall[1])},
                 {"furniture", ScoreJson(voxels.nyu4_recall[2])}, {"props", ScoreJson(voxels.nyu4_recall[3])},
                 {"average", ScoreJson(voxels.nyu4_average)}, {"global", ScoreJson(voxels.nyu4_global)}};
  j["d_room_segmentation"] = {{"recall", ScoreJson(rooms.recall)}, {"precision", ScoreJson(rooms.precision)},
                              {"gt_rooms", rooms.gt_rooms}, {"predicted_rooms", rooms.predicted_rooms}};
  j["d_room_segmentation_typed_areas"] = {{"recall", ScoreJson(rooms_typed.recall)}, {"precision", ScoreJson(rooms_typed.precision)},
                                          {"gt_rooms", rooms_typed.gt_rooms}, {"predicted_rooms", rooms_typed.predicted_rooms}};
  nlohmann::ordered_json per_type = nlohmann::ordered_json::object();
  for (const auto& [t, v] : room_types.recall_per_type) per_type[RoomTypes()[size_t(std::clamp(t, 0, kNumRoomTypes - 1))].name] = Round6(v);
  auto type_name = [](int t) { return RoomTypes()[size_t(std::clamp(t, 0, kNumRoomTypes - 1))].name; };
  nlohmann::ordered_json confusion = nlohmann::ordered_json::object();
  for (const auto& [gt, row] : room_types.confusion_pixels)
    for (const auto& [pt, count] : row) confusion[type_name(gt)][type_name(pt)] = count;
  j["e_room_types"] = {{"global", ScoreJson(room_types.global)}, {"average", ScoreJson(room_types.average)}, {"recall_per_type", per_type},
                       {"confusion_pixels", confusion}};
  if (confidence.scored) j["f_confidence"] = ConfidenceJson(confidence);
  return j.dump(2) + "\n";
}

std::string EvalReport::Table() const {
  std::ostringstream os;
  auto row = [&](const char* name, const Score& s) {
    os << "  " << std::left << std::setw(44) << name << std::right;
    if (s.present) os << std::fixed << std::setprecision(1) << std::setw(7) << 100.0 * s.value << " %";
    else os << std::setw(9) << "absent";
    if (!s.note.empty()) os << "   (" << s.note << ")";
    os << "\n";
  };
  os << "semvox eval: " << pred_dir << " against " << gt_dir << " (voxel " << voxel_size_m << " m)\n";
  row("(a) top-view geometric accuracy", top_view.geometric_accuracy);
  row("(a) top-view semantic accuracy (class mean)", top_view.semantic_accuracy);
  row("(a) top-view semantic accuracy (global)", top_view.semantic_global);
  row("(b) visible-voxel accuracy", voxels.accuracy);
  row("(b) visible-voxel class-mean recall", voxels.mean_recall);
  row("(b) visible-voxel mean IoU", voxels.mean_iou);
  row("(c) NYU-4 ground recall", voxels.nyu4_recall[0]);
  row("(c) NYU-4 structure recall", voxels.nyu4_recall[1]);
  row("(c) NYU-4 furniture recall", voxels.nyu4_recall[2]);
  row("(c) NYU-4 props recall", voxels.nyu4_recall[3]);
  row("(c) NYU-4 average", voxels.nyu4_average);
  row("(c) NYU-4 global", voxels.nyu4_global);
  row("(d) room segmentation recall", rooms.recall);
  row("(d) room segmentation precision", rooms.precision);
  row("(d) recall vs typed areas (open plan split)", rooms_typed.recall);
  row("(d) precision vs typed areas", rooms_typed.precision);
  row("(e) room-type accuracy (global)", room_types.global);
  row("(e) room-type accuracy (type mean)", room_types.average);
  if (confidence.scored) {
    os << "  (f) confidence of the visible voxels:\n";
    os << ConfidenceTable(confidence);
  }
  return os.str();
}

}  // namespace semvox
