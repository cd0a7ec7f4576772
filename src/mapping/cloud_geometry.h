// Local geometry of a point cloud: PCA normals and point spacing from k nearest neighbours.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/geometry.h"

namespace semvox {

struct CloudGeometry {
  std::vector<Eigen::Vector3f> normals;  // Unit, oriented towards +Z where ambiguous (sign is arbitrary).
  std::vector<float> spacing;            // Mean distance to the k nearest neighbours, metres.
};

CloudGeometry EstimateCloudGeometry(const PointCloud& cloud, int k);

}  // namespace semvox
