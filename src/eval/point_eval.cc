#include "eval/point_eval.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <unordered_map>

#include "core/file_util.h"
#include "core/labels.h"
#include "core/ply.h"
#include "eval/score_json.h"

namespace semvox {
namespace fs = std::filesystem;

namespace {

double Ratio(size_t num, size_t den) { return den ? double(num) / double(den) : 0.0; }

// Voxel centres hashed into cubic cells of the match radius: the nearest centre within the radius lies in
// one of the 27 cells around a query's.
class CentreGrid {
 public:
  CentreGrid(const std::vector<Eigen::Vector3d>& centres, double cell) : centres_(centres), cell_(cell) {
    cells_.reserve(centres.size());
    for (size_t i = 0; i < centres.size(); ++i) cells_[Key(Cell(centres[i]))].push_back(i);
  }
  // Index of the nearest centre within `radius` (<= the cell size) of p; -1 when none. Ties: the lower index.
  long Nearest(const Eigen::Vector3d& p, double radius) const {
    const Eigen::Vector3i c = Cell(p);
    long best = -1;
    double best_d2 = radius * radius;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(Key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (size_t i : it->second) {
            const double d2 = (centres_[i] - p).squaredNorm();
            if (d2 < best_d2 || (d2 == best_d2 && best >= 0 && long(i) < best)) {
              best_d2 = d2;
              best = long(i);
            }
          }
        }
    return best;
  }

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3d& p) const {
    return Eigen::Vector3i(int(std::floor(p.x() / cell_)), int(std::floor(p.y() / cell_)), int(std::floor(p.z() / cell_)));
  }
  static uint64_t Key(const Eigen::Vector3i& c) {
    return (uint64_t(uint32_t(c.x()) & 0x1fffff) << 42) | (uint64_t(uint32_t(c.y()) & 0x1fffff) << 21) |
           uint64_t(uint32_t(c.z()) & 0x1fffff);
  }
  const std::vector<Eigen::Vector3d>& centres_;
  double cell_;
  std::unordered_map<uint64_t, std::vector<size_t>> cells_;
};

}  // namespace

Result<LabelledPoints> ReadLabelledPoints(const std::string& path) {
  Result<PlyData> ply = ReadPly(path);
  if (!ply.ok()) return ply.status();
  const PlyElement* v = ply->Find("vertex");
  const PlyProperty *x = v ? v->Find("x") : nullptr, *y = v ? v->Find("y") : nullptr, *z = v ? v->Find("z") : nullptr;
  if (!x || !y || !z)
    return Status::InvalidInput(FileError(path, "expected vertices with x, y, z", "pass a labelled point cloud (x, y, z, label)"));
  const PlyProperty* label = v->Find("label");
  if (!label)
    return Status::InvalidInput(FileError(path, "vertices have no label property",
                                          "pass a point cloud with one NYU40 label per point, as s3dis_office_room/office_room.ply"));
  LabelledPoints out;
  out.path = path;
  for (size_t i = 0; i < v->count; ++i) {
    const double l = label->values[i];
    if (!(l >= 0 && l < kNumNyu40) || l != std::floor(l))
      return Status::InvalidInput(FileError(path, "point " + std::to_string(i) + " has label " + std::to_string(l) +
                                                      ", not a NYU40 id (0-40)", "labels are NYU40 ids, 0 for unlabelled"));
    if (l == 0) continue;
    const Eigen::Vector3d p(x->values[i], y->values[i], z->values[i]);
    if (!p.allFinite()) continue;
    out.points.push_back(p);
    out.labels.push_back(int(l));
  }
  if (out.points.empty())
    return Status::InvalidInput(FileError(path, "no labelled point (every label is 0)", "labels are NYU40 ids, 0 for unlabelled"));
  return out;
}

