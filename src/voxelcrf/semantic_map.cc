#include "voxelcrf/semantic_map.h"

#include <algorithm>
#include <utility>
#include <deque>
#include <map>

#include "core/labels.h"
#include "core/ply.h"
#include "io/image_io.h"
#include "mapping/occupancy_map.h"

namespace semvox {

SemanticMap MakeSemanticMap(const VoxelGrid& grid, const VoxelCrfNodes& nodes, const VoxelEvidence& ev,
                            const VoxelCrfResult& result, const VoxelCrfModel& model) {
  SemanticMap m;
  const size_t n = nodes.size();
  m.node_occupied.assign(n, 0);
  std::vector<int32_t> record_of_node(n, -1);
  // Nodes are in block order; records go in grid-index order.
  std::vector<uint32_t> order;
  for (size_t i = 0; i < n; ++i)
    if (result.labels[i] > 0) m.node_occupied[i] = 1, order.push_back(uint32_t(i));
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return nodes.voxel[a] < nodes.voxel[b]; });
  m.occupied.reserve(order.size());
  for (uint32_t i : order) {
    SemanticVoxelRecord r;
    r.voxel = nodes.voxel[i];
    const auto c = grid.Cell(r.voxel);
    r.centre = grid.CellCenter(c[0], c[1], c[2]).cast<float>();
    const int cls = result.labels[i] - 1;
    r.label = uint16_t(cls < model.num_classes() ? model.nyu40_of_class[size_t(cls)] : 0);
    r.confidence = result.confidence[i];
    r.completed = nodes.initial_state[i] == uint8_t(VoxelState::kUnknown);
    if (ev.hits[i] > 0) r.rgb = ev.colour[i];
    record_of_node[i] = int32_t(m.occupied.size());
    m.occupied.push_back(r);
  }
  // Colour of voxels without observed colour: nearest observed voxel of the same label.
  std::vector<int> dist(m.occupied.size(), -1);
  std::deque<uint32_t> queue;
  for (size_t k = 0; k < m.occupied.size(); ++k) {
    const int32_t node = nodes.node_of_voxel[m.occupied[k].voxel];
    if (ev.hits[size_t(node)] > 0) dist[k] = 0, queue.push_back(uint32_t(k));
  }
  const auto& d = grid.dims();
  while (!queue.empty()) {
    const uint32_t k = queue.front();
    queue.pop_front();
    if (dist[k] >= 20) continue;
    const auto c = grid.Cell(m.occupied[k].voxel);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
          if (x < 0 || y < 0 || z < 0 || x >= d[0] || y >= d[1] || z >= d[2]) continue;
          const int32_t node = nodes.node_of_voxel[grid.Index(x, y, z)];
          if (node < 0) continue;
          const int32_t j = record_of_node[size_t(node)];
          if (j < 0 || dist[size_t(j)] >= 0 || m.occupied[size_t(j)].label != m.occupied[k].label) continue;
          dist[size_t(j)] = dist[k] + 1;
          m.occupied[size_t(j)].rgb = m.occupied[k].rgb;
          queue.push_back(uint32_t(j));
        }
  }
  for (size_t k = 0; k < m.occupied.size(); ++k)
    if (dist[k] < 0) {
      const Rgb8 c = Nyu40Labels()[std::min<size_t>(m.occupied[k].label, kNumNyu40 - 1)].color;
      m.occupied[k].rgb = {c.r, c.g, c.b};
    }
  return m;
}

VoxelGrid SemanticMap::RefinedGrid(const VoxelGrid& grid, const VoxelCrfNodes& nodes) const {
  VoxelGrid out = grid;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (node_occupied[i])
      out.set_state(nodes.voxel[i], VoxelState::kOccupied);
    else if (nodes.initial_state[i] == uint8_t(VoxelState::kOccupied))
      out.set_state(nodes.voxel[i], VoxelState::kFree);
  }
  return out;
}

const SemanticVoxelRecord* SemanticMap::Find(uint32_t voxel) const {
  const auto it = std::lower_bound(occupied.begin(), occupied.end(), voxel,
                                   [](const SemanticVoxelRecord& r, uint32_t v) { return r.voxel < v; });
  return it == occupied.end() || it->voxel != voxel ? nullptr : &*it;
}

SemanticVoxelRecord* SemanticMap::Find(uint32_t voxel) {
  return const_cast<SemanticVoxelRecord*>(std::as_const(*this).Find(voxel));
}

std::vector<std::pair<int, size_t>> SemanticMap::LabelCounts() const {
  std::map<int, size_t> c;
  for (const auto& r : occupied) ++c[r.label];
  return {c.begin(), c.end()};
}

size_t SemanticMap::completed_count() const {
  return size_t(std::count_if(occupied.begin(), occupied.end(), [](const SemanticVoxelRecord& r) { return r.completed; }));
}

