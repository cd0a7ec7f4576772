#include "mapping/occupancy_map.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/file_util.h"

namespace semvox {

bool OccupancyOptions::Check(std::string* error) const {
  if (!CheckOptions(*this, Options(), error)) return false;
  if (!(band_max_above_floor_m > band_min_above_floor_m)) {
    *error = "band_max_above_floor_m = " + std::to_string(band_max_above_floor_m) +
             ". Violated constraint: band_max_above_floor_m > band_min_above_floor_m (" +
             std::to_string(band_min_above_floor_m) + ")";
    return false;
  }
  if (!(free_thresh > 0 && free_thresh < occupied_thresh && occupied_thresh < 1)) {
    *error = "free_thresh = " + std::to_string(free_thresh) + ", occupied_thresh = " + std::to_string(occupied_thresh) +
             ". Violated constraint: 0 < free_thresh < occupied_thresh < 1";
    return false;
  }
  return true;
}

OccupancyMap ComputeOccupancy(const VoxelGrid& grid, double floor_z, const OccupancyOptions& options) {
  const auto& d = grid.dims();
  OccupancyMap m;
  m.resolution = grid.resolution();
  const Eigen::Vector3d corner = grid.MinCorner();
  m.origin_x = corner.x();
  m.origin_y = corner.y();
  m.image = ImageRgb8(d[0], d[1], 1, kPgmUnknown);
  const double zlo = floor_z + options.band_min_above_floor_m, zhi = floor_z + options.band_max_above_floor_m;
  int iz0 = d[2], iz1 = -1;
  for (int iz = 0; iz < d[2]; ++iz) {
    const double zc = grid.CellCenter(0, 0, iz).z();
    if (zc >= zlo && zc <= zhi) iz0 = std::min(iz0, iz), iz1 = std::max(iz1, iz);
  }
  for (int iy = 0; iy < d[1]; ++iy)
    for (int ix = 0; ix < d[0]; ++ix) {
      bool occ = false, fr = false;
      for (int iz = iz0; iz <= iz1; ++iz) {
        const VoxelState s = grid.state(grid.Index(ix, iy, iz));
        occ |= s == VoxelState::kOccupied;
        fr |= s == VoxelState::kFree;
      }
      m.image.at(ix, d[1] - 1 - iy) = occ ? kPgmOccupied : (fr ? kPgmFree : kPgmUnknown);
    }
  return m;
}

Status WriteOccupancyMap(const OccupancyMap& map, const std::string& dir, const std::string& stem) {
  const std::string pgm_name = stem + ".pgm";
  std::string pgm = "P5\n" + std::to_string(map.image.width) + " " + std::to_string(map.image.height) + "\n255\n";
  pgm.append(reinterpret_cast<const char*>(map.image.data.data()), map.image.data.size());
  std::ostringstream yaml;
  yaml.precision(10);
  yaml << "image: " << pgm_name << "\n"
       << "resolution: " << map.resolution << "\n"
       << "origin: [" << map.origin_x << ", " << map.origin_y << ", ";
  if (map.origin_yaw == 0) yaml << "0.0";
  else yaml << map.origin_yaw;
  yaml << "]\n"
       << "negate: 0\n"
       << "occupied_thresh: 0.65\n"
       << "free_thresh: 0.196\n";
  const std::filesystem::path base(dir);
  SEMVOX_RETURN_IF_ERROR(WriteFileAtomic((base / pgm_name).string(), pgm));
  return WriteFileAtomic((base / (stem + ".yaml")).string(), yaml.str());
}

Result<OccupancyMap> ReadOccupancyMap(const std::string& yaml_path) {
  std::string text;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(yaml_path, &text));
  OccupancyMap m;
  std::string image;
  std::istringstream is(text);
  std::string line;
  while (std::getline(is, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string key = line.substr(0, colon);
    std::string value = line.substr(colon + 1);
    while (!value.empty() && value.front() == ' ') value.erase(0, 1);
    if (key == "image") image = value;
    else if (key == "resolution") m.resolution = std::atof(value.c_str());
    else if (key == "origin") std::sscanf(value.c_str(), "[%lf, %lf, %lf", &m.origin_x, &m.origin_y, &m.origin_yaw);
  }
  if (image.empty() || !(m.resolution > 0))
    return Status::InvalidInput(FileError(yaml_path, "not a map_server YAML (needs image and resolution)", ""));
  const std::string pgm_path = (std::filesystem::path(yaml_path).parent_path() / image).string();
  std::string pgm;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(pgm_path, &pgm));
  int w = 0, h = 0, maxv = 0, consumed = 0;
  if (std::sscanf(pgm.c_str(), "P5 %d %d %d%n", &w, &h, &maxv, &consumed) != 3 || maxv != 255 || w <= 0 || h <= 0)
    return Status::InvalidInput(FileError(pgm_path, "not a binary 8-bit PGM", ""));
  const size_t off = size_t(consumed) + 1;
  if (pgm.size() < off + size_t(w) * h) return Status::InvalidInput(FileError(pgm_path, "truncated PGM", ""));
  m.image = ImageRgb8(w, h, 1);
  std::copy(pgm.begin() + off, pgm.begin() + off + size_t(w) * h, m.image.data.begin());
  return m;
}

}  // namespace semvox