PointEvalReport EvaluatePoints(const RunVoxels& voxels, const LabelledPoints& gt) {
  PointEvalReport rep;
  rep.gt_path = gt.path;
  const size_t n = std::min(voxels.centres.size(), voxels.labels.size());
  rep.occupied = n;
  const CentreGrid grid(voxels.centres, kPointMatchRadiusM);
  std::map<int, std::map<int, size_t>> predicted;  // Class -> predicted label (0: unmatched) -> points.
  size_t correct = 0, matched = 0;
  const bool has_confidence = voxels.confidence.size() >= n;
  std::vector<float> conf;
  std::vector<uint8_t> right;
  for (size_t i = 0; i < gt.points.size(); ++i) {
    const int truth = gt.labels[i];
    PointClassScore& c = rep.per_class[truth];
    c.nyu40 = truth;
    ++c.points;
    const long v = grid.Nearest(gt.points[i], kPointMatchRadiusM);
    const int label = v >= 0 ? voxels.labels[size_t(v)] : 0;
    ++predicted[truth][label];
    if (v < 0) {
      ++c.unmatched;
      continue;
    }
    ++matched;
    const bool ok = LabelsMatch(label, truth);
    c.correct += ok;
    correct += ok;
    if (has_confidence) conf.push_back(voxels.confidence[size_t(v)]), right.push_back(ok);
  }
  rep.points = gt.points.size();
  double recall_sum = 0;
  for (auto& [id, c] : rep.per_class) {
    c.recall = Score{true, Ratio(c.correct, c.points), std::to_string(c.points) + " points"};
    recall_sum += c.recall.value;
    for (const auto& [label, count] : predicted[id]) c.top.push_back({label, count});
    std::stable_sort(c.top.begin(), c.top.end(), [](const LabelCount& a, const LabelCount& b) { return a.count > b.count; });
    if (c.top.size() > 3) c.top.resize(3);
  }
  const std::string of = std::to_string(rep.points) + " labelled points";
  rep.accuracy = Score{true, Ratio(correct, rep.points), of};
  rep.matched = Score{true, Ratio(matched, rep.points), "a voxel centre within " + std::to_string(int(kPointMatchRadiusM * 1000)) + " mm"};
  rep.mean_class_recall = Score{true, recall_sum / double(rep.per_class.size()), std::to_string(rep.per_class.size()) + " classes"};
  const auto floor = rep.per_class.find(nyu40::kFloor);
  rep.floor_recall = floor != rep.per_class.end() ? floor->second.recall : Score{false, 0.0, "no floor point"};
  size_t walls = 0;
  for (size_t i = 0; i < n; ++i) walls += voxels.labels[i] == nyu40::kWall;
  rep.wall_share = n ? Score{true, Ratio(walls, n), std::to_string(n) + " occupied voxels"} : Score{false, 0.0, "no occupied voxel"};
  rep.rooms_present = Score{false, 0.0, "rooms.geojson not read"};
  rep.confidence = ScoreConfidence(conf, right);
  return rep;
}

Result<PointEvalReport> EvaluateRunAgainstPoints(const std::string& pred_dir, const std::string& gt_path) {
  Result<RunExtras> extras = ReadRunExtras(pred_dir);
  if (!extras.ok()) return extras.status();
  Result<LabelledPoints> gt = ReadLabelledPoints(gt_path);
  if (!gt.ok()) return gt.status();
  Result<RunVoxels> voxels = ReadRunVoxels(pred_dir, *extras);
  if (!voxels.ok()) return voxels.status();
  PointEvalReport rep = EvaluatePoints(*voxels, *gt);
  AttachRunExtras(pred_dir, std::move(*extras), &rep);
  return rep;
}

std::string PointEvalReport::ToJson() const {
  nlohmann::ordered_json j;
  j["pred"] = pred_dir;
  j["gt"] = gt_path;
  j["occupied"] = occupied;
  j["points"] = points;
  j["match_radius_m"] = kPointMatchRadiusM;
  j["accuracy"] = ScoreJson(accuracy);
  j["matched"] = ScoreJson(matched);
  nlohmann::ordered_json pc = nlohmann::ordered_json::object();
  for (const auto& [id, c] : per_class) {
    nlohmann::ordered_json top = nlohmann::ordered_json::array();
    for (const LabelCount& t : c.top)
      top.push_back({{"label", t.label}, {"name", t.label ? LabelName(t.label) : "unmatched"}, {"points", t.count}});
    pc[LabelName(id)] = {{"nyu40", id},          {"points", c.points},           {"correct", c.correct},
                         {"unmatched", c.unmatched}, {"recall", ScoreJson(c.recall)}, {"top_labels", top}};
  }
  j["per_class"] = pc;
  j["mean_class_recall"] = ScoreJson(mean_class_recall);
  j["floor_recall"] = ScoreJson(floor_recall);
  j["wall_share"] = ScoreJson(wall_share);
  if (confidence.scored) j["confidence"] = ConfidenceJson(confidence);
  AddRoomsAndSecondsJson(rooms_present, rooms, seconds, j);
  return j.dump(2) + "\n";
}

std::string PointEvalReport::Table() const {
  std::ostringstream os;
  os << "semvox eval: " << pred_dir << " against labelled points " << gt_path << " (" << points << " points, " << occupied
     << " occupied voxels)\n";
  os << "  " << std::left << std::setw(16) << "class" << std::right << std::setw(6) << "nyu40" << std::setw(9) << "points"
     << std::setw(10) << "recall" << "   top labels (points)\n";
  for (const auto& [id, c] : per_class) {
    os << "  " << std::left << std::setw(16) << LabelName(id) << std::right << std::setw(6) << id << std::setw(9) << c.points
       << std::setw(10) << PercentCell(c.recall) << "  ";
    for (const LabelCount& t : c.top) os << " " << (t.label ? LabelName(t.label) : "unmatched") << " (" << t.count << ")";
    os << "\n";
  }
  const auto row = [&](const char* name, const Score& s) { AppendScoreRow(os, name, s); };
  row("point accuracy", accuracy);
  row("mean class recall", mean_class_recall);
  row("matched", matched);
  row("floor recall", floor_recall);
  row("wall share", wall_share);
  if (confidence.scored) os << ConfidenceTable(confidence);
  AppendRoomsAndSeconds(rooms_present, rooms, seconds, os);
  return os.str();
}

}  // namespace semvox
