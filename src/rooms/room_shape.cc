#include "rooms/room_shape.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <set>

#include "core/file_util.h"

namespace semvox {

std::array<double, kRoomShapeFeatures> RoomShape::Vector() const {
  return {std::log(std::max(area_m2, 0.01)), std::log(std::max(aspect, 1.0)), std::log(std::max(width_m, 0.05)),
          std::log(std::clamp(area_share, 1e-3, 1.0)), std::log1p(double(std::max(connections, 0))),
          std::clamp(exterior_share, 0.0, 1.0)};
}

const std::array<const char*, kRoomShapeFeatures>& RoomShapeFeatureNames() {
  static const std::array<const char*, kRoomShapeFeatures> names = {
      "log_area_m2", "log_aspect", "log_width_m", "log_area_share", "log1p_connections", "exterior_share"};
  return names;
}

int RoomShapeFeatureIndex(const std::string& name) {
  const auto& names = RoomShapeFeatureNames();
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : int(it - names.begin());
}

namespace {

// Per room (index id - 1): the share of its edge pixels (a 4-neighbour outside the room) with no pixel of
// another room within `reach` pixels (Euclidean, by a two-pass chamfer distance on the room's box grown by
// `reach`).
std::vector<double> ExteriorShares(const ImageU16& ids, int num_rooms, int reach) {
  const int W = ids.width, H = ids.height;
  std::vector<double> out(size_t(num_rooms), 0.0);
  std::vector<int> x0(size_t(num_rooms), W), x1(size_t(num_rooms), -1), y0(size_t(num_rooms), H), y1(size_t(num_rooms), -1);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int id = ids.at(x, y);
      if (id < 1 || id > num_rooms) continue;
      const size_t r = size_t(id - 1);
      x0[r] = std::min(x0[r], x), x1[r] = std::max(x1[r], x), y0[r] = std::min(y0[r], y), y1[r] = std::max(y1[r], y);
    }
  std::vector<float> dist;
  constexpr float kDiag = 1.41421356f, kFar = 1e9f;
  for (int id = 1; id <= num_rooms; ++id) {
    const size_t r = size_t(id - 1);
    if (x1[r] < 0) continue;
    const int bx0 = std::max(0, x0[r] - reach), bx1 = std::min(W - 1, x1[r] + reach);
    const int by0 = std::max(0, y0[r] - reach), by1 = std::min(H - 1, y1[r] + reach);
    const int bw = bx1 - bx0 + 1, bh = by1 - by0 + 1;
    dist.assign(size_t(bw) * bh, kFar);
    auto d = [&](int x, int y) -> float& { return dist[size_t(y - by0) * bw + (x - bx0)]; };
    for (int y = by0; y <= by1; ++y)
      for (int x = bx0; x <= bx1; ++x) {
        const int other = ids.at(x, y);
        if (other != 0 && other != id) d(x, y) = 0;
      }
    for (int y = by0; y <= by1; ++y)
      for (int x = bx0; x <= bx1; ++x) {
        float v = d(x, y);
        if (x > bx0) v = std::min(v, d(x - 1, y) + 1);
        if (y > by0) {
          v = std::min(v, d(x, y - 1) + 1);
          if (x > bx0) v = std::min(v, d(x - 1, y - 1) + kDiag);
          if (x < bx1) v = std::min(v, d(x + 1, y - 1) + kDiag);
        }
        d(x, y) = v;
      }
    for (int y = by1; y >= by0; --y)
      for (int x = bx1; x >= bx0; --x) {
        float v = d(x, y);
        if (x < bx1) v = std::min(v, d(x + 1, y) + 1);
        if (y < by1) {
          v = std::min(v, d(x, y + 1) + 1);
          if (x < bx1) v = std::min(v, d(x + 1, y + 1) + kDiag);
          if (x > bx0) v = std::min(v, d(x - 1, y + 1) + kDiag);
        }
        d(x, y) = v;
      }
    int edge = 0, exterior = 0;
    for (int y = y0[r]; y <= y1[r]; ++y)
      for (int x = x0[r]; x <= x1[r]; ++x) {
        if (ids.at(x, y) != id) continue;
        bool on_edge = false;
        for (const auto& [nx, ny] : {std::pair{x - 1, y}, std::pair{x + 1, y}, std::pair{x, y - 1}, std::pair{x, y + 1}})
          on_edge = on_edge || nx < 0 || ny < 0 || nx >= W || ny >= H || ids.at(nx, ny) != id;
        if (!on_edge) continue;
        ++edge;
        exterior += d(x, y) > float(reach);
      }
    out[r] = edge > 0 ? double(exterior) / edge : 0.0;
  }
  return out;
}

}  // namespace

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
    if (connections && r + 1 < connections->size())
      s.neighbours = (*connections)[r + 1];
    else
      s.neighbours.assign(neighbours[r].begin(), neighbours[r].end());
    s.connections = int(s.neighbours.size());
  }
  const std::vector<double> exterior = ExteriorShares(ids, num_rooms, std::max(1, int(std::lround(kExteriorReachM / res))));
  for (size_t r = 0; r < out.size(); ++r) out[r].exterior_share = exterior[r];
  double total = 0;
  for (const RoomShape& s : out) total += s.area_m2;
  for (RoomShape& s : out) s.area_share = total > 0 ? s.area_m2 / total : 1.0;
  return out;
}

