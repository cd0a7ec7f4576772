#include "objects/proposals.h"

#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <queue>
#include <set>
#include <unordered_map>

#include "core/file_util.h"
#include "core/hash.h"
#include "objects/support_fusion.h"

namespace semvox {
namespace {

double MsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Median depth of a box (on a grid of at most 16 x 16 samples), 0 without depth.
double MedianDepth(const RenderedView& view, const Box2i& b) {
  std::vector<float> d;
  const int sx = std::max(1, b.width() / 16), sy = std::max(1, b.height() / 16);
  for (int y = b.y0; y < b.y1; y += sy)
    for (int x = b.x0; x < b.x1; x += sx)
      if (view.depth.at(x, y) > 0) d.push_back(view.depth.at(x, y));
  if (d.size() < 3) return 0;
  std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
  return d[d.size() / 2];
}

}  // namespace

bool ProposalOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!CheckOptions(*this, Options(), error)) return false;
  if (!(min_side_m > 0 && max_side_m >= min_side_m)) return fail("min_side_m, max_side_m = " + std::to_string(min_side_m) + ", " + std::to_string(max_side_m) + ". Violated constraint: 0 < min_side_m <= max_side_m");
  if (border_px < 1) return fail("border_px = " + std::to_string(border_px) + ". Violated constraint: border_px >= 1");
  if (colour_bins < 2 || colour_bins > 64) return fail("colour_bins = " + std::to_string(colour_bins) + ". Violated constraint: 2 <= colour_bins <= 64");
  if (!(nms_iou > 0 && nms_iou <= 1)) return fail("nms_iou = " + std::to_string(nms_iou) + ". Violated constraint: 0 < nms_iou <= 1");
  if (max_per_view < 1) return fail("max_per_view = " + std::to_string(max_per_view) + ". Violated constraint: max_per_view >= 1");
  if (!(depth_band_m > 0)) return fail("depth_band_m = " + std::to_string(depth_band_m) + ". Violated constraint: depth_band_m > 0");
  return true;
}

double BoxIoU(const Box2i& a, const Box2i& b) {
  const int ix = std::max(0, std::min(a.x1, b.x1) - std::max(a.x0, b.x0));
  const int iy = std::max(0, std::min(a.y1, b.y1) - std::max(a.y0, b.y0));
  const double inter = double(ix) * iy;
  const double uni = double(a.width()) * a.height() + double(b.width()) * b.height() - inter;
  return uni > 0 ? inter / uni : 0.0;
}

ClassIntegral ClassIntegral::Build(int width, int height, const std::vector<float>& p) {
  ClassIntegral c;
  c.width = width, c.height = height;
  c.sum.assign(size_t(width + 1) * size_t(height + 1) * 4, 0.0);
  if (p.size() != size_t(width) * size_t(height) * 4) {  // No probabilities: uniform.
    for (int y = 1; y <= height; ++y)
      for (int x = 1; x <= width; ++x)
        for (int k = 0; k < 4; ++k) c.sum[(size_t(y) * size_t(width + 1) + size_t(x)) * 4 + size_t(k)] = 0.25 * x * y;
    return c;
  }
  for (int y = 1; y <= height; ++y)
    for (int x = 1; x <= width; ++x)
      for (int k = 0; k < 4; ++k) {
        const size_t i = (size_t(y) * size_t(width + 1) + size_t(x)) * 4 + size_t(k);
        c.sum[i] = p[(size_t(y - 1) * size_t(width) + size_t(x - 1)) * 4 + size_t(k)] + c.sum[i - 4] +
                   c.sum[i - size_t(width + 1) * 4] - c.sum[i - size_t(width + 1) * 4 - 4];
      }
  return c;
}

std::array<double, 4> ClassIntegral::Mean(const Box2i& b) const {
  std::array<double, 4> m{0.25, 0.25, 0.25, 0.25};
  const int x0 = std::clamp(b.x0, 0, width), x1 = std::clamp(b.x1, 0, width), y0 = std::clamp(b.y0, 0, height), y1 = std::clamp(b.y1, 0, height);
  if (x1 <= x0 || y1 <= y0) return m;
  double total = 0;
  auto at = [&](int x, int y, int k) { return sum[(size_t(y) * size_t(width + 1) + size_t(x)) * 4 + size_t(k)]; };
  for (int k = 0; k < 4; ++k) total += (m[size_t(k)] = at(x1, y1, k) - at(x0, y1, k) - at(x1, y0, k) + at(x0, y0, k));
  if (total > 0)
    for (double& v : m) v /= total;
  return m;
}

