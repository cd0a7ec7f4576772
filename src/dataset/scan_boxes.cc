#include "dataset/scan_boxes.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <sstream>

#include "core/file_util.h"
#include "core/label_aliases.h"
#include "core/labels.h"

namespace semvox {
namespace {

constexpr const char* kGtHint = "expected {\"axis_align_matrix\": 4x4 rows, \"boxes_in_aligned_frame\": [{\"class\", \"nyu40\", "
                                "\"centre_size\": [cx, cy, cz, dx, dy, dz]}]}; see docs/metrics.md";

Status GtError(const std::string& name, const std::string& what) { return Status::InvalidInput(FileError(name, what, kGtHint)); }

// A finite number at j, else false.
bool Number(const nlohmann::json& j, double* v) {
  if (!j.is_number()) return false;
  *v = j.get<double>();
  return std::isfinite(*v);
}

constexpr const char* kSunHint = "expected a tab-separated header with class_name cx cy cz dx dy dz yaw_rad, then one box per line "
                                 "(SUN RGB-D / mmdetection3d depth boxes); see docs/metrics.md";

Status SunError(const std::string& name, const std::string& what) { return Status::InvalidInput(FileError(name, what, kSunHint)); }

std::vector<std::string> SplitTabs(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, '\t')) out.push_back(field);
  return out;
}

}  // namespace

bool GroundTruthBox::Contains(const Eigen::Vector3d& p) const {
  Eigen::Vector3d q = p - centre;
  if (yaw_rad != 0) {  // Into the box's axes: turn by -yaw about z.
    const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
    q = Eigen::Vector3d(c * q.x() + s * q.y(), -s * q.x() + c * q.y(), q.z());
  }
  return (q.cwiseAbs().array() <= 0.5 * size.array()).all();
}

Result<BoxGroundTruth> ParseSunRgbdBoxes(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  std::map<std::string, size_t> column;
  BoxGroundTruth gt;
  gt.path = name;
  const char* kNeeded[] = {"class_name", "cx", "cy", "cz", "dx", "dy", "dz", "yaw_rad"};
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::vector<std::string> f = SplitTabs(line);
    const std::string where = "line " + std::to_string(line_no);
    if (column.empty()) {
      for (size_t k = 0; k < f.size(); ++k) column[f[k]] = k;
      for (const char* c : kNeeded)
        if (!column.count(c)) return SunError(name, where + ": the header has no column " + std::string(c));
      continue;
    }
    GroundTruthBox g;
    double v[7];
    for (int k = 0; k < 7; ++k) {
      const size_t col = column.at(kNeeded[k + 1]);
      if (col >= f.size()) return SunError(name, where + ": no " + std::string(kNeeded[k + 1]) + " field");
      size_t used = 0;
      try {
        v[k] = std::stod(f[col], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != f[col].size() || !std::isfinite(v[k]))
        return SunError(name, where + ", " + kNeeded[k + 1] + ": \"" + f[col] + "\" is not a finite number");
      if (k >= 3 && k < 6 && v[k] < 0) return SunError(name, where + ", " + kNeeded[k + 1] + ": negative size");
    }
    const size_t cc = column.at("class_name");
    if (cc >= f.size()) return SunError(name, where + ": no class_name field");
    g.class_name = f[cc];
    g.nyu40 = Nyu40IdByAlias(g.class_name);
    if (g.nyu40 < 1) return SunError(name, where + ", class_name: \"" + g.class_name + "\" is not a NYU40 class name (`semvox labels` lists them)");
    g.centre = Eigen::Vector3d(v[0], v[1], v[2]);
    g.size = Eigen::Vector3d(v[3], v[4], v[5]);
    g.yaw_rad = v[6];
    gt.boxes.push_back(std::move(g));
  }
  if (column.empty()) return SunError(name, "empty file");
  return gt;
}

Result<BoxGroundTruth> ParseBoxGroundTruth(const std::string& text, const std::string& name) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    return GtError(name, std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object()) return GtError(name, "expected a JSON object at the top level");
  BoxGroundTruth gt;
  gt.path = name;
  const auto m = j.find("axis_align_matrix");
  if (m == j.end()) return GtError(name, "missing field axis_align_matrix");
  if (!m->is_array() || m->size() != 4) return GtError(name, "axis_align_matrix: expected 4 rows of 4 numbers");
  for (int r = 0; r < 4; ++r) {
    const nlohmann::json& row = (*m)[size_t(r)];
    if (!row.is_array() || row.size() != 4) return GtError(name, "axis_align_matrix: expected 4 rows of 4 numbers");
    for (int c = 0; c < 4; ++c)
      if (!Number(row[size_t(c)], &gt.axis_align(r, c)))
        return GtError(name, "axis_align_matrix[" + std::to_string(r) + "][" + std::to_string(c) + "]: expected a finite number");
  }
  const auto b = j.find("boxes_in_aligned_frame");
  if (b == j.end()) return GtError(name, "missing field boxes_in_aligned_frame");
  if (!b->is_array()) return GtError(name, "boxes_in_aligned_frame: expected an array of boxes");
  for (size_t i = 0; i < b->size(); ++i) {
    const nlohmann::json& box = (*b)[i];
    const std::string where = "boxes_in_aligned_frame[" + std::to_string(i) + "]";
    if (!box.is_object()) return GtError(name, where + ": expected an object");
    GroundTruthBox g;
    const auto cls = box.find("class");
    if (cls == box.end() || !cls->is_string()) return GtError(name, where + ".class: missing or not a string");
    g.class_name = cls->get<std::string>();
    const auto id = box.find("nyu40");
    if (id == box.end() || !id->is_number_integer()) return GtError(name, where + ".nyu40: missing or not an integer");
    g.nyu40 = id->get<int>();
    if (g.nyu40 < 1 || g.nyu40 >= kNumNyu40) return GtError(name, where + ".nyu40: " + std::to_string(g.nyu40) + " is outside 1..40");
    const auto cs = box.find("centre_size");
    if (cs == box.end() || !cs->is_array() || cs->size() != 6) return GtError(name, where + ".centre_size: expected 6 numbers (cx cy cz dx dy dz)");
    for (int k = 0; k < 6; ++k) {
      double v;
      if (!Number((*cs)[size_t(k)], &v)) return GtError(name, where + ".centre_size[" + std::to_string(k) + "]: expected a finite number");
      if (k < 3) g.centre[k] = v;
      else if (v < 0) return GtError(name, where + ".centre_size[" + std::to_string(k) + "]: negative size");
      else g.size[k - 3] = v;
    }
    gt.boxes.push_back(std::move(g));
  }
  return gt;
}

Result<BoxGroundTruth> ReadBoxGroundTruth(const std::string& path) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  if (path.ends_with(".tsv")) return ParseSunRgbdBoxes(bytes, path);
  return ParseBoxGroundTruth(bytes, path);
}

}  // namespace semvox
