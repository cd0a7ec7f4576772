#include "rooms/room_shape.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <set>

#include "core/file_util.h"

namespace semvox {

std::array<double, kRoomShapeFeatures> RoomShape::Vector() const {
  return {std::log(std::max(area_m2, 0.01)), std::log(std::max(aspect, 1.0)), std::log(std::max(width_m, 0.05)),
          std::log(std::clamp(area_share, 1e-3, 1.0))};
}

std::vector<RoomShape> MeasureRoomShapes(const ImageU16& ids, int num_rooms, double res,
                                     const std::vector<std::vector<int>>* connections) {
  std::vector<RoomShape> out(size_t(std::max(num_rooms, 0)));
  if (num_rooms <= 0) return out;
  const int W = ids.width, H = ids.height;
  auto id_at = [&](int x, int y) { return x >= 0 && y >= 0 && x < W && y < H ? int(ids.at(x, y)) : 0; };
  // Chessboard distance to the nearest pixel of another id (two passes), per pixel.
  std::vector<int> dist(size_t(W) * H, 0);
  const int kFar = 1 << 28;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int id = id_at(x, y);
      if (!id) continue;
      int d = kFar;
      for (int dy = -1; dy <= 0; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (dy == 0 && dx >= 0) break;
          const int nx = x + dx, ny = y + dy;
          d = std::min(d, id_at(nx, ny) == id ? dist[size_t(ny) * W + nx] + 1 : 1);
        }
      dist[size_t(y) * W + x] = d;
    }
  for (int y = H - 1; y >= 0; --y)
    for (int x = W - 1; x >= 0; --x) {
      const int id = id_at(x, y);
      if (!id) continue;
      int d = dist[size_t(y) * W + x];
      for (int dy = 0; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (dy == 0 && dx <= 0) continue;
          const int nx = x + dx, ny = y + dy;
          d = std::min(d, id_at(nx, ny) == id ? dist[size_t(ny) * W + nx] + 1 : 1);
        }
      dist[size_t(y) * W + x] = d;
    }
  std::vector<Eigen::Vector2d> sum(out.size(), Eigen::Vector2d::Zero());
  std::vector<Eigen::Matrix2d> sum2(out.size(), Eigen::Matrix2d::Zero());
  std::vector<double> count(out.size(), 0);
  std::vector<int> deepest(out.size(), 0);
  std::vector<std::set<int>> neighbours(out.size());
  std::vector<std::vector<Eigen::Vector2d>> pixels(out.size());  // Per room, for its extents below.
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int id = id_at(x, y);
      if (id < 1 || id > num_rooms) continue;
      const size_t r = size_t(id - 1);
      const Eigen::Vector2d p(x, y);
      sum[r] += p, sum2[r] += p * p.transpose(), count[r] += 1;
      pixels[r].push_back(p);
      deepest[r] = std::max(deepest[r], dist[size_t(y) * W + x]);
      for (const auto& [nx, ny] : {std::pair{x + 1, y}, std::pair{x, y + 1}}) {
        const int other = id_at(nx, ny);
        if (other && other != id && other <= num_rooms) neighbours[r].insert(other), neighbours[size_t(other - 1)].insert(id);
      }
    }
  for (size_t r = 0; r < out.size(); ++r) {
    RoomShape& s = out[r];
    if (count[r] == 0) continue;
    const Eigen::Vector2d mean = sum[r] / count[r];
    const Eigen::Matrix2d cov = sum2[r] / count[r] - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    const Eigen::Vector2d major = eig.eigenvectors().col(1), minor = eig.eigenvectors().col(0);
    double a0 = 1e30, a1 = -1e30, b0 = 1e30, b1 = -1e30;
    for (const Eigen::Vector2d& p : pixels[r]) {
      const Eigen::Vector2d q = p - mean;
      a0 = std::min(a0, q.dot(major)), a1 = std::max(a1, q.dot(major));
      b0 = std::min(b0, q.dot(minor)), b1 = std::max(b1, q.dot(minor));
    }
    const double length = (a1 - a0 + 1) * res, width = (b1 - b0 + 1) * res;
    s.area_m2 = count[r] * res * res;
    s.aspect = std::max(length, width) / std::max(std::min(length, width), res);
    s.fill = std::clamp(s.area_m2 / (length * width), 0.0, 1.0);
    s.width_m = std::min(std::min(length, width), (2.0 * deepest[r] - 1.0) * res);
    s.connections = connections && r + 1 < connections->size() ? int((*connections)[r + 1].size()) : int(neighbours[r].size());
  }
  double total = 0;
  for (const RoomShape& s : out) total += s.area_m2;
  for (RoomShape& s : out) s.area_share = total > 0 ? s.area_m2 / total : 1.0;
  return out;
}