GradientMaps GradientMaps::Compute(const RenderedView& view) {
  const int w = view.rgb.width, h = view.rgb.height;
  GradientMaps g;
  g.intensity_magnitude = g.intensity_bin = g.depth_magnitude = g.depth_bin = ImageF32(w, h, 1, 0.f);
  auto grey = [&](int x, int y) { return 0.299f * view.rgb.at(x, y, 0) + 0.587f * view.rgb.at(x, y, 1) + 0.114f * view.rgb.at(x, y, 2); };
  auto bin = [](float gx, float gy) {
    double a = std::atan2(double(gy), double(gx)) * 180.0 / M_PI;  // (-180, 180]
    if (a < 0) a += 360.0;
    return float(std::min(8, int(a / 40.0)));
  };
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      const float gx = 0.5f * (grey(x + 1, y) - grey(x - 1, y)), gy = 0.5f * (grey(x, y + 1) - grey(x, y - 1));
      g.intensity_magnitude.at(x, y) = std::sqrt(gx * gx + gy * gy);
      g.intensity_bin.at(x, y) = bin(gx, gy);
      const float l = view.depth.at(x - 1, y), r = view.depth.at(x + 1, y), u = view.depth.at(x, y - 1), d = view.depth.at(x, y + 1);
      if (l > 0 && r > 0 && u > 0 && d > 0) {
        const float dx = 0.5f * (r - l), dy = 0.5f * (d - u);
        g.depth_magnitude.at(x, y) = std::sqrt(dx * dx + dy * dy);
        g.depth_bin.at(x, y) = bin(dx, dy);
      }
    }
  return g;
}

std::vector<float> WindowFeature(const GradientMaps& g, const ClassIntegral& nyu4, const Box2i& box, int b) {
  std::vector<float> f(kProposalFeatureDims, 0.f);
  const int w = g.intensity_magnitude.width, h = g.intensity_magnitude.height;
  // Blocks w1 (top), w2 (right), w3 (bottom), w4 (left) between the box shrunk and enlarged by b.
  const Box2i blocks[4] = {{box.x0 - b, box.y0 - b, box.x1 + b, box.y0 + b},
                           {box.x1 - b, box.y0 + b, box.x1 + b, box.y1 - b},
                           {box.x0 - b, box.y1 - b, box.x1 + b, box.y1 + b},
                           {box.x0 - b, box.y0 + b, box.x0 + b, box.y1 - b}};
  for (int k = 0; k < 4; ++k) {
    const Box2i& r = blocks[k];
    float* hi = &f[size_t(k) * 9];
    float* hd = &f[36 + size_t(k) * 9];
    for (int y = std::max(0, r.y0); y < std::min(h, r.y1); ++y)
      for (int x = std::max(0, r.x0); x < std::min(w, r.x1); ++x) {
        hi[int(g.intensity_bin.at(x, y))] += g.intensity_magnitude.at(x, y);
        hd[int(g.depth_bin.at(x, y))] += g.depth_magnitude.at(x, y);
      }
    for (float* hist : {hi, hd}) {
      float s = 0;
      for (int i = 0; i < 9; ++i) s += hist[i];
      if (s > 0)
        for (int i = 0; i < 9; ++i) hist[i] /= s;
    }
  }
  const std::array<double, 4> p = nyu4.Mean(box);
  for (int k = 0; k < 4; ++k) f[size_t(kBoundaryFeatureDims + k)] = float(p[size_t(k)]);
  return f;
}