void AssignRooms(const ImageU16& room_ids, const VoxelGrid& grid, SemanticMap* map) {
  const auto& d = grid.dims();
  for (auto& r : map->occupied) {
    const auto c = grid.Cell(r.voxel);
    const int row = d[1] - 1 - c[1];
    r.room = -1;
    if (c[0] < room_ids.width && row >= 0 && row < room_ids.height) {
      const int id = room_ids.at(c[0], row);
      if (id > 0) r.room = id;
    }
  }
}

Status WriteVoxelsPly(const SemanticMap& map, const std::string& path, const Eigen::Isometry3d& input_from_world) {
  const bool identity = IsIdentity(input_from_world);
  const size_t n = map.occupied.size();
  std::vector<double> x(n), y(n), z(n), red(n), green(n), blue(n), label(n), conf(n), room(n), completed(n);
  for (size_t i = 0; i < n; ++i) {
    const auto& r = map.occupied[i];
    const Eigen::Vector3d c = identity ? Eigen::Vector3d(r.centre.cast<double>()) : Eigen::Vector3d(input_from_world * r.centre.cast<double>());
    x[i] = c.x(), y[i] = c.y(), z[i] = c.z();
    red[i] = r.rgb[0], green[i] = r.rgb[1], blue[i] = r.rgb[2];
    label[i] = r.label, conf[i] = r.confidence, room[i] = r.room, completed[i] = r.completed;
  }
  PlyWriter w;
  w.AddComment("semvox voxels.ply: one vertex per occupied voxel centre; label = NYU40 id (docs/outputs.md)");
  w.AddElement("vertex", n);
  w.AddProperty("x", PlyType::kFloat32, std::move(x));
  w.AddProperty("y", PlyType::kFloat32, std::move(y));
  w.AddProperty("z", PlyType::kFloat32, std::move(z));
  w.AddProperty("red", PlyType::kUInt8, std::move(red));
  w.AddProperty("green", PlyType::kUInt8, std::move(green));
  w.AddProperty("blue", PlyType::kUInt8, std::move(blue));
  w.AddProperty("label", PlyType::kUInt16, std::move(label));
  w.AddProperty("confidence", PlyType::kFloat32, std::move(conf));
  w.AddProperty("room", PlyType::kInt32, std::move(room));
  w.AddProperty("completed", PlyType::kUInt8, std::move(completed));
  return w.Write(path);
}

ImageU16 SemanticTopView(const SemanticMap& map, const VoxelGrid& grid, double floor_z, double band_min_m, double band_max_m,
                         double min_confidence) {
  const auto& d = grid.dims();
  ImageU16 img(d[0], d[1], 1, 0);
  std::vector<int> top(size_t(d[0]) * d[1], -1);
  const double lo = floor_z + band_min_m, hi = floor_z + band_max_m;
  for (const auto& r : map.occupied) {
    if (r.centre.z() < lo || r.centre.z() >= hi || r.confidence < min_confidence) continue;
    const auto c = grid.Cell(r.voxel);
    int& t = top[size_t(c[1]) * d[0] + c[0]];
    if (c[2] > t) t = c[2], img.at(c[0], d[1] - 1 - c[1]) = r.label;
  }
  return img;
}

ImageRgb8 ColourSemanticTopView(const ImageU16& labels, const ImageRgb8& occupancy_pgm, bool show_unlabelled) {
  const Rgb8 unsure{80, 80, 80};
  ImageRgb8 out(labels.width, labels.height, 3, 255);
  std::map<int, size_t> present;
  for (int y = 0; y < labels.height; ++y)
    for (int x = 0; x < labels.width; ++x) {
      const int l = labels.at(x, y);
      Rgb8 c{255, 255, 255};
      if (l > 0 && l < kNumNyu40) {
        c = Nyu40Labels()[size_t(l)].color;
        ++present[l];
      } else if (!occupancy_pgm.empty() && occupancy_pgm.at(x, y) == kPgmUnknown) {
        c = Rgb8{180, 180, 180};
      } else if (show_unlabelled && !occupancy_pgm.empty() && occupancy_pgm.at(x, y) == kPgmOccupied) {
        c = unsure;
      }
      out.at(x, y, 0) = c.r, out.at(x, y, 1) = c.g, out.at(x, y, 2) = c.b;
    }
  std::vector<std::pair<Rgb8, std::string>> legend;
  for (const auto& [l, count] : present) legend.push_back({Nyu40Labels()[size_t(l)].color, Nyu40Labels()[size_t(l)].name});
  legend.push_back({Rgb8{255, 255, 255}, "free"});
  legend.push_back({Rgb8{180, 180, 180}, "unknown"});
  if (show_unlabelled) legend.push_back({unsure, "under the confidence floor"});
  return AppendLegend(out, legend);
}

}  // namespace semvox
