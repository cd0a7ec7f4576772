#include "perception/superpixels.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/slic.hpp>
#include <vector>

namespace semvox {

bool SuperpixelOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (region_size_px < 4 || region_size_px > 256)
    return fail("region_size_px = " + std::to_string(region_size_px) + ". Violated constraint: 4 <= region_size_px <= 256");
  if (!(compactness > 0))
    return fail("compactness = " + std::to_string(compactness) + ". Violated constraint: compactness > 0");
  if (iterations < 1 || iterations > 100)
    return fail("iterations = " + std::to_string(iterations) + ". Violated constraint: 1 <= iterations <= 100");
  if (min_element_size_percent < 0 || min_element_size_percent > 100)
    return fail("min_element_size_percent = " + std::to_string(min_element_size_percent) +
                ". Violated constraint: 0 <= min_element_size_percent <= 100");
  return true;
}

namespace {

cv::Mat ToMat(const ImageRgb8& rgb) {
  // OpenCV wants BGR; copy once into a contiguous Mat.
  cv::Mat bgr(rgb.height, rgb.width, CV_8UC3);
  for (int y = 0; y < rgb.height; ++y) {
    auto* row = bgr.ptr<cv::Vec3b>(y);
    for (int x = 0; x < rgb.width; ++x) row[x] = cv::Vec3b(rgb.at(x, y, 2), rgb.at(x, y, 1), rgb.at(x, y, 0));
  }
  return bgr;
}

}  // namespace

Result<Superpixels> ComputeSuperpixels(const ImageRgb8& rgb, const SuperpixelOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("superpixels: " + error);
  if (rgb.empty() || rgb.channels != 3 || rgb.data.size() != size_t(rgb.width) * rgb.height * 3)
    return Status::InvalidInput("superpixels: expected a non-empty 3-channel image, got " +
                                std::to_string(rgb.width) + "x" + std::to_string(rgb.height) + "x" +
                                std::to_string(rgb.channels));
  cv::Mat lab;
  cv::cvtColor(ToMat(rgb), lab, cv::COLOR_BGR2Lab);  // 8-bit LAB: what SLIC's distance expects.
  cv::Ptr<cv::ximgproc::SuperpixelSLIC> slic = cv::ximgproc::createSuperpixelSLIC(
      lab, cv::ximgproc::SLIC, options.region_size_px, float(options.compactness));
  slic->iterate(options.iterations);
  if (options.min_element_size_percent > 0) slic->enforceLabelConnectivity(options.min_element_size_percent);
  cv::Mat labels;
  slic->getLabels(labels);  // CV_32SC1.

  // Renumber to [0, count) in raster order of first appearance, so ids are dense and deterministic.
  Superpixels out;
  out.label = Image<int32_t>(rgb.width, rgb.height, 1, -1);
  std::vector<int32_t> remap(size_t(slic->getNumberOfSuperpixels()) + 1, -1);
  for (int y = 0; y < rgb.height; ++y) {
    const int32_t* row = labels.ptr<int32_t>(y);
    for (int x = 0; x < rgb.width; ++x) {
      const int32_t l = row[x];
      if (l < 0) return Status::Internal("superpixels: SLIC returned a negative label");
      if (size_t(l) >= remap.size()) remap.resize(size_t(l) + 1, -1);
      if (remap[l] < 0) remap[l] = out.count++;
      out.label.at(x, y) = remap[l];
    }
  }
  return out;
}

ImageF32 RgbToLab(const ImageRgb8& rgb) {
  ImageF32 out(rgb.width, rgb.height, 3);
  if (rgb.empty()) return out;
  cv::Mat f;
  ToMat(rgb).convertTo(f, CV_32FC3, 1.0 / 255.0);
  cv::Mat lab;
  cv::cvtColor(f, lab, cv::COLOR_BGR2Lab);  // Float input in [0, 1]: L in [0, 100].
  for (int y = 0; y < rgb.height; ++y) {
    const auto* row = lab.ptr<cv::Vec3f>(y);
    for (int x = 0; x < rgb.width; ++x)
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = row[x][c];
  }
  return out;
}

}  // namespace semvox
