#include "mapping/octomap_io.h"

#include <octomap/OcTree.h>
#include <octomap/OccupancyOcTreeBase.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "core/file_util.h"

namespace semvox {
namespace {
// Debian's liboctomap is built with debug output on (" done." on stderr when writing); silence it.
class ScopedSilenceStderr {
 public:
  ScopedSilenceStderr() {
    std::fflush(stderr);
    saved_ = ::dup(2);
    const int null = ::open("/dev/null", O_WRONLY);
    if (saved_ >= 0 && null >= 0) ::dup2(null, 2);
    if (null >= 0) ::close(null);
  }
  ~ScopedSilenceStderr() {
    std::fflush(stderr);
    if (saved_ >= 0) ::dup2(saved_, 2), ::close(saved_);
  }
 private:
  int saved_ = -1;
};
}  // namespace

Status WriteOctomapBinary(const VoxelGrid& grid, const std::string& path) {
  octomap::OcTree tree(grid.resolution());
  const float hit = tree.getClampingThresMaxLog(), miss = tree.getClampingThresMinLog();
  const auto& d = grid.dims();
  for (int iz = 0; iz < d[2]; ++iz)
    for (int iy = 0; iy < d[1]; ++iy)
      for (int ix = 0; ix < d[0]; ++ix) {
        const VoxelState s = grid.state(grid.Index(ix, iy, iz));
        if (s == VoxelState::kUnknown) continue;
        const VoxelKey k = grid.KeyOf(ix, iy, iz);
        tree.setNodeValue(octomap::OcTreeKey(k.x, k.y, k.z), s == VoxelState::kOccupied ? hit : miss, true);
      }
  tree.updateInnerOccupancy();
  tree.prune();
  std::ostringstream os;
  bool ok;
  {
    ScopedSilenceStderr silence;
    ok = tree.writeBinaryConst(os);
  }
  if (!ok) return Status::Internal(FileError(path, "OctoMap serialisation failed", ""));
  return WriteFileAtomic(path, os.str());
}

Result<std::vector<std::pair<VoxelKey, bool>>> ReadOctomapLeaves(const std::string& path, double* resolution) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  std::istringstream is(bytes);
  octomap::OcTree tree(0.1);
  bool ok;
  {
    ScopedSilenceStderr silence;
    ok = tree.readBinary(is);
  }
  if (!ok) return Status::InvalidInput(FileError(path, "not an OctoMap binary tree", ""));
  *resolution = tree.getResolution();
  std::vector<std::pair<VoxelKey, bool>> out;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    const int depth = int(it.getDepth());
    const int span = 1 << (16 - depth);
    const octomap::OcTreeKey base = it.getIndexKey();
    const bool occ = tree.isNodeOccupied(*it);
    for (int dz = 0; dz < span; ++dz)
      for (int dy = 0; dy < span; ++dy)
        for (int dx = 0; dx < span; ++dx)
          out.push_back({VoxelKey{uint16_t(base[0] + dx), uint16_t(base[1] + dy), uint16_t(base[2] + dz)}, occ});
  }
  std::sort(out.begin(), out.end());
  return out;
}

// ---- Semantic OctoMap (map.ot) ----
namespace {

// A leaf of the semantic tree: OcTreeNode's occupancy log-odds plus label and confidence.
class SemanticOcTreeNode : public octomap::OcTreeNode {
 public:
  SemanticOcTreeNode() = default;
  SemanticOcTreeNode(const SemanticOcTreeNode& rhs) : OcTreeNode(rhs), label(rhs.label), confidence(rhs.confidence) {}
  bool operator==(const SemanticOcTreeNode& rhs) const {
    return rhs.value == value && rhs.label == label && rhs.confidence == confidence;
  }
  void copyData(const SemanticOcTreeNode& from) {
    OcTreeNode::copyData(from);
    label = from.label;
    confidence = from.confidence;
  }
  std::istream& readData(std::istream& s) {
    s.read(reinterpret_cast<char*>(&value), sizeof(value));
    s.read(reinterpret_cast<char*>(&label), sizeof(label));
    s.read(reinterpret_cast<char*>(&confidence), sizeof(confidence));
    return s;
  }
  std::ostream& writeData(std::ostream& s) const {
    s.write(reinterpret_cast<const char*>(&value), sizeof(value));
    s.write(reinterpret_cast<const char*>(&label), sizeof(label));
    s.write(reinterpret_cast<const char*>(&confidence), sizeof(confidence));
    return s;
  }
  uint16_t label = 0;
  float confidence = 0;
};

class SemanticOcTree : public octomap::OccupancyOcTreeBase<SemanticOcTreeNode> {
 public:
  explicit SemanticOcTree(double resolution) : OccupancyOcTreeBase<SemanticOcTreeNode>(resolution) {
    registration_.ensureLinking();
  }
  SemanticOcTree* create() const override { return new SemanticOcTree(resolution); }
  std::string getTreeType() const override { return "SemanticOcTree"; }

