#include "eval/box_eval.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "core/file_util.h"
#include "core/labels.h"
#include "core/ply.h"
#include "eval/score_json.h"

namespace semvox {
namespace fs = std::filesystem;

namespace {

double Ratio(size_t num, size_t den) { return den ? double(num) / double(den) : 0.0; }

}  // namespace

std::string LabelName(int id) { return id >= 0 && id < kNumNyu40 ? Nyu40Labels()[size_t(id)].name : "id " + std::to_string(id); }

bool LabelsMatch(int predicted, int truth) {
  using namespace nyu40;
  if (predicted == truth) return true;
  const auto table_like = [](int l) { return l == kTable || l == kDesk; };
  return table_like(predicted) && table_like(truth);
}

Result<RunVoxels> ReadRunVoxels(const std::string& path, double voxel_size_m) {
  Result<PlyData> ply = ReadPly(path);
  if (!ply.ok()) return ply.status();
  const PlyElement* v = ply->Find("vertex");
  const PlyProperty *x = v ? v->Find("x") : nullptr, *y = v ? v->Find("y") : nullptr, *z = v ? v->Find("z") : nullptr;
  if (!x || !y || !z) return Status::InvalidInput(FileError(path, "expected vertices with x, y, z", "pass the voxels.ply of `semvox run`"));
  const PlyProperty* label = v->Find("label");
  const PlyProperty* confidence = v->Find("confidence");
  if (!label)
    return Status::InvalidInput(FileError(path, "vertices have no label property",
                                          "pass the voxels.ply of `semvox run`, which has one NYU40 label per voxel"));
  RunVoxels out;
  out.voxel_size_m = voxel_size_m;
  out.centres.reserve(v->count);
  out.labels.reserve(v->count);
  for (size_t i = 0; i < v->count; ++i) {
    out.centres.emplace_back(x->values[i], y->values[i], z->values[i]);
    out.labels.push_back(int(label->values[i]));
  }
  if (confidence) out.confidence.assign(confidence->values.begin(), confidence->values.end());
  return out;
}

double EstimateFloorHeight(const std::vector<double>& z, double voxel_size_m) {
  if (z.empty() || !(voxel_size_m > 0)) return 0.0;
  const double lo = *std::min_element(z.begin(), z.end());
  // Level k holds the centres nearest lo + k * voxel: voxels of one grid share a level exactly.
  std::map<long, size_t> levels;
  for (double v : z) ++levels[std::lround((v - lo) / voxel_size_m)];
  size_t peak = 0;
  for (const auto& [k, n] : levels) peak = std::max(peak, n);
  for (const auto& [k, n] : levels)
    if (double(n) >= kFloorLevelShare * double(peak)) return lo + (double(k) - 0.5) * voxel_size_m;
  return lo - 0.5 * voxel_size_m;  // Not reached: the peak level qualifies.
}

BoxEvalReport EvaluateBoxes(const RunVoxels& voxels, const BoxGroundTruth& gt) {
  BoxEvalReport rep;
  rep.gt_path = gt.path;
  const size_t n = std::min(voxels.centres.size(), voxels.labels.size());
  rep.occupied = n;
  std::vector<Eigen::Vector3d> q(n);
  const Eigen::Matrix3d rot = gt.axis_align.topLeftCorner<3, 3>();
  const Eigen::Vector3d shift = gt.axis_align.topRightCorner<3, 1>();
  for (size_t i = 0; i < n; ++i) q[i] = rot * voxels.centres[i] + shift;

  std::vector<char> in_any(n, 0);
  const bool has_confidence = voxels.confidence.size() >= n;
  std::vector<float> conf;
  std::vector<uint8_t> right;
  double recall_sum = 0;
  for (const GroundTruthBox& box : gt.boxes) {
    BoxScore s;
    s.class_name = box.class_name;
    s.nyu40 = box.nyu40;
    std::map<int, size_t> counts;
    for (size_t i = 0; i < n; ++i) {
      if (!box.Contains(q[i])) continue;
      in_any[i] = 1;
      ++s.voxels;
      ++counts[voxels.labels[i]];
      const bool ok = LabelsMatch(voxels.labels[i], box.nyu40);
      s.correct += ok;
      if (has_confidence) conf.push_back(voxels.confidence[i]), right.push_back(ok);
    }
    for (const auto& [label, count] : counts) s.top.push_back({label, count});
    std::stable_sort(s.top.begin(), s.top.end(), [](const LabelCount& a, const LabelCount& b) { return a.count > b.count; });
    if (s.top.size() > 3) s.top.resize(3);
    if (s.voxels) {
      s.recall = Score{true, Ratio(s.correct, s.voxels), std::to_string(s.voxels) + " voxels"};
      recall_sum += s.recall.value;
      ++rep.boxes_scored;
    } else {
      s.recall = Score{false, 0.0, "no voxel inside the box"};
    }
    ClassScore& c = rep.per_class[box.class_name];
    c.nyu40 = box.nyu40;
    ++c.boxes;
    c.voxels += s.voxels;
    c.correct += s.correct;
    rep.boxes.push_back(std::move(s));
  }
  for (auto& [name, c] : rep.per_class)
    c.recall = c.voxels ? Score{true, Ratio(c.correct, c.voxels), std::to_string(c.boxes) + " boxes, " + std::to_string(c.voxels) + " voxels"}
                        : Score{false, 0.0, "no voxel inside its boxes"};
  rep.mean_box_recall = rep.boxes_scored
                            ? Score{true, recall_sum / rep.boxes_scored,
                                    std::to_string(rep.boxes_scored) + " of " + std::to_string(gt.boxes.size()) + " boxes hold voxels"}
                            : Score{false, 0.0, "no box holds a voxel"};

  // Floor band and wall share.
  std::vector<double> z(n);
  for (size_t i = 0; i < n; ++i) z[i] = q[i].z();
  rep.floor_z_m = EstimateFloorHeight(z, voxels.voxel_size_m);
  size_t floor_ok = 0, walls = 0;
  for (size_t i = 0; i < n; ++i) {
    walls += voxels.labels[i] == nyu40::kWall;
    if (in_any[i] || z[i] < rep.floor_z_m || z[i] >= rep.floor_z_m + kFloorBandM) continue;
    ++rep.floor_band_voxels;
    floor_ok += voxels.labels[i] == nyu40::kFloor;
    if (has_confidence) conf.push_back(voxels.confidence[i]), right.push_back(voxels.labels[i] == nyu40::kFloor);
  }
  std::ostringstream band;
  band << rep.floor_band_voxels << " voxels in the band [" << std::fixed << std::setprecision(3) << rep.floor_z_m << ", "
       << rep.floor_z_m + kFloorBandM << ") m, outside every box";
  rep.floor_recall = rep.floor_band_voxels ? Score{true, Ratio(floor_ok, rep.floor_band_voxels), band.str()}
                                           : Score{false, 0.0, "no voxel in the floor band"};
  rep.wall_share = n ? Score{true, Ratio(walls, n), std::to_string(n) + " occupied voxels"} : Score{false, 0.0, "no occupied voxel"};
  rep.rooms_present = Score{false, 0.0, "rooms.geojson not read"};
  rep.confidence = ScoreConfidence(conf, right);
  return rep;
}

Result<std::vector<RoomFound>> ReadRoomsFound(const std::string& path) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  std::vector<RoomFound> rooms;
  try {
    const nlohmann::json j = nlohmann::json::parse(bytes);
    for (const auto& f : j.at("features")) {
      const auto& p = f.at("properties");
      RoomFound r;
      r.id = p.at("id").get<int>();
      r.type = p.at("type").get<std::string>();
      r.area_m2 = p.at("area_m2").get<double>();
      rooms.push_back(std::move(r));
    }
  } catch (const nlohmann::json::exception& e) {
    return Status::InvalidInput(FileError(path, std::string("expected a FeatureCollection whose features have properties "
                                                            "id, type and area_m2: ") + e.what()));
  }
  return rooms;
}

