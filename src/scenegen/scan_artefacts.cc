#include "scenegen/scan_artefacts.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <unordered_map>

#include "core/labels.h"
#include "scenegen/random.h"

namespace semvox {

bool ScanArtefactOptions::Check(std::string* error) const {
  std::ostringstream os;
  if (!(hidden_margin_m >= 0)) os << "hidden_margin_m = " << hidden_margin_m << ". Violated constraint: >= 0";
  else if (!(holes_per_m2 >= 0)) os << "holes_per_m2 = " << holes_per_m2 << ". Violated constraint: >= 0";
  else if (!(min_hole_radius_m > 0 && max_hole_radius_m >= min_hole_radius_m))
    os << "min_hole_radius_m = " << min_hole_radius_m << ", max_hole_radius_m = " << max_hole_radius_m
       << ". Violated constraint: 0 < min_hole_radius_m <= max_hole_radius_m";
  else if (!(unscanned_ceiling_fraction >= 0 && unscanned_ceiling_fraction <= 1))
    os << "unscanned_ceiling_fraction = " << unscanned_ceiling_fraction << ". Violated constraint: in [0, 1]";
  else if (!(face_dropout >= 0 && face_dropout < 1)) os << "face_dropout = " << face_dropout << ". Violated constraint: in [0, 1)";
  else if (!(vertex_noise_m >= 0)) os << "vertex_noise_m = " << vertex_noise_m << ". Violated constraint: >= 0";
  else if (!(roughness_m >= 0)) os << "roughness_m = " << roughness_m << ". Violated constraint: >= 0";
  else if (!(roughness_wavelength_m > 0))
    os << "roughness_wavelength_m = " << roughness_wavelength_m << ". Violated constraint: > 0";
  if (os.str().empty()) return true;
  if (error) *error = os.str();
  return false;
}

namespace {

bool InsideBox(const OrientedBox& b, const Eigen::Vector3d& p, double margin) {
  const double c = std::cos(b.yaw_rad), s = std::sin(b.yaw_rad);
  const Eigen::Vector3d d = p - b.center;
  const double lx = c * d.x() + s * d.y(), ly = -s * d.x() + c * d.y();
  return std::fabs(lx) <= b.size.x() / 2 + margin && std::fabs(ly) <= b.size.y() / 2 + margin &&
         std::fabs(d.z()) <= b.size.z() / 2 + margin;
}

// Parts bucketed on a 2-D grid by their footprint bounds, for local look-ups.
class PartIndex {
 public:
  PartIndex(const std::vector<SolidPart>& parts, double cell, double margin) : cell_(cell) {
    for (size_t i = 0; i < parts.size(); ++i) {
      const OrientedBox& b = parts[i].box;
      const double c = std::fabs(std::cos(b.yaw_rad)), s = std::fabs(std::sin(b.yaw_rad));
      const double ex = b.size.x() / 2 * c + b.size.y() / 2 * s + margin, ey = b.size.x() / 2 * s + b.size.y() / 2 * c + margin;
      for (long ix = Cell(b.center.x() - ex); ix <= Cell(b.center.x() + ex); ++ix)
        for (long iy = Cell(b.center.y() - ey); iy <= Cell(b.center.y() + ey); ++iy) grid_[Key(ix, iy)].push_back(int(i));
    }
  }
  const std::vector<int>* At(const Eigen::Vector3d& p) const {
    auto it = grid_.find(Key(Cell(p.x()), Cell(p.y())));
    return it == grid_.end() ? nullptr : &it->second;
  }

