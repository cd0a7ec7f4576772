#include "perception/room_evidence.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "perception/superpixels.h"

namespace semvox {

int RoomDescriptorDims(int num_classes) { return num_classes + 6 + 1 + 2 + 1 + 1; }

std::vector<float> RoomViewDescriptor(const RenderedView& view, const Image<int32_t>& classes, int num_classes) {
  std::vector<float> d(static_cast<size_t>(RoomDescriptorDims(num_classes)), 0.0f);
  const int w = view.rgb.width, h = view.rgb.height;
  if (w == 0 || h == 0 || classes.width != w || classes.height != h) return d;
  const ImageF32 lab = RgbToLab(view.rgb);
  std::vector<double> hist(static_cast<size_t>(num_classes), 0.0);
  double lab_sum[3] = {0, 0, 0}, lab_sq[3] = {0, 0, 0}, grad = 0, depth = 0, depth_sq = 0;
  long hits = 0, upper = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!view.hit(x, y)) continue;
      ++hits;
      if (y < h / 2) ++upper;
      const int c = classes.at(x, y);
      if (c >= 0 && c < num_classes) hist[size_t(c)] += 1;
      for (int k = 0; k < 3; ++k) {
        lab_sum[k] += lab.at(x, y, k);
        lab_sq[k] += double(lab.at(x, y, k)) * lab.at(x, y, k);
      }
      if (x + 1 < w && y + 1 < h)
        grad += std::hypot(lab.at(x + 1, y, 0) - lab.at(x, y, 0), lab.at(x, y + 1, 0) - lab.at(x, y, 0));
      depth += view.depth.at(x, y);
      depth_sq += double(view.depth.at(x, y)) * view.depth.at(x, y);
    }
  if (hits == 0) return d;
  const double n = double(hits);
  size_t i = 0;
  for (int c = 0; c < num_classes; ++c) d[i++] = float(hist[size_t(c)] / n);
  for (int k = 0; k < 3; ++k) d[i++] = float(lab_sum[k] / n);
  for (int k = 0; k < 3; ++k) d[i++] = float(std::sqrt(std::max(0.0, lab_sq[k] / n - (lab_sum[k] / n) * (lab_sum[k] / n))));
  d[i++] = float(grad / n);
  d[i++] = float(depth / n);
  d[i++] = float(std::sqrt(std::max(0.0, depth_sq / n - (depth / n) * (depth / n))));
  d[i++] = float(n / (double(w) * h));
  d[i++] = float(double(upper) / n);
  return d;
}

double ObjectPixelFraction(const RenderedView& view, const Image<int32_t>& classes, const std::vector<bool>& is_object_class) {
  long hits = 0, objects = 0;
  for (int y = 0; y < view.rgb.height; ++y)
    for (int x = 0; x < view.rgb.width; ++x) {
      if (!view.hit(x, y)) continue;
      ++hits;
      const int c = classes.at(x, y);
      if (c >= 0 && size_t(c) < is_object_class.size() && is_object_class[size_t(c)]) ++objects;
    }
  return hits > 0 ? double(objects) / double(hits) : 0.0;
}

std::vector<double> RoomTypeProbabilities(const KnnClassifier& knn, const std::vector<float>& descriptor,
                                          double object_fraction, double min_object_fraction) {
  if (object_fraction < min_object_fraction || knn.dims() != int(descriptor.size())) {
    std::vector<double> p(size_t(kNumRoomTypeClasses), 0.0);
    p[kOtherRoomTypeIndex] = 1.0;
    return p;
  }
  return knn.Probabilities(descriptor);
}

std::vector<double> RoomTypeProbabilities(const KnnClassifier& knn, const std::vector<float>& descriptor,
                                          double object_fraction, double min_object_fraction, double familiar_distance,
                                          double* unfamiliarity) {
  *unfamiliarity = std::numeric_limits<double>::quiet_NaN();
  if (object_fraction < min_object_fraction || knn.dims() != int(descriptor.size()))
    return RoomTypeProbabilities(knn, descriptor, object_fraction, min_object_fraction);
  double distance = 0;
  std::vector<double> p = knn.Probabilities(descriptor, &distance);
  if (familiar_distance > 0 && std::isfinite(distance)) *unfamiliarity = distance / familiar_distance;
  return p;
}

double DiscountUnfamiliarRoomView(double unfamiliarity, std::vector<double>* p) {
  if (!std::isfinite(unfamiliarity) || p->empty()) return 0;
  const double lambda = std::clamp(unfamiliarity - 1.0, 0.0, 1.0);
  if (lambda <= 0) return 0;
  double sum = 0;
  for (double v : *p) sum += v;
  const double uniform = sum / double(p->size());
  for (double& v : *p) v = (1 - lambda) * v + lambda * uniform;
  return lambda;
}

std::vector<bool> RoomObjectClasses(const std::vector<std::string>& class_names) {
  std::vector<bool> out;
  for (const std::string& name : class_names)
    out.push_back(name != "wall" && name != "floor" && name != "ceiling" && name != "window" && name != "door");
  return out;
}

}  // namespace semvox