Result<std::vector<std::pair<std::string, double>>> ReadRunSeconds(const std::string& path, double* voxel_size_m) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  std::vector<std::pair<std::string, double>> out;
  try {
    const nlohmann::ordered_json j = nlohmann::ordered_json::parse(bytes);
    const auto size = j.find("voxel_size_m");
    if (voxel_size_m && size != j.end() && size->is_number() && size->get<double>() > 0) *voxel_size_m = size->get<double>();
    const auto s = j.find("seconds");
    if (s == j.end()) return out;
    for (const auto& [stage, v] : s->items()) out.emplace_back(stage, v.get<double>());
  } catch (const nlohmann::json::exception& e) {
    return Status::InvalidInput(FileError(path, std::string("expected a JSON object whose \"seconds\" maps stages to numbers: ") + e.what(),
                                          "pass the OUTDIR of `semvox run`"));
  }
  return out;
}

Result<RunExtras> ReadRunExtras(const std::string& pred_dir) {
  std::error_code ec;
  if (!fs::is_directory(pred_dir, ec))
    return Status::InvalidInput(FileError(pred_dir, "not a directory", "pass the OUTDIR of `semvox run`"));
  const auto path = [&](const char* name) { return (fs::path(pred_dir) / name).string(); };
  RunExtras out;
  if (fs::exists(path("summary.json"), ec)) {
    Result<std::vector<std::pair<std::string, double>>> s = ReadRunSeconds(path("summary.json"), &out.voxel_size_m);
    if (!s.ok()) return s.status();
    out.seconds = std::move(s.value());
  }
  if (fs::exists(path("rooms.geojson"), ec)) {
    Result<std::vector<RoomFound>> rooms = ReadRoomsFound(path("rooms.geojson"));
    if (!rooms.ok()) return rooms.status();
    out.rooms = std::move(rooms.value());
    out.rooms_present = Score{true, 0.0, std::to_string(out.rooms.size()) + " rooms"};
  } else {
    out.rooms_present = Score{false, 0.0, "rooms.geojson not found"};
  }
  return out;
}

Result<RunVoxels> ReadRunVoxels(const std::string& pred_dir, const RunExtras& extras) {
  return ReadRunVoxels((fs::path(pred_dir) / "voxels.ply").string(), extras.voxel_size_m);
}