 private:
  long Cell(double v) const { return long(std::floor(v / cell_)); }
  static uint64_t Key(long ix, long iy) { return (uint64_t(uint32_t(ix)) << 32) | uint32_t(iy); }
  double cell_;
  std::unordered_map<uint64_t, std::vector<int>> grid_;
};

// A standard normal value that depends only on (key, stream).
double HashNormal(uint64_t key, uint64_t stream) {
  const uint64_t a = SplitMix64(key ^ SplitMix64(stream)), b = SplitMix64(a);
  const double u1 = (double(a >> 11) + 1.0) * 0x1.0p-53, u2 = double(b >> 11) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

}  // namespace

Mesh ApplyScanArtefacts(const Apartment& apt, const ScanArtefactOptions& o) {
  using namespace nyu40;
  const Mesh& in = apt.mesh;
  const size_t nf = in.faces.size();
  const std::vector<int32_t>& label = in.face_attributes.at("label");
  Rng rng(SplitMix64(o.seed ^ 0x5ca17e5ULL));
  std::vector<uint8_t> keep(nf, 1);
  std::vector<Eigen::Vector3d> centroid(nf);
  std::vector<double> area(nf);
  for (size_t f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = in.vertices[size_t(in.faces[f][0])].cast<double>(), b = in.vertices[size_t(in.faces[f][1])].cast<double>(),
                          c = in.vertices[size_t(in.faces[f][2])].cast<double>();
    centroid[f] = (a + b + c) / 3.0;
    area[f] = 0.5 * (b - a).cross(c - a).norm();
  }
  auto structural = [&](size_t f) { return label[f] == kWall || label[f] == kFloor || label[f] == kCeiling; };

  if (o.remove_hidden) {
    const PartIndex index(apt.parts, 0.5, o.hidden_margin_m);
    for (size_t f = 0; f < nf; ++f) {
      const std::vector<int>* cand = index.At(centroid[f]);
      if (!cand) continue;
      const int own = f < apt.face_part.size() ? apt.face_part[f] : -1;
      const bool is_structural = structural(f);
      for (int p : *cand) {
        if (p == own) continue;
        const SolidPart& part = apt.parts[size_t(p)];
        // Walls, floors and ceilings are hidden by furniture only (not by other wall pieces, whose ends
        // they meet, nor by doors and windows set into them).
        if (is_structural && (part.structural || part.label == kDoor || part.label == kWindow)) continue;
        // Hidden only when the whole face is: a large face (a mattress top) partly under a pillow stays.
        if (InsideBox(part.box, centroid[f], o.hidden_margin_m) &&
            InsideBox(part.box, in.vertices[size_t(in.faces[f][0])].cast<double>(), o.hidden_margin_m) &&
            InsideBox(part.box, in.vertices[size_t(in.faces[f][1])].cast<double>(), o.hidden_margin_m) &&
            InsideBox(part.box, in.vertices[size_t(in.faces[f][2])].cast<double>(), o.hidden_margin_m)) {
          keep[f] = 0;
          break;
        }
      }
    }
  }

  // Holes in walls and floors, centred on random surface points (area-weighted).
  std::vector<size_t> surf;
  std::vector<double> cum;
  double total = 0;
  for (size_t f = 0; f < nf; ++f)
    if (label[f] == kWall || label[f] == kFloor) {
      total += area[f];
      surf.push_back(f);
      cum.push_back(total);
    }
  const int holes = int(std::lround(o.holes_per_m2 * total));
  for (int h = 0; h < holes && total > 0; ++h) {
    const double t = rng.Uniform(0, total);
    const size_t k = size_t(std::lower_bound(cum.begin(), cum.end(), t) - cum.begin());
    const Eigen::Vector3d centre = centroid[surf[std::min(k, surf.size() - 1)]];
    const double r = rng.Uniform(o.min_hole_radius_m, o.max_hole_radius_m);
    // Walls and floors only: they are tessellated finely; furniture faces are whole box sides.
    for (size_t f : surf)
      if ((centroid[f] - centre).squaredNorm() <= r * r) keep[f] = 0;
  }

  // Unscanned ceiling patches until the target fraction of the ceiling area is gone.
  std::vector<size_t> ceil;
  double ceil_area = 0;
  for (size_t f = 0; f < nf; ++f)
    if (label[f] == kCeiling) ceil.push_back(f), ceil_area += area[f];
  double removed = 0;
  for (int it = 0; it < 500 && !ceil.empty() && removed < o.unscanned_ceiling_fraction * ceil_area; ++it) {
    const Eigen::Vector3d centre = centroid[ceil[size_t(rng.UniformInt(0, int(ceil.size()) - 1))]];
    const double r = rng.Uniform(0.4, 1.2);
    for (size_t f : ceil)
      if (keep[f] && (centroid[f] - centre).head<2>().squaredNorm() <= r * r) keep[f] = 0, removed += area[f];
  }

  if (o.face_dropout > 0)
    for (size_t f = 0; f < nf; ++f)
      if (rng.Bernoulli(o.face_dropout)) keep[f] = 0;

  // Assemble, keeping only used vertices; noise and roughness by clean position.
  Mesh out;
  std::vector<int> remap(in.vertices.size(), -1);
  for (const auto& [name, values] : in.face_attributes) out.face_attributes[name];
  const double phase_seed = double(o.seed % 1000003);
  const double w = 2 * M_PI / o.roughness_wavelength_m;
  const double ph[6] = {phase_seed * 0.37, phase_seed * 0.73, phase_seed * 1.31, phase_seed * 1.97, phase_seed * 2.41, phase_seed * 2.83};
  for (size_t f = 0; f < nf; ++f) {
    if (!keep[f]) continue;
    Eigen::Vector3i tri;
    for (int k = 0; k < 3; ++k) {
      const int v = in.faces[f][k];
      if (remap[size_t(v)] < 0) {
        remap[size_t(v)] = int(out.vertices.size());
        const Eigen::Vector3d p = in.vertices[size_t(v)].cast<double>();
        Eigen::Vector3d q = p;
        if (o.vertex_noise_m > 0) {
          const uint64_t key = SplitMix64(uint64_t(std::llround(p.x() * 1e4))) ^ SplitMix64(uint64_t(std::llround(p.y() * 1e4)) + 1) ^
                               SplitMix64(uint64_t(std::llround(p.z() * 1e4)) + 2) ^ o.seed;
          for (int d = 0; d < 3; ++d) q[d] += o.vertex_noise_m * HashNormal(key, uint64_t(d));
        }
        if (o.roughness_m > 0) {
          q.x() += o.roughness_m * std::sin(w * p.y() + ph[0]) * std::cos(w * p.z() + ph[1]);
          q.y() += o.roughness_m * std::sin(w * p.z() + ph[2]) * std::cos(w * p.x() + ph[3]);
          q.z() += o.roughness_m * std::sin(w * p.x() + ph[4]) * std::cos(w * p.y() + ph[5]);
        }
        out.vertices.push_back(q.cast<float>());
        if (in.has_vertex_colors()) out.vertex_colors.push_back(in.vertex_colors[size_t(v)]);
      }
      tri[k] = remap[size_t(v)];
    }
    out.faces.push_back(tri);
    for (const auto& [name, values] : in.face_attributes) out.face_attributes[name].push_back(values[f]);
  }
  return out;
}

}  // namespace semvox
