#include "mapping/cloud_geometry.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <nanoflann.hpp>

namespace semvox {
namespace {

struct CloudAdaptor {
  const std::vector<Eigen::Vector3f>& pts;
  size_t kdtree_get_point_count() const { return pts.size(); }
  float kdtree_get_pt(size_t i, size_t d) const { return pts[i][int(d)]; }
  template <class B>
  bool kdtree_get_bbox(B&) const { return false; }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, CloudAdaptor>, CloudAdaptor, 3>;

}  // namespace

CloudGeometry EstimateCloudGeometry(const PointCloud& cloud, int k) {
  CloudGeometry g;
  const size_t n = cloud.points.size();
  g.normals.assign(n, Eigen::Vector3f::UnitZ());
  g.spacing.assign(n, 0.0f);
  if (n < 3) return g;
  CloudAdaptor adaptor{cloud.points};
  KdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  const size_t kk = std::min<size_t>(size_t(k) + 1, n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<uint32_t> idx(kk);
    std::vector<float> d2(kk);
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const size_t found = tree.knnSearch(cloud.points[i].data(), kk, idx.data(), d2.data());
      Eigen::Vector3f mean = Eigen::Vector3f::Zero();
      double dist = 0;
      int m = 0;
      for (size_t j = 0; j < found; ++j) {
        mean += cloud.points[idx[j]];
        if (idx[j] != i) dist += std::sqrt(double(d2[j])), ++m;
      }
      mean /= float(found);
      Eigen::Matrix3f cov = Eigen::Matrix3f::Zero();
      for (size_t j = 0; j < found; ++j) {
        const Eigen::Vector3f d = cloud.points[idx[j]] - mean;
        cov += d * d.transpose();
      }
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> es(cov);
      Eigen::Vector3f nrm = es.eigenvectors().col(0);
      if (nrm.z() < 0) nrm = -nrm;
      if (nrm.allFinite() && nrm.norm() > 0.5f) g.normals[i] = nrm.normalized();
      g.spacing[i] = m > 0 ? float(dist / m) : 0.0f;
    }
  });
  return g;
}

}  // namespace semvox
