#include "objects/support_fusion.h"

#include <algorithm>

#include "core/ply.h"
#include "io/image_io.h"

namespace semvox {

bool SupportFusionOptions::Check(std::string* error) const {
  if (!CheckOptions(*this, Options(), error)) return false;
  if (!(voxel_size_m > 0)) {
    if (error) *error = "voxel_size_m = " + std::to_string(voxel_size_m) + ". Violated constraint: voxel_size_m > 0";
    return false;
  }
  return true;
}

Status SupportClutterFusion::AddView(const RenderedView& view, const std::vector<float>& probabilities) {
  std::string error;
  if (!options_.Check(&error)) return Status::InvalidInput("support fusion options: " + error);
  const size_t n = size_t(view.rgb.width) * size_t(view.rgb.height);
  if (probabilities.size() != n * 3 || view.voxel_key.data.size() != n || view.primitive.data.size() != n)
    return Status::InvalidInput("support fusion: probabilities (" + std::to_string(probabilities.size()) + " values) must be 3 per pixel of the view (" +
                                std::to_string(n) + " pixels)");
  for (size_t i = 0; i < n; ++i) {
    if (view.primitive.data[i] < 0) continue;
    Acc& a = acc_[view.voxel_key.data[i].Pack()];
    for (int c = 0; c < 3; ++c) a.sum[size_t(c)] += probabilities[i * 3 + size_t(c)];
    ++a.count;
  }
  ++views_;
  return Status::Ok();
}

std::vector<SupportVoxel> SupportClutterFusion::Voxels() const {
  std::vector<SupportVoxel> out;
  out.reserve(acc_.size());
  for (const auto& [packed, a] : acc_) {
    SupportVoxel v;
    v.key = VoxelKey{uint16_t(packed >> 32), uint16_t(packed >> 16), uint16_t(packed)};
    v.centre = KeyToCoord(v.key, options_.voxel_size_m).cast<float>();
    double s = a.sum[0] + a.sum[1] + a.sum[2];
    if (!(s > 0)) s = 1;
    for (int c = 0; c < 3; ++c) v.p[size_t(c)] = float(a.sum[size_t(c)] / s);
    const int best = int(std::max_element(v.p.begin(), v.p.end()) - v.p.begin());
    v.label = best < 2 && v.p[size_t(best)] >= options_.min_label_probability ? uint8_t(best + 1) : uint8_t(0);
    v.observations = a.count;
    out.push_back(v);
  }
  std::sort(out.begin(), out.end(), [](const SupportVoxel& a, const SupportVoxel& b) { return a.key < b.key; });
  return out;
}

Status SupportClutterFusion::WritePly(const std::string& path, const Eigen::Isometry3d& input_from_world) const {
  const bool identity = IsIdentity(input_from_world);
  const std::vector<SupportVoxel> voxels = Voxels();
  const size_t n = voxels.size();
  std::vector<double> x(n), y(n), z(n), label(n), ps(n), pc(n), po(n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d c = identity ? Eigen::Vector3d(voxels[i].centre.cast<double>())
                                       : Eigen::Vector3d(input_from_world * voxels[i].centre.cast<double>());
    x[i] = c.x(), y[i] = c.y(), z[i] = c.z();
    label[i] = voxels[i].label;
    ps[i] = voxels[i].p[0], pc[i] = voxels[i].p[1], po[i] = voxels[i].p[2];
  }
  PlyWriter w;
  w.AddComment("semvox support_clutter: label 1 support, 2 clutter, 0 other; voxel size " + std::to_string(options_.voxel_size_m) + " m; " +
               std::to_string(views_) + " views");
  w.AddElement("vertex", n);
  w.AddProperty("x", PlyType::kFloat32, std::move(x));
  w.AddProperty("y", PlyType::kFloat32, std::move(y));
  w.AddProperty("z", PlyType::kFloat32, std::move(z));
  w.AddProperty("label", PlyType::kUInt8, std::move(label));
  w.AddProperty("p_support", PlyType::kFloat32, std::move(ps));
  w.AddProperty("p_clutter", PlyType::kFloat32, std::move(pc));
  w.AddProperty("p_other", PlyType::kFloat32, std::move(po));
  return w.Write(path);
}

ImageRgb8 SupportClutterFusion::TopView(const VoxelGrid& grid) const {
  const auto& d = grid.dims();
  ImageRgb8 img(d[0], d[1], 3, 255);
  std::vector<int> top(size_t(d[0]) * size_t(d[1]), -1);
  // Background: the grid's top-down state (any occupied voxel in the column -> occupied, else free if any
  // free voxel, else unknown).
  for (int iy = 0; iy < d[1]; ++iy)
    for (int ix = 0; ix < d[0]; ++ix) {
      bool occupied = false, free = false;
      for (int iz = 0; iz < d[2]; ++iz) {
        const VoxelState s = grid.state(grid.Index(ix, iy, iz));
        occupied |= s == VoxelState::kOccupied;
        free |= s == VoxelState::kFree;
      }
      const uint8_t g = occupied ? 90 : (free ? 255 : 200);
      for (int c = 0; c < 3; ++c) img.at(ix, d[1] - 1 - iy, c) = g;
    }
  for (const SupportVoxel& v : Voxels()) {
    if (v.label == 0) continue;
    std::array<int, 3> cell;
    if (!grid.CellOfKey(v.key, &cell)) continue;
    int& t = top[size_t(cell[1]) * size_t(d[0]) + size_t(cell[0])];
    if (cell[2] <= t) continue;
    t = cell[2];
    const Rgb8 colour = v.label == 1 ? Rgb8{40, 170, 60} : Rgb8{220, 40, 40};
    img.at(cell[0], d[1] - 1 - cell[1], 0) = colour.r;
    img.at(cell[0], d[1] - 1 - cell[1], 1) = colour.g;
    img.at(cell[0], d[1] - 1 - cell[1], 2) = colour.b;
  }
  return img;
}

Status SupportClutterFusion::WriteTopView(const std::string& path, const VoxelGrid& grid) const {
  return WriteImage(path, TopView(grid));
}

}  // namespace semvox