RoomShapeModel TrainRoomShapeModel(const std::vector<RoomShapeSample>& samples, int min_rooms, double ridge) {
  constexpr int F = kRoomShapeFeatures;
  using Vec = Eigen::Matrix<double, F, 1>;
  using Mat = Eigen::Matrix<double, F, F>;
  RoomShapeModel m;
  for (int t = 0; t < kRoomShapeTypes; ++t) {
    std::vector<Vec> xs;
    for (const RoomShapeSample& s : samples)
      if (s.type_id == t + 1) {
        const auto v = s.shape.Vector();
        xs.push_back(Eigen::Map<const Vec>(v.data()));
      }
    if (int(xs.size()) < std::max(min_rooms, F + 1)) continue;
    Vec mean = Vec::Zero();
    for (const Vec& x : xs) mean += x;
    mean /= double(xs.size());
    Mat cov = Mat::Zero();
    for (const Vec& x : xs) cov += (x - mean) * (x - mean).transpose();
    cov /= double(xs.size() - 1);
    cov += ridge * Mat::Identity();
    const Eigen::LLT<Mat> llt(cov);
    if (llt.info() != Eigen::Success) continue;
    const Mat inv = llt.solve(Mat::Identity());
    RoomShapeModel::TypeModel& tm = m.types[size_t(t)];
    tm.rooms = int(xs.size());
    for (int i = 0; i < F; ++i) {
      tm.mean[size_t(i)] = mean(i);
      for (int j = 0; j < F; ++j) tm.inverse_covariance[size_t(i * F + j)] = inv(i, j);
    }
    double log_det = 0;
    for (int i = 0; i < F; ++i) log_det += 2 * std::log(llt.matrixL()(i, i));
    tm.log_det_covariance = log_det;
  }
  for (const auto& [type, proxy] : {std::pair{3, 2}, std::pair{9, 2}, std::pair{5, 8}})
    if (m.types[size_t(type - 1)].rooms == 0 && m.types[size_t(proxy - 1)].rooms > 0) m.types[size_t(type - 1)].proxy_type_id = proxy;
  return m;
}

std::array<double, kRoomShapeTypes> LogLikelihoodRatios(const RoomShapeModel& model, const RoomShape& shape, bool open_plan) {
  constexpr int F = kRoomShapeFeatures;
  std::array<double, kRoomShapeTypes> out{};
  const auto v = shape.Vector();
  std::array<double, kRoomShapeTypes> log_p{};
  double best = -1e300;
  int modelled = 0;
  for (int t = 0; t < kRoomShapeTypes; ++t) {
    const RoomShapeModel::TypeModel& tm = model.types[size_t(t)];
    if (tm.rooms <= 0) continue;
    double q = 0;
    for (int i = 0; i < F; ++i)
      for (int j = 0; j < F; ++j)
        q += (v[size_t(i)] - tm.mean[size_t(i)]) * tm.inverse_covariance[size_t(i * F + j)] * (v[size_t(j)] - tm.mean[size_t(j)]);
    log_p[size_t(t)] = -0.5 * (q + tm.log_det_covariance);
    best = std::max(best, log_p[size_t(t)]);
    ++modelled;
  }
  if (modelled == 0) return out;
  double z = 0;
  for (int t = 0; t < kRoomShapeTypes; ++t)
    if (model.types[size_t(t)].rooms > 0) z += std::exp(log_p[size_t(t)] - best);
  const double log_mean = best + std::log(z / modelled);
  for (int t = 0; t < kRoomShapeTypes; ++t)
    if (model.types[size_t(t)].rooms > 0)
      out[size_t(t)] = std::clamp(log_p[size_t(t)] - log_mean, -model.min_ratio, model.max_ratio);
  for (int t = 0; t < kRoomShapeTypes; ++t) {
    const int proxy = model.types[size_t(t)].proxy_type_id;
    if (model.types[size_t(t)].rooms == 0 && proxy >= 1 && proxy <= kRoomShapeTypes && model.types[size_t(proxy - 1)].rooms > 0)
      out[size_t(t)] = out[size_t(proxy - 1)];
  }
  // Kitchens and dining rooms are often a part of an open-plan living room, whose region then has the living
  // room's shape: they are never less likely than the living room.
  if (open_plan)
    for (const int t : {5, 6}) out[size_t(t - 1)] = std::max(out[size_t(t - 1)], out[7]);
  return out;
}

