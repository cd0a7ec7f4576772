#include "io/image_encode.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace semvox {

Result<std::string> EncodePng(const ImageRgb8& image) {
  if (image.empty() || (image.channels != 1 && image.channels != 3) ||
      image.data.size() != size_t(image.width) * image.height * image.channels)
    return Status::Internal("EncodePng: image must be non-empty with 1 or 3 channels");
  cv::Mat m(image.height, image.width, image.channels == 3 ? CV_8UC3 : CV_8UC1, const_cast<uint8_t*>(image.data.data()));
  cv::Mat bgr;
  if (image.channels == 3) cv::cvtColor(m, bgr, cv::COLOR_RGB2BGR);
  else bgr = m;
  std::vector<uchar> buf;
  try {
    if (!cv::imencode(".png", bgr, buf)) return Status::Internal("EncodePng: OpenCV could not encode the PNG");
  } catch (const cv::Exception& e) {
    return Status::Internal(std::string("EncodePng: ") + e.what());
  }
  return std::string(buf.begin(), buf.end());
}

}  // namespace semvox