std::vector<CandidateWindow> CandidateWindows(const RenderedView& view, const Superpixels& sp, const ClassIntegral& nyu4,
                                              const ProposalOptions& options, CandidateStats* stats) {
  const int w = view.rgb.width, h = view.rgb.height, bins = options.colour_bins;
  const double image_area = double(w) * h;
  struct Region {
    std::vector<float> hist;  // L1-normalised colour histogram, 3 x bins.
    double size = 0;
    Box2i box{1 << 30, 1 << 30, -1, -1};
    std::set<int> neighbours;
    bool alive = true;
  };
  std::vector<Region> regions(size_t(sp.count));
  for (Region& r : regions) r.hist.assign(size_t(3 * bins), 0.f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      Region& r = regions[size_t(sp.label.at(x, y))];
      for (int c = 0; c < 3; ++c) r.hist[size_t(c * bins + view.rgb.at(x, y, c) * bins / 256)] += 1.f;
      r.size += 1;
      r.box.x0 = std::min(r.box.x0, x), r.box.y0 = std::min(r.box.y0, y);
      r.box.x1 = std::max(r.box.x1, x + 1), r.box.y1 = std::max(r.box.y1, y + 1);
      if (x + 1 < w && sp.label.at(x + 1, y) != sp.label.at(x, y)) {
        r.neighbours.insert(sp.label.at(x + 1, y));
        regions[size_t(sp.label.at(x + 1, y))].neighbours.insert(sp.label.at(x, y));
      }
      if (y + 1 < h && sp.label.at(x, y + 1) != sp.label.at(x, y)) {
        r.neighbours.insert(sp.label.at(x, y + 1));
        regions[size_t(sp.label.at(x, y + 1))].neighbours.insert(sp.label.at(x, y));
      }
    }
  for (Region& r : regions)
    for (float& v : r.hist) v /= float(3 * std::max(1.0, r.size));
  auto similarity = [&](const Region& a, const Region& b) {
    double colour = 0;
    for (size_t i = 0; i < a.hist.size(); ++i) colour += std::min(a.hist[i], b.hist[i]);
    const double size = 1.0 - (a.size + b.size) / image_area;
    const Box2i u{std::min(a.box.x0, b.box.x0), std::min(a.box.y0, b.box.y0), std::max(a.box.x1, b.box.x1), std::max(a.box.y1, b.box.y1)};
    const double fill = 1.0 - (double(u.width()) * u.height() - a.size - b.size) / image_area;
    return 3.0 * colour + size + fill;  // Colour histograms sum to 1 over 3 channels: scale to [0, 1] per channel.
  };
  struct Pair {
    double s;
    int a, b;
    bool operator<(const Pair& o) const { return s != o.s ? s < o.s : (a != o.a ? a > o.a : b > o.b); }
  };
  std::priority_queue<Pair> queue;
  for (int a = 0; a < sp.count; ++a)
    for (int b : regions[size_t(a)].neighbours)
      if (a < b) queue.push({similarity(regions[size_t(a)], regions[size_t(b)]), a, b});
  while (!queue.empty()) {
    const Pair p = queue.top();
    queue.pop();
    if (!regions[size_t(p.a)].alive || !regions[size_t(p.b)].alive) continue;  // Stale pair.
    Region merged;
    const Region& a = regions[size_t(p.a)];
    const Region& b = regions[size_t(p.b)];
    merged.size = a.size + b.size;
    merged.hist.resize(a.hist.size());
    for (size_t i = 0; i < a.hist.size(); ++i) merged.hist[i] = float((a.hist[i] * a.size + b.hist[i] * b.size) / merged.size);
    merged.box = {std::min(a.box.x0, b.box.x0), std::min(a.box.y0, b.box.y0), std::max(a.box.x1, b.box.x1), std::max(a.box.y1, b.box.y1)};
    for (int n : a.neighbours) if (n != p.b) merged.neighbours.insert(n);
    for (int n : b.neighbours) if (n != p.a) merged.neighbours.insert(n);
    const int id = int(regions.size());
    regions[size_t(p.a)].alive = regions[size_t(p.b)].alive = false;
    for (int n : merged.neighbours) {
      regions[size_t(n)].neighbours.erase(p.a);
      regions[size_t(n)].neighbours.erase(p.b);
      regions[size_t(n)].neighbours.insert(id);
    }
    regions.push_back(std::move(merged));
    for (int n : regions[size_t(id)].neighbours) queue.push({similarity(regions[size_t(id)], regions[size_t(n)]), std::min(n, id), std::max(n, id)});
  }
  CandidateStats s;
  s.regions = int(regions.size());
  std::vector<CandidateWindow> out;
  std::set<std::array<int, 4>> seen;
  for (const Region& r : regions) {
    if (r.box.x1 <= r.box.x0 || !seen.insert({r.box.x0, r.box.y0, r.box.x1, r.box.y1}).second) continue;
    ++s.windows;
    const double z = MedianDepth(view, r.box);
    if (!(z > 0)) continue;
    CandidateWindow c;
    c.box = r.box;
    c.width_m = r.box.width() * z / view.camera.fx;
    c.height_m = r.box.height() * z / view.camera.fy;
    if (c.width_m < options.min_side_m || c.width_m > options.max_side_m || c.height_m < options.min_side_m || c.height_m > options.max_side_m) continue;
    ++s.sized;
    const std::array<double, 4> p = nyu4.Mean(r.box);
    c.semantic = p[2] + p[3];
    if (options.sample_by_semantics) {
      const uint64_t hsh = SplitMix64(options.seed ^ SplitMix64((uint64_t(r.box.x0) << 48) ^ (uint64_t(r.box.y0) << 32) ^ (uint64_t(r.box.x1) << 16) ^ uint64_t(r.box.y1)));
      const double u = double(hsh >> 11) * (1.0 / 9007199254740992.0);
      if (u >= c.semantic) continue;
    }
    ++s.sampled;
    out.push_back(c);
  }
  if (stats) *stats = s;
  return out;
}