namespace {
constexpr const char* kFormat = "semvox room-shape model 1";
}

std::string RoomShapeModelToJson(const RoomShapeModel& m) {
  nlohmann::json j;
  j["format"] = kFormat;
  j["provenance"] = m.provenance;
  j["features"] = {"log_area_m2", "log_aspect", "log_width_m", "log_area_share"};
  j["max_ratio"] = m.max_ratio;
  j["min_ratio"] = m.min_ratio;
  nlohmann::json types = nlohmann::json::array();
  for (int t = 0; t < kRoomShapeTypes; ++t) {
    const auto& tm = m.types[size_t(t)];
    types.push_back({{"type_id", t + 1},
                     {"rooms", tm.rooms},
                     {"mean", tm.mean},
                     {"inverse_covariance", tm.inverse_covariance},
                     {"log_det_covariance", tm.log_det_covariance},
                     {"proxy_type_id", tm.proxy_type_id}});
  }
  j["types"] = types;
  return j.dump(1) + "\n";
}

Status SaveRoomShapeModel(const RoomShapeModel& model, const std::string& path) {
  return WriteFileAtomic(path, RoomShapeModelToJson(model));
}

Result<RoomShapeModel> LoadRoomShapeModel(const std::string& path) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  RoomShapeModel m;
  try {
    const nlohmann::json j = nlohmann::json::parse(bytes);
    if (j.at("format").get<std::string>() != kFormat) throw std::runtime_error("unknown format");
    m.provenance = j.value("provenance", "");
    m.max_ratio = j.at("max_ratio").get<double>();
    m.min_ratio = j.at("min_ratio").get<double>();
    const auto& types = j.at("types");
    if (!types.is_array() || types.size() != size_t(kRoomShapeTypes)) throw std::runtime_error("types: need 12 entries");
    if (j.at("features").size() != size_t(kRoomShapeFeatures)) throw std::runtime_error("features: need 4");
    for (int t = 0; t < kRoomShapeTypes; ++t) {
      auto& tm = m.types[size_t(t)];
      tm.rooms = types[size_t(t)].at("rooms").get<int>();
      tm.mean = types[size_t(t)].at("mean").get<decltype(tm.mean)>();
      tm.inverse_covariance = types[size_t(t)].at("inverse_covariance").get<decltype(tm.inverse_covariance)>();
      tm.log_det_covariance = types[size_t(t)].at("log_det_covariance").get<double>();
      tm.proxy_type_id = types[size_t(t)].value("proxy_type_id", 0);
      if (tm.proxy_type_id < 0 || tm.proxy_type_id > kRoomShapeTypes) throw std::runtime_error("proxy_type_id out of range");
      for (double x : tm.mean)
        if (!std::isfinite(x)) throw std::runtime_error("non-finite mean");
      for (double x : tm.inverse_covariance)
        if (!std::isfinite(x)) throw std::runtime_error("non-finite inverse covariance");
    }
    if (!(m.max_ratio >= 0 && m.min_ratio >= 0)) throw std::runtime_error("max_ratio and min_ratio must be >= 0");
  } catch (const std::exception& e) {
    return Status::InvalidInput(FileError(path, std::string("not a room-shape model: ") + e.what(),
                                          "write one with `semvox train --room-shapes`"));
  }
  return m;
}

}  // namespace semvox