Result<BoxEvalReport> EvaluateRunAgainstBoxes(const std::string& pred_dir, const std::string& gt_path) {
  Result<BoxGroundTruth> gt = ReadBoxGroundTruth(gt_path);
  if (!gt.ok()) return gt.status();
  Result<RunExtras> extras = ReadRunExtras(pred_dir);
  if (!extras.ok()) return extras.status();
  Result<RunVoxels> voxels = ReadRunVoxels(pred_dir, *extras);
  if (!voxels.ok()) return voxels.status();
  BoxEvalReport rep = EvaluateBoxes(*voxels, *gt);
  AttachRunExtras(pred_dir, std::move(*extras), &rep);
  return rep;
}

std::string BoxEvalReport::ToJson() const {
  nlohmann::ordered_json j;
  j["pred"] = pred_dir;
  j["gt"] = gt_path;
  j["occupied"] = occupied;
  nlohmann::ordered_json bs = nlohmann::ordered_json::array();
  for (const BoxScore& b : boxes) {
    nlohmann::ordered_json top = nlohmann::ordered_json::array();
    for (const LabelCount& t : b.top) top.push_back({{"label", t.label}, {"name", LabelName(t.label)}, {"voxels", t.count}});
    bs.push_back({{"class", b.class_name}, {"nyu40", b.nyu40}, {"voxels", b.voxels}, {"correct", b.correct},
                  {"recall", ScoreJson(b.recall)}, {"top_labels", top}});
  }
  j["boxes"] = bs;
  nlohmann::ordered_json pc = nlohmann::ordered_json::object();
  for (const auto& [name, c] : per_class)
    pc[name] = {{"nyu40", c.nyu40}, {"boxes", c.boxes}, {"voxels", c.voxels}, {"correct", c.correct}, {"recall", ScoreJson(c.recall)}};
  j["per_class"] = pc;
  j["mean_box_recall"] = ScoreJson(mean_box_recall);
  j["boxes_scored"] = boxes_scored;
  j["floor_z_m"] = Round6(floor_z_m);
  j["floor_band_m"] = kFloorBandM;
  j["floor_band_voxels"] = floor_band_voxels;
  j["floor_recall"] = ScoreJson(floor_recall);
  j["wall_share"] = ScoreJson(wall_share);
  if (confidence.scored) j["confidence"] = ConfidenceJson(confidence);
  AddRoomsAndSecondsJson(rooms_present, rooms, seconds, j);
  return j.dump(2) + "\n";
}

void AppendRoomsAndSeconds(const Score& rooms_present, const std::vector<RoomFound>& rooms,
                           const std::vector<std::pair<std::string, double>>& seconds, std::ostream& os) {
  os << "  rooms:";
  if (!rooms_present.present) os << " absent (" << rooms_present.note << ")";
  else if (rooms.empty()) os << " none";
  for (const RoomFound& r : rooms) os << " " << r.type << " " << std::fixed << std::setprecision(1) << r.area_m2 << " m2;";
  os << "\n  run seconds:";
  if (seconds.empty()) os << " absent (no summary.json or no seconds in it)";
  for (const auto& [stage, s] : seconds)
    if (stage == "total") os << " total " << std::fixed << std::setprecision(1) << s << ";";
  for (const auto& [stage, s] : seconds)
    if (stage != "total") os << " " << stage << " " << std::fixed << std::setprecision(1) << s;
  os << "\n";
}

std::string BoxEvalReport::Table() const {
  std::ostringstream os;
  const auto pct = PercentCell;
  os << "semvox eval: " << pred_dir << " against boxes " << gt_path << " (" << occupied << " occupied voxels)\n";
  os << "  " << std::left << std::setw(4) << "box" << std::setw(14) << "class" << std::right << std::setw(6) << "nyu40"
     << std::setw(8) << "voxels" << std::setw(10) << "recall" << "   top labels (voxels)\n";
  for (size_t i = 0; i < boxes.size(); ++i) {
    const BoxScore& b = boxes[i];
    os << "  " << std::left << std::setw(4) << i << std::setw(14) << b.class_name << std::right << std::setw(6) << b.nyu40
       << std::setw(8) << b.voxels << std::setw(10) << pct(b.recall) << "  ";
    for (const LabelCount& t : b.top) os << " " << LabelName(t.label) << " (" << t.count << ")";
    os << "\n";
  }
  os << "  per class:\n";
  for (const auto& [name, c] : per_class)
    os << "    " << std::left << std::setw(14) << name << std::right << std::setw(10) << pct(c.recall) << "   (" << c.boxes << " boxes, "
       << c.voxels << " voxels)\n";
  const auto row = [&](const char* name, const Score& s) { AppendScoreRow(os, name, s); };
  row("mean box recall", mean_box_recall);
  row("floor recall", floor_recall);
  row("wall share", wall_share);
  if (confidence.scored) os << ConfidenceTable(confidence);
  AppendRoomsAndSeconds(rooms_present, rooms, seconds, os);
  return os.str();
}

}  // namespace semvox
