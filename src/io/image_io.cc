#include "io/image_io.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <algorithm>
#include <cstring>

#include "core/file_util.h"

namespace semvox {
namespace {

ImageRgb8 FromMat(const cv::Mat& m) {
  cv::Mat rgb;
  if (m.channels() == 1) {
    cv::Mat g8;
    m.convertTo(g8, CV_8U, m.depth() == CV_16U ? 1.0 / 257.0 : 1.0);
    cv::Mat chans[3] = {g8, g8, g8};
    cv::merge(chans, 3, rgb);
  } else {
    cv::Mat m8;
    m.convertTo(m8, CV_8U, m.depth() == CV_16U ? 1.0 / 257.0 : 1.0);
    if (m8.channels() == 4) cv::cvtColor(m8, rgb, cv::COLOR_BGRA2RGB);  // NOLINT
    else cv::cvtColor(m8, rgb, cv::COLOR_BGR2RGB);
  }
  ImageRgb8 img(rgb.cols, rgb.rows, 3);
  for (int y = 0; y < rgb.rows; ++y) std::memcpy(&img.at(0, y), rgb.ptr(y), size_t(rgb.cols) * 3);
  return img;
}

Status Encode(const std::string& path, const cv::Mat& m) {
  std::string ext = "." + LowerExtension(path);
  std::vector<uchar> buf;
  try {
    if (!cv::imencode(ext, m, buf))
      return Status::Internal(FileError(path, "image encoding failed", "use .png"));
  } catch (const cv::Exception& e) {
    return Status::InvalidInput(FileError(path, "cannot encode image as " + ext, "use .png"));
  }
  return WriteFileAtomic(path, std::string(buf.begin(), buf.end()));
}

// Only formats semvox reads or writes are handed to OpenCV; anything else would reach fallback decoders
// (GDAL) that print to stderr and widen the attack surface of untrusted input.
bool KnownImageMagic(const std::string& b) {
  auto starts = [&](const char* m, size_t n) { return b.size() >= n && b.compare(0, n, m, n) == 0; };
  return starts("\x89PNG\r\n\x1a\n", 8) || starts("\xff\xd8\xff", 3) || starts("P5", 2) || starts("P2", 2) ||
         starts("P6", 2) || starts("P3", 2) || starts("BM", 2) || starts("II*\0", 4) || starts("MM\0*", 4);
}

// Decodes bytes of a known image format with OpenCV's `flags`; errors name `name`.
Result<cv::Mat> DecodeMat(const std::string& bytes, const std::string& name, int flags, const char* hint) {
  if (!KnownImageMagic(bytes))
    return Status::InvalidInput(FileError(name, "not a PNG, JPEG, PGM/PPM, BMP or TIFF image", "convert the image to PNG"));
  cv::Mat m;
  try {
    std::vector<uchar> buf(bytes.begin(), bytes.end());
    m = cv::imdecode(buf, flags);
  } catch (const cv::Exception&) {
    m = cv::Mat();
  }
  if (m.empty()) return Status::InvalidInput(FileError(name, "cannot decode image", hint));
  return m;
}

Result<cv::Mat> ReadMat(const std::string& path, int flags, const char* hint) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  return DecodeMat(bytes, path, flags, hint);
}

}  // namespace

Result<ImageRgb8> DecodeImageRgb8(const std::string& bytes, const std::string& name) {
  Result<cv::Mat> m = DecodeMat(bytes, name, cv::IMREAD_UNCHANGED, "use PNG or JPEG");
  if (!m.ok()) return m.status();
  return FromMat(m.value());
}

Result<ImageRgb8> ReadImageRgb8(const std::string& path) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  return DecodeImageRgb8(bytes, path);
}

Result<Image<uint8_t>> ReadImageGrey8(const std::string& path) {
  Result<cv::Mat> m = ReadMat(path, cv::IMREAD_GRAYSCALE, "use an 8-bit PNG or PGM");
  if (!m.ok()) return m.status();
  Image<uint8_t> img(m->cols, m->rows, 1);
  for (int y = 0; y < m->rows; ++y) std::memcpy(&img.at(0, y), m->ptr(y), size_t(m->cols));
  return img;
}

Result<ImageU16> ReadImageU16(const std::string& path) {
  Result<cv::Mat> m = ReadMat(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE, "use an 8- or 16-bit PNG");
  if (!m.ok()) return m.status();
  cv::Mat m16;
  m->convertTo(m16, CV_16U);
  ImageU16 img(m16.cols, m16.rows, 1);
  for (int y = 0; y < m16.rows; ++y) std::memcpy(&img.at(0, y), m16.ptr(y), size_t(m16.cols) * 2);
  return img;
}

Status WriteImage(const std::string& path, const ImageRgb8& image) {
  if (image.channels == 1) {
    cv::Mat m(image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.data.data()));
    return Encode(path, m);
  }
  cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<uint8_t*>(image.data.data())), bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return Encode(path, bgr);
}

Status WriteImage(const std::string& path, const ImageU16& image) {
  cv::Mat m(image.height, image.width, CV_16UC1, const_cast<uint16_t*>(image.data.data()));
  return Encode(path, m);
}

ImageRgb8 AppendLegend(const ImageRgb8& image, const std::vector<std::pair<Rgb8, std::string>>& entries) {
  const int row_h = 18, swatch = 12, pad = 6;
  int text_w = 0;
  for (const auto& e : entries) {
    int base = 0;
    text_w = std::max(text_w, cv::getTextSize(e.second, cv::FONT_HERSHEY_SIMPLEX, 0.4, 1, &base).width);
  }
  const int legend_w = entries.empty() ? 0 : pad * 3 + swatch + text_w;
  const int h = std::max(image.height, pad * 2 + row_h * int(entries.size()));
  cv::Mat out(h, image.width + legend_w, CV_8UC3, cv::Scalar(255, 255, 255));
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) out.at<cv::Vec3b>(y, x)[c] = image.channels == 3 ? image.at(x, y, c) : image.at(x, y, 0);
  for (size_t i = 0; i < entries.size(); ++i) {
    const int y = pad + int(i) * row_h;
    const int x = image.width + pad;
    const Rgb8& c = entries[i].first;
    cv::rectangle(out, cv::Rect(x, y + 2, swatch, swatch), cv::Scalar(c.r, c.g, c.b), cv::FILLED);
    cv::rectangle(out, cv::Rect(x, y + 2, swatch, swatch), cv::Scalar(0, 0, 0), 1);
    cv::putText(out, entries[i].second, cv::Point(x + swatch + pad, y + 12), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  ImageRgb8 result(out.cols, out.rows, 3);
  std::memcpy(result.data.data(), out.data, result.data.size());  // The Mat holds R, G, B in that order here.
  return result;
}

}  // namespace semvox
