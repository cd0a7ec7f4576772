#include "mapping/octomap_io.h"

#include <octomap/OcTree.h>

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
