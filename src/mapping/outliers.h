// Trimming of stray geometry far from the scan (a single point 1 km away must not blow up the grid).
#pragma once

#include "core/geometry.h"

namespace semvox {

struct OutlierOptions {
  double quantile = 0.001;     // Robust bounds per axis: [q, 1 - q] quantiles of the vertices. [0, 0.1].
  double margin_factor = 0.5;  // Keep everything within margin_factor * robust extent (>= min_margin_m).
  double min_margin_m = 1.0;   // Metres.
};

struct OutlierReport {
  size_t removed_vertices = 0;  // Points (clouds) or vertices (meshes) outside the kept box.
  size_t removed_faces = 0;     // Meshes: faces with a vertex outside the kept box.
  Aabb kept_box;
};

// Removes points, or faces with any vertex, outside the robust box. Unused vertices stay (harmless).
OutlierReport TrimOutliers(Scene* scene, const OutlierOptions& options = {});

}  // namespace semvox