Result<ObjectProposer> ObjectProposer::Train(const std::vector<float>& rows, const std::vector<int>& labels, const ProposalOptions& options,
                                             const SvmOptions& svm_options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("proposal options: " + error);
  SvmOptions o = svm_options;
  o.kernel = SvmKernel::kHistogramIntersection;
  Result<SvmClassifier> svm = SvmClassifier::Train(rows, kProposalFeatureDims, labels, 2, o);
  if (!svm.ok()) return svm.status();
  return ObjectProposer(std::move(svm).value(), options);
}

Result<ObjectProposer> ObjectProposer::Load(const std::string& path, const ProposalOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("proposal options: " + error);
  Result<SvmClassifier> svm = SvmClassifier::Load(path);
  if (!svm.ok()) return svm.status();
  if (svm->dims() != kProposalFeatureDims || svm->num_classes() != 2)
    return Status::InvalidInput(path + ": not an object-proposal SVM (expected 76 dims, 2 classes; hint: retrain with `semvox train`)");
  return ObjectProposer(std::move(svm).value(), options);
}

double ObjectProposer::Score(const std::vector<float>& feature) const {
  double p[2];
  svm_.PredictProbabilities(feature.data(), p);
  return p[1];
}

bool BackProject(const RenderedView& view, const Box2i& box, double band, Eigen::Vector3d* centre, Eigen::Vector3d* size) {
  const double z = MedianDepth(view, box);
  if (!(z > 0)) return false;
  std::array<std::vector<double>, 3> coords;
  const Eigen::Matrix3d R = view.world_from_camera.linear();
  const Eigen::Vector3d t = view.world_from_camera.translation();
  for (int y = std::max(0, box.y0); y < std::min(view.depth.height, box.y1); ++y)
    for (int x = std::max(0, box.x0); x < std::min(view.depth.width, box.x1); ++x) {
      const float d = view.depth.at(x, y);
      if (!(d > 0) || std::abs(d - z) > band) continue;
      const Eigen::Vector3d p = t + R * (view.camera.PixelRay(x, y) * double(d));
      for (int k = 0; k < 3; ++k) coords[size_t(k)].push_back(p[k]);
    }
  if (coords[0].size() < 10) return false;
  for (int k = 0; k < 3; ++k) {
    std::vector<double>& c = coords[size_t(k)];
    std::sort(c.begin(), c.end());
    const double lo = c[c.size() * 5 / 100], hi = c[std::min(c.size() - 1, c.size() * 95 / 100)];
    (*centre)[k] = 0.5 * (lo + hi);
    (*size)[k] = std::max(1e-3, hi - lo);
  }
  return true;
}

Result<ViewProposals> ObjectProposer::Propose(const RenderedView& view, const Superpixels& superpixels, const std::vector<float>& nyu4) const {
  ViewProposals out;
  auto t0 = std::chrono::steady_clock::now();
  const ClassIntegral integral = ClassIntegral::Build(view.rgb.width, view.rgb.height, nyu4);
  std::vector<CandidateWindow> candidates = CandidateWindows(view, superpixels, integral, options_, &out.stats);
  out.ms_candidates = MsSince(t0);
  t0 = std::chrono::steady_clock::now();
  const GradientMaps gradients = GradientMaps::Compute(view);
  std::vector<std::vector<float>> features(candidates.size());
  tbb::parallel_for(size_t(0), candidates.size(), [&](size_t i) { features[i] = WindowFeature(gradients, integral, candidates[i].box, options_.border_px); });
  out.ms_features = MsSince(t0);
  t0 = std::chrono::steady_clock::now();
  std::vector<double> scores(candidates.size());
  tbb::parallel_for(size_t(0), candidates.size(), [&](size_t i) { scores[i] = Score(features[i]); });
  out.ms_svm = MsSince(t0);
  std::vector<size_t> order(candidates.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return scores[a] > scores[b]; });
  for (size_t i : order) {
    if (scores[i] < options_.min_score || int(out.proposals.size()) >= options_.max_per_view) break;
    bool suppressed = false;
    for (const ObjectProposal& p : out.proposals) suppressed |= BoxIoU(p.box, candidates[i].box) > options_.nms_iou;
    if (suppressed) continue;
    ObjectProposal p;
    p.box = candidates[i].box;
    p.score = scores[i];
    p.has_3d = BackProject(view, p.box, options_.depth_band_m, &p.centre, &p.size);
    out.proposals.push_back(p);
  }
  return out;
}