 private:
  // Registers the tree type with OctoMap's factory, so AbstractOcTree::read can create it.
  struct Registration {
    Registration() {
      auto* tree = new SemanticOcTree(0.1);
      tree->clearKeyRays();
      AbstractOcTree::registerTreeType(tree);
    }
    void ensureLinking() {}
  };
  static Registration registration_;
};
SemanticOcTree::Registration SemanticOcTree::registration_;

}  // namespace

Status WriteSemanticOctree(const std::vector<SemanticVoxel>& voxels, double resolution, const std::string& path) {
  SemanticOcTree tree(resolution);
  const float hit = tree.getClampingThresMaxLog(), miss = tree.getClampingThresMinLog();
  for (const SemanticVoxel& v : voxels) {
    SemanticOcTreeNode* node = tree.setNodeValue(octomap::OcTreeKey(v.key.x, v.key.y, v.key.z), v.occupied ? hit : miss, true);
    node->label = v.label;
    node->confidence = v.confidence;
  }
  tree.updateInnerOccupancy();
  tree.prune();
  std::ostringstream os;
  bool ok;
  {
    ScopedSilenceStderr silence;
    ok = tree.write(os);
  }
  if (!ok) return Status::Internal(FileError(path, "OctoMap serialisation failed", ""));
  return WriteFileAtomic(path, os.str());
}

Result<std::vector<SemanticVoxel>> ReadSemanticOctree(const std::string& path, double* resolution) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  std::istringstream is(bytes);
  std::unique_ptr<octomap::AbstractOcTree> any;
  {
    ScopedSilenceStderr silence;
    any.reset(octomap::AbstractOcTree::read(is));
  }
  auto* tree = dynamic_cast<SemanticOcTree*>(any.get());
  if (!tree) return Status::InvalidInput(FileError(path, "not a semantic OctoMap (tree type SemanticOcTree)", "write it with `semvox run`"));
  *resolution = tree->getResolution();
  std::vector<SemanticVoxel> out;
  for (auto it = tree->begin_leafs(), end = tree->end_leafs(); it != end; ++it) {
    const int span = 1 << (16 - int(it.getDepth()));
    const octomap::OcTreeKey base = it.getIndexKey();
    SemanticVoxel v;
    v.occupied = tree->isNodeOccupied(*it);
    v.label = it->label;
    v.confidence = it->confidence;
    for (int dz = 0; dz < span; ++dz)
      for (int dy = 0; dy < span; ++dy)
        for (int dx = 0; dx < span; ++dx) {
          v.key = VoxelKey{uint16_t(base[0] + dx), uint16_t(base[1] + dy), uint16_t(base[2] + dz)};
          out.push_back(v);
        }
  }
  std::sort(out.begin(), out.end(), [](const SemanticVoxel& a, const SemanticVoxel& b) { return a.key.Pack() < b.key.Pack(); });
  return out;
}

struct OccupancyOctree::Impl {
  explicit Impl(double r) : tree(r) {}
  octomap::OcTree tree;
};

OccupancyOctree::OccupancyOctree(double resolution) : impl_(std::make_unique<Impl>(resolution)) {}
OccupancyOctree::~OccupancyOctree() = default;
OccupancyOctree::OccupancyOctree(OccupancyOctree&&) noexcept = default;

void OccupancyOctree::Apply(const FrameUpdate& update) {
  for (const VoxelKey& k : update.free) impl_->tree.updateNode(octomap::OcTreeKey(k.x, k.y, k.z), false, true);
  for (const VoxelKey& k : update.occupied) impl_->tree.updateNode(octomap::OcTreeKey(k.x, k.y, k.z), true, true);
  impl_->tree.updateInnerOccupancy();
}

size_t OccupancyOctree::num_nodes() const { return impl_->tree.size(); }

Status OccupancyOctree::WriteBinary(const std::string& path) const {
  std::ostringstream os;
  bool ok;
  {
    ScopedSilenceStderr silence;
    ok = impl_->tree.writeBinaryConst(os);
  }
  if (!ok) return Status::Internal(FileError(path, "OctoMap serialisation failed", ""));
  return WriteFileAtomic(path, os.str());
}

}  // namespace semvox