RoomShapeModel TrainRoomShapeModel(const std::vector<RoomShapeSample>& samples, int min_rooms, double ridge,
                                   const std::vector<int>& features) {
  const int F = int(features.size());
  using Vec = Eigen::VectorXd;
  using Mat = Eigen::MatrixXd;
  RoomShapeModel m;
  m.features = features;
  for (int t = 0; t < kRoomShapeTypes; ++t) {
    std::vector<Vec> xs;
    for (const RoomShapeSample& s : samples)
      if (s.type_id == t + 1) {
        const auto v = s.shape.Vector();
        Vec x(F);
        for (int i = 0; i < F; ++i) x(i) = v[size_t(features[size_t(i)])];
        xs.push_back(x);
      }
    if (F == 0 || int(xs.size()) < std::max(min_rooms, F + 1)) continue;
    Vec mean = Vec::Zero(F);
    for (const Vec& x : xs) mean += x;
    mean /= double(xs.size());
    Mat cov = Mat::Zero(F, F);
    for (const Vec& x : xs) cov += (x - mean) * (x - mean).transpose();
    cov /= double(xs.size() - 1);
    cov += ridge * Mat::Identity(F, F);
    const Eigen::LLT<Mat> llt(cov);
    if (llt.info() != Eigen::Success) continue;
    const Mat inv = llt.solve(Mat::Identity(F, F));
    RoomShapeModel::TypeModel& tm = m.types[size_t(t)];
    tm.rooms = int(xs.size());
    tm.mean.assign(size_t(F), 0.0);
    tm.inverse_covariance.assign(size_t(F) * F, 0.0);
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

namespace {

// The 0.95 quantile of the chi-square distribution with k degrees of freedom (k = 1..8; the Wilson-Hilferty
// approximation above).
double ChiSquare95(int k) {
  static constexpr double kTable[] = {0, 3.841, 5.991, 7.815, 9.488, 11.070, 12.592, 14.067, 15.507};
  if (k >= 1 && k <= 8) return kTable[k];
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1 - a + 1.6449 * std::sqrt(a), 3);
}

}  // namespace

std::array<double, kRoomShapeTypes> LogLikelihoodRatios(const RoomShapeModel& model, const RoomShape& shape, bool open_plan) {
  const int F = int(model.features.size());
  std::array<double, kRoomShapeTypes> out{};
  const auto all = shape.Vector();
  // Log-likelihood (up to a constant) and squared Mahalanobis distance of the room under each type's Gaussian,
  // over the features `place` allows: false marginalises the Gaussians over the connection and exterior
  // features (the sub-vector's mean and the covariance's sub-block).
  std::array<double, kRoomShapeTypes> log_p{};
  double best = -1e300, nearest = 1e300;
  int modelled = 0, used_count = 0;
  auto evaluate = [&](bool place) {
    std::vector<int> used;
    for (int i = 0; i < F; ++i) {
      const int f = model.features[size_t(i)];
      if (!place && (f == 4 || f == 5)) continue;
      used.push_back(i);
    }
    const int U = int(used.size());
    used_count = U;
    best = -1e300, nearest = 1e300, modelled = 0;
    log_p.fill(0);
    Eigen::VectorXd v(U);
    for (int k = 0; k < U; ++k) v(k) = all[size_t(model.features[size_t(used[size_t(k)])])];
    for (int t = 0; t < kRoomShapeTypes; ++t) {
      const RoomShapeModel::TypeModel& tm = model.types[size_t(t)];
      if (tm.rooms <= 0 || U == 0 || tm.mean.size() != size_t(F) || tm.inverse_covariance.size() != size_t(F) * F) continue;
      Eigen::MatrixXd inverse(F, F);
      for (int i = 0; i < F; ++i)
        for (int j = 0; j < F; ++j) inverse(i, j) = tm.inverse_covariance[size_t(i * F + j)];
      Eigen::MatrixXd inv_sub(U, U);
      double log_det = tm.log_det_covariance;
      if (U == F) {
        inv_sub = inverse;
      } else {
        const Eigen::MatrixXd cov = inverse.inverse();
        Eigen::MatrixXd sub(U, U);
        for (int a = 0; a < U; ++a)
          for (int b = 0; b < U; ++b) sub(a, b) = cov(used[size_t(a)], used[size_t(b)]);
        const Eigen::LLT<Eigen::MatrixXd> llt(sub);
        if (llt.info() != Eigen::Success) continue;
        inv_sub = llt.solve(Eigen::MatrixXd::Identity(U, U));
        log_det = 0;
        for (int a = 0; a < U; ++a) log_det += 2 * std::log(llt.matrixL()(a, a));
      }
      Eigen::VectorXd d(U);
      for (int k = 0; k < U; ++k) d(k) = v(k) - tm.mean[size_t(used[size_t(k)])];
      const double mahalanobis = d.dot(inv_sub * d);
      log_p[size_t(t)] = -0.5 * (mahalanobis + log_det);
      best = std::max(best, log_p[size_t(t)]);
      nearest = std::min(nearest, mahalanobis);
      ++modelled;
    }
  };
  // A room without a neighbour shows nothing of its place in the flat (a scan of one room, or of a room whose
  // neighbours were not scanned): its connection and exterior features are not observed. A room whose place
  // is unlike any type's in the plans (outside every type's 95 % ellipsoid with them, e.g. the main room of a
  // studio: 90 % of the flat, one connection, nearly all of its edge outside) is judged the same way, by its
  // own four features: far outside the Gaussians their ratios say only which type is the broadest.
  const bool has_place = shape.connections > 0;
  evaluate(has_place);
  if (has_place && modelled > 0 && nearest > ChiSquare95(used_count)) evaluate(false);
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

std::array<std::array<double, kRoomShapeTypes>, kRoomShapeTypes> TrainRoomAdjacency(const std::vector<RoomShapeSample>& samples,
                                                                                     double pseudo_count) {
  constexpr int T = kRoomShapeTypes;
  std::array<int, T> present{};
  for (const RoomShapeSample& s : samples)
    if (s.type_id >= 1 && s.type_id <= T) ++present[size_t(s.type_id - 1)];
  // Stand-ins for the types the samples lack (as TrainRoomShapeModel).
  std::array<int, T> as{};
  for (int t = 0; t < T; ++t) as[size_t(t)] = t;
  for (const auto& [type, proxy] : {std::pair{3, 2}, std::pair{9, 2}, std::pair{5, 8}})
    if (present[size_t(type - 1)] == 0) as[size_t(type - 1)] = proxy - 1;
  std::array<std::array<double, T>, T> n{};
  for (const RoomShapeSample& s : samples) {
    if (s.type_id < 1 || s.type_id > T) continue;
    for (const int j : s.neighbours) {
      if (j < 0 || size_t(j) >= samples.size()) continue;
      const int b = samples[size_t(j)].type_id;
      if (b >= 1 && b <= T) n[size_t(s.type_id - 1)][size_t(b - 1)] += 1;
    }
  }
  double total = 0;
  for (int a = 0; a < T; ++a)
    for (int b = 0; b < T; ++b)
      if (present[size_t(a)] && present[size_t(b)]) total += (n[size_t(a)][size_t(b)] += pseudo_count);
  std::array<std::array<double, T>, T> out{};
  if (total <= 0) return out;
  std::array<double, T> row{};
  for (int a = 0; a < T; ++a)
    for (int b = 0; b < T; ++b) row[size_t(a)] += n[size_t(a)][size_t(b)] / total;
  for (int a = 0; a < T; ++a)
    for (int b = 0; b < T; ++b) {
      const int pa = as[size_t(a)], pb = as[size_t(b)];
      if (!present[size_t(pa)] || !present[size_t(pb)] || row[size_t(pa)] <= 0 || row[size_t(pb)] <= 0) continue;
      const double joint = n[size_t(pa)][size_t(pb)] / total;
      out[size_t(a)][size_t(b)] = std::clamp(std::log(joint / (row[size_t(pa)] * row[size_t(pb)])), -kMaxAdjacency, kMaxAdjacency);
      // Two neighbouring regions of one type are never penalised: a scan's segmentation may cut one room in
      // two (a plan seldom has two living rooms side by side, a segmented open-plan space often has).
      if (pa == pb) out[size_t(a)][size_t(b)] = std::max(out[size_t(a)][size_t(b)], 0.0);
    }
  return out;
}

void AddAdjacencyMessage(const std::array<std::array<double, kRoomShapeTypes>, kRoomShapeTypes>& adjacency,
                         const std::array<double, kRoomShapeTypes>& neighbour_share, double weight,
                         std::array<double, kRoomShapeTypes>* message) {
  for (int y = 0; y < kRoomShapeTypes; ++y) {
    double e = 0;
    for (int t = 0; t < kRoomShapeTypes; ++t) e += neighbour_share[size_t(t)] * adjacency[size_t(y)][size_t(t)];
    (*message)[size_t(y)] += weight * e;
  }
}

std::vector<std::array<double, kRoomShapeTypes>> AdjacencyMessages(const RoomShapeModel& model,
                                                                   const std::vector<std::array<double, kRoomShapeTypes>>& log_evidence,
                                                                   const std::vector<std::vector<int>>& neighbours, double weight,
                                                                   int iterations) {
  constexpr int T = kRoomShapeTypes;
  using Dist = std::array<double, T>;
  const size_t R = log_evidence.size();
  std::vector<Dist> message(R, Dist{}), q(R, Dist{});
  auto update_q = [&](size_t r) {
    double mx = -1e300;
    for (int y = 0; y < T; ++y) mx = std::max(mx, log_evidence[r][size_t(y)] + message[r][size_t(y)]);
    double z = 0;
    for (int y = 0; y < T; ++y) z += (q[r][size_t(y)] = std::exp(log_evidence[r][size_t(y)] + message[r][size_t(y)] - mx));
    for (double& v : q[r]) v /= z;
  };
  for (size_t r = 0; r < R; ++r) update_q(r);
  if (weight <= 0) return message;
  for (int it = 0; it < iterations; ++it) {
    std::vector<Dist> next(R, Dist{});
    for (size_t r = 0; r < R; ++r) {
      if (r >= neighbours.size()) continue;
      for (const int s : neighbours[r])
        if (s >= 0 && size_t(s) < R && size_t(s) != r) AddAdjacencyMessage(model.adjacency, q[size_t(s)], weight, &next[r]);
    }
    for (size_t r = 0; r < R; ++r)
      for (int y = 0; y < T; ++y) message[r][size_t(y)] = 0.5 * message[r][size_t(y)] + 0.5 * next[r][size_t(y)];
    for (size_t r = 0; r < R; ++r) update_q(r);
  }
  return message;
}

namespace {
constexpr const char* kFormat = "semvox room-shape model 1";
}

std::string RoomShapeModelToJson(const RoomShapeModel& m) {
  nlohmann::json j;
  j["format"] = kFormat;
  j["provenance"] = m.provenance;
  j["features"] = nlohmann::json::array();
  for (const int f : m.features) j["features"].push_back(RoomShapeFeatureNames()[size_t(f)]);
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
  j["adjacency"] = m.adjacency;
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
    m.features.clear();
    for (const auto& name : j.at("features")) {
      const int f = RoomShapeFeatureIndex(name.get<std::string>());
      if (f < 0) throw std::runtime_error("unknown feature " + name.get<std::string>());
      m.features.push_back(f);
    }
    if (m.features.empty()) throw std::runtime_error("features: none");
    const size_t F = m.features.size();
    for (int t = 0; t < kRoomShapeTypes; ++t) {
      auto& tm = m.types[size_t(t)];
      tm.rooms = types[size_t(t)].at("rooms").get<int>();
      tm.mean = types[size_t(t)].at("mean").get<std::vector<double>>();
      tm.inverse_covariance = types[size_t(t)].at("inverse_covariance").get<std::vector<double>>();
      if (tm.rooms > 0 && (tm.mean.size() != F || tm.inverse_covariance.size() != F * F))
        throw std::runtime_error("type " + std::to_string(t + 1) + ": mean / inverse_covariance do not match the features");
      tm.log_det_covariance = types[size_t(t)].at("log_det_covariance").get<double>();
      tm.proxy_type_id = types[size_t(t)].value("proxy_type_id", 0);
      if (tm.proxy_type_id < 0 || tm.proxy_type_id > kRoomShapeTypes) throw std::runtime_error("proxy_type_id out of range");
      for (double x : tm.mean)
        if (!std::isfinite(x)) throw std::runtime_error("non-finite mean");
      for (double x : tm.inverse_covariance)
        if (!std::isfinite(x)) throw std::runtime_error("non-finite inverse covariance");
    }
    if (j.contains("adjacency")) {
      m.adjacency = j.at("adjacency").get<decltype(m.adjacency)>();
      for (const auto& row : m.adjacency)
        for (double x : row)
          if (!std::isfinite(x)) throw std::runtime_error("non-finite adjacency");
    }
    if (!(m.max_ratio >= 0 && m.min_ratio >= 0)) throw std::runtime_error("max_ratio and min_ratio must be >= 0");
  } catch (const std::exception& e) {
    return Status::InvalidInput(FileError(path, std::string("not a room-shape model: ") + e.what(),
                                          "write one with `semvox train --room-shapes`"));
  }
  return m;
}

}  // namespace semvox
