#include "dataset/ground_truth.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

#include "core/file_util.h"

namespace semvox {
namespace fs = std::filesystem;

bool FloorGrid::PixelOf(double x, double y, int* c, int* r) const {
  const long cc = long(std::floor((x - origin_x) / resolution));
  const long rr = long(height) - 1 - long(std::floor((y - origin_y) / resolution));
  if (cc < 0 || rr < 0 || cc >= width || rr >= height) return false;
  *c = int(cc), *r = int(rr);
  return true;
}

Result<GroundTruth> ReadGroundTruth(const std::string& dir) {
  const std::string path = (fs::path(dir) / "gt.json").string();
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  GroundTruth gt;
  gt.dir = dir;
  try {
    const nlohmann::json j = nlohmann::json::parse(bytes);
    if (j.value("format", "") != kGroundTruthFormat)
      return Status::InvalidInput(FileError(path, std::string("not a semvox ground-truth file (format != ") + kGroundTruthFormat + ")",
                                            "pass a directory written by `semvox generate --seed N`"));
    gt.floor_z_m = j.at("floor_z_m").get<double>();
    gt.ceiling_z_m = j.at("ceiling_z_m").get<double>();
    gt.band_min_above_floor_m = j.at("topview_band_above_floor_m").at(0).get<double>();
    gt.band_max_above_floor_m = j.at("topview_band_above_floor_m").at(1).get<double>();
    const auto& g = j.at("rooms_gt");
    gt.grid.resolution = g.at("resolution").get<double>();
    gt.grid.origin_x = g.at("origin").at(0).get<double>();
    gt.grid.origin_y = g.at("origin").at(1).get<double>();
    gt.grid.width = g.at("width").get<int>();
    gt.grid.height = g.at("height").get<int>();
    gt.rooms_image = (fs::path(dir) / g.at("image").get<std::string>()).string();
    gt.topview_image = (fs::path(dir) / j.at("topview_gt").at("image").get<std::string>()).string();
    gt.gt_mesh = (fs::path(dir) / j.at("files").at("gt_mesh").get<std::string>()).string();
    for (const auto& r : j.at("rooms"))
      gt.rooms.push_back({r.at("id").get<int>(), r.at("type_id").get<int>(), r.at("type").get<std::string>(),
                          r.value("open_to", std::vector<int>())});
  } catch (const nlohmann::json::exception& e) {
    return Status::InvalidInput(FileError(path, std::string("malformed ground truth: ") + e.what(),
                                          "regenerate it with `semvox generate --seed N`"));
  }
  return gt;
}

}  // namespace semvox