namespace {

double BoxIoU3(const Eigen::Vector3d& ca, const Eigen::Vector3d& sa, const Eigen::Vector3d& cb, const Eigen::Vector3d& sb) {
  double inter = 1;
  for (int k = 0; k < 3; ++k) {
    const double lo = std::max(ca[k] - sa[k] / 2, cb[k] - sb[k] / 2), hi = std::min(ca[k] + sa[k] / 2, cb[k] + sb[k] / 2);
    inter *= std::max(0.0, hi - lo);
  }
  const double uni = sa.prod() + sb.prod() - inter;
  return uni > 0 ? inter / uni : 0.0;
}

}  // namespace

void ProposalMerger::Add(const std::vector<ObjectProposal>& proposals) {
  for (const ObjectProposal& p : proposals) {
    if (!p.has_3d) continue;
    Merged* target = nullptr;
    for (Merged& m : merged_)
      if (BoxIoU3(m.centre, m.size, p.centre, p.size) >= min_iou_) {
        target = &m;
        break;
      }
    if (!target) {
      merged_.push_back({p.centre, p.size, p.score, p.score, 1});
      continue;
    }
    const double w = std::max(1e-6, p.score), total = target->weight + w;
    target->centre = (target->centre * target->weight + p.centre * w) / total;
    target->size = (target->size * target->weight + p.size * w) / total;
    target->weight = total;
    target->score = std::max(target->score, p.score);
    ++target->views;
  }
}

Status ProposalMerger::WriteJson(const std::string& path, const SupportClutterFusion* fusion, double voxel_size_m,
                                 const Eigen::Isometry3d& input_from_world) const {
  const bool identity = IsIdentity(input_from_world);
  // Support voxels by column.
  std::unordered_map<uint64_t, std::vector<double>> support_z;
  if (fusion)
    for (const SupportVoxel& v : fusion->Voxels())
      if (v.label == 1) support_z[(uint64_t(v.key.x) << 16) | v.key.y].push_back(v.centre.z());
  std::vector<size_t> order(merged_.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return merged_[a].score > merged_[b].score; });
  nlohmann::json proposals = nlohmann::json::array();
  int supported = 0;
  for (size_t i : order) {
    const Merged& m = merged_[i];
    nlohmann::json j;
    auto r4 = [](double v) { return std::round(v * 1e4) / 1e4; };
    const Eigen::Vector3d centre = identity ? Eigen::Vector3d(m.centre.cast<double>()) : Eigen::Vector3d(input_from_world * m.centre.cast<double>());
    j["centre"] = {r4(centre.x()), r4(centre.y()), r4(centre.z())};
    j["size"] = {r4(m.size.x()), r4(m.size.y()), r4(m.size.z())};
    j["score"] = r4(m.score);
    j["views"] = m.views;
    // The highest support voxel under the footprint whose centre is within 0.15 m below to 0.05 m above the
    // box's bottom.
    const double bottom = m.centre.z() - m.size.z() / 2;
    double best = -1e9;
    int count = 0;
    for (int64_t kx = CoordToKeyIndex(m.centre.x() - m.size.x() / 2, voxel_size_m); kx <= CoordToKeyIndex(m.centre.x() + m.size.x() / 2, voxel_size_m); ++kx)
      for (int64_t ky = CoordToKeyIndex(m.centre.y() - m.size.y() / 2, voxel_size_m); ky <= CoordToKeyIndex(m.centre.y() + m.size.y() / 2, voxel_size_m); ++ky) {
        const auto it = support_z.find((uint64_t(kx) << 16) | uint64_t(ky));
        if (it == support_z.end()) continue;
        for (double z : it->second)
          if (z >= bottom - 0.15 && z <= bottom + 0.05) best = std::max(best, z), ++count;
      }
    if (count > 0) {
      // Input-frame z of the support's top below the box centre.
      const double top = identity ? best + voxel_size_m / 2
                                  : (input_from_world * Eigen::Vector3d(m.centre.x(), m.centre.y(), best + voxel_size_m / 2)).z();
      j["supporting_surface"] = {{"z", r4(top)}, {"voxels", count}};
      ++supported;
    } else {
      j["supporting_surface"] = nullptr;
    }
    proposals.push_back(j);
  }
  nlohmann::json root;
  root["count"] = proposals.size();
  root["on_support"] = supported;
  root["proposals"] = proposals;
  return WriteFileAtomic(path, root.dump(1) + "\n");
}

}  // namespace semvox
