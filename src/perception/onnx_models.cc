#include "perception/onnx_models.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "core/label_aliases.h"
#include "core/labels.h"

namespace semvox {

bool OnnxPreprocessing::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (input_width < 1 || input_width > 8192)
    return fail("input_width = " + std::to_string(input_width) + ". Violated constraint: 1 <= input_width <= 8192");
  if (input_height < 1 || input_height > 8192)
    return fail("input_height = " + std::to_string(input_height) + ". Violated constraint: 1 <= input_height <= 8192");
  if (!(pixel_scale > 0) || !std::isfinite(pixel_scale))
    return fail("pixel_scale = " + std::to_string(pixel_scale) + ". Violated constraint: pixel_scale > 0");
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(mean[size_t(c)]))
      return fail("mean[" + std::to_string(c) + "] = " + std::to_string(mean[size_t(c)]) + ". Violated constraint: finite");
    if (!(std[size_t(c)] > 0) || !std::isfinite(std[size_t(c)]))
      return fail("std[" + std::to_string(c) + "] = " + std::to_string(std[size_t(c)]) + ". Violated constraint: std > 0");
  }
  return true;
}

// ---- label maps ----

namespace {

std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const size_t e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

bool ParseInt(const std::string& s, long long* value) {
  if (s.empty() || s.size() > 9) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  *value = std::stoll(s);
  return true;
}

std::string RoomTypeHint() {
  std::string names;
  for (const std::string& n : RoomTypeAliases()) {
    if (!names.empty()) names += ", ";
    names += n;
  }
  return "use an id 1-12, '-' for no room type, or a room_types.tsv name: " + names;
}

}  // namespace

Result<OnnxLabelMap> ParseOnnxLabelMap(const std::string& text, const std::string& path, LabelMapVocabulary vocabulary) {
  const bool rooms = vocabulary == LabelMapVocabulary::kRoomType;
  const std::string format_hint = "each line is NET_INDEX then a " +
                                  std::string(rooms ? "room type" : "NYU40 class") +
                                  ", e.g. '0<TAB>" + (rooms ? "bedroom" : "wall") + "'; '#' starts a comment";
  OnnxLabelMap map;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  std::vector<int> listed_on_line;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string where = path + ":" + std::to_string(line_no);
    const size_t hash = line.find('#');
    const std::string content = Trim(hash == std::string::npos ? line : line.substr(0, hash));
    if (content.empty()) continue;
    const size_t gap = content.find_first_of(" \t");
    if (gap == std::string::npos)
      return Status::InvalidInput(FileError(where, "expected NET_INDEX and a target, found '" + content + "'", format_hint));
    const std::string index_text = content.substr(0, gap);
    const std::string target = Trim(content.substr(gap));
    long long index = 0;
    if (!ParseInt(index_text, &index) || index > 1000000)
      return Status::InvalidInput(FileError(where, "'" + index_text + "' is not a network class index (0 to 1000000)", format_hint));
    int id = -1;
    long long number = 0;
    if (target == "-") {
      id = 0;
    } else if (ParseInt(target, &number)) {
      const long long max_id = rooms ? kNumRoomTypeClasses : kNumNyu40 - 1;
      if (number > max_id)
        return Status::InvalidInput(FileError(where, "id " + target + " is out of range 0-" + std::to_string(max_id),
                                              rooms ? RoomTypeHint() : "use a NYU40 id 1-40 from nyu40_classes.tsv, or '-'"));
      id = int(number);
    } else {
      id = rooms ? RoomTypeIdByAlias(target) : Nyu40IdByAlias(target);
      if (id < 0)
        return Status::InvalidInput(FileError(
            where, "'" + target + "' is not a " + (rooms ? "room type" : "NYU40 class"),
            rooms ? RoomTypeHint() : "use a NYU40 id 1-40 or a nyu40_classes.tsv name (wall, floor, cabinet, ...), or '-'"));
    }
    if (size_t(index) >= map.target_of_class.size()) {
      map.target_of_class.resize(size_t(index) + 1, -1);
      listed_on_line.resize(size_t(index) + 1, 0);
    }
    if (listed_on_line[size_t(index)] != 0)
      return Status::InvalidInput(FileError(where, "network class " + index_text + " is already mapped on line " +
                                                       std::to_string(listed_on_line[size_t(index)]),
                                            "list every class once"));
    listed_on_line[size_t(index)] = line_no;
    map.target_of_class[size_t(index)] = id > 0 ? id : -1;
    ++map.listed;
  }
  if (map.listed == 0) return Status::InvalidInput(FileError(path, "the label map lists no class", format_hint));
  return map;
}

Result<OnnxLabelMap> ReadOnnxLabelMap(const std::string& path, LabelMapVocabulary vocabulary) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return Status::InvalidInput(FileError(path, "label map not found", "pass a text file of NET_INDEX TARGET lines"));
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::InvalidInput(FileError(path, "cannot open the label map", "check its permissions"));
  std::ostringstream text;
  text << in.rdbuf();
  return ParseOnnxLabelMap(text.str(), path, vocabulary);
}

// ---- networks ----

namespace {

// Silences OpenCV's own log lines (the ONNX importer prints its errors) while it lives.
class QuietOpenCv {
 public:
  QuietOpenCv() : previous_(cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT)) {}
  ~QuietOpenCv() { cv::utils::logging::setLogLevel(previous_); }

 private:
  cv::utils::logging::LogLevel previous_;
};

std::string FirstLine(const std::string& s) {
  const std::string t = Trim(s);
  const size_t nl = t.find('\n');
  return nl == std::string::npos ? t : t.substr(0, nl);
}

struct Network {
  cv::dnn::Net net;
  std::string path;
  OnnxPreprocessing preprocessing;
  std::unique_ptr<std::mutex> mutex = std::make_unique<std::mutex>();
};

Status ReadNetwork(const std::string& path, const OnnxPreprocessing& preprocessing, Network* network) {
  std::string why;
  if (!preprocessing.Check(&why)) return Status::InvalidInput("ONNX preprocessing: " + why);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return Status::InvalidInput(FileError(path, "ONNX model not found", "pass the path of an .onnx file"));
  QuietOpenCv quiet;
  try {
    network->net = cv::dnn::readNetFromONNX(path);
  } catch (const cv::Exception& e) {
    return Status::InvalidInput(FileError(path, "not a model OpenCV DNN can read (" + FirstLine(e.err) + ")",
                                          "export the network to ONNX with opset 11-13"));
  }
  if (network->net.empty())
    return Status::InvalidInput(FileError(path, "the ONNX model holds no layers", "export the network again"));
  network->net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  network->net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  network->path = path;
  network->preprocessing = preprocessing;
  return Status::Ok();
}

// The view's RGB as the NCHW input blob of the preprocessing.
cv::Mat InputBlob(const ImageRgb8& rgb, const OnnxPreprocessing& p) {
  const int w = p.input_width, h = p.input_height;
  cv::Mat image(rgb.height, rgb.width, CV_8UC3, const_cast<uint8_t*>(rgb.data.data()));  // R, G, B.
  cv::Mat resized;
  if (rgb.width == w && rgb.height == h)
    resized = image;
  else
    cv::resize(image, resized, cv::Size(w, h), 0, 0, (w <= rgb.width && h <= rgb.height) ? cv::INTER_AREA : cv::INTER_LINEAR);
  const int sizes[] = {1, 3, h, w};
  cv::Mat blob(4, sizes, CV_32F);
  float* planes = blob.ptr<float>();
  for (int c = 0; c < 3; ++c) {
    const int source = p.bgr ? 2 - c : c;  // Blob channel c reads this RGB channel.
    const float scale = float(p.pixel_scale / p.std[size_t(source)]);
    const float offset = float(-p.mean[size_t(source)] / p.std[size_t(source)]);
    float* plane = planes + size_t(c) * size_t(w) * size_t(h);
    for (int y = 0; y < h; ++y) {
      const uint8_t* row = resized.ptr<uint8_t>(y);
      for (int x = 0; x < w; ++x) plane[size_t(y) * size_t(w) + size_t(x)] = float(row[3 * x + source]) * scale + offset;
    }
  }
  return blob;
}

Result<cv::Mat> Forward(const Network& network, const ImageRgb8& rgb) {
  if (rgb.empty() || rgb.channels != 3)
    return Status::InvalidInput(network.path + ": the view has no RGB image to classify");
  const cv::Mat blob = InputBlob(rgb, network.preprocessing);
  std::lock_guard<std::mutex> lock(*network.mutex);
  auto& net = const_cast<cv::dnn::Net&>(network.net);
  try {
    net.setInput(blob);
    return net.forward().clone();
  } catch (const cv::Exception& e) {
    return Status::InvalidInput(FileError(
        network.path, "the forward pass failed on a " + std::to_string(network.preprocessing.input_width) + "x" +
                          std::to_string(network.preprocessing.input_height) + " input (" + FirstLine(e.err) + ")",
        "set the input size the network was exported with"));
  }
}

// Turns C scores of each of n pixels (plane-major: value of class k at pixel i is scores[k * n + i]) into
// probabilities in place, per OnnxOutputKind. Loops run along the planes (contiguous) in blocks of pixels.
void ToProbabilities(float* scores, int num_classes, size_t n, OnnxOutputKind kind) {
  const size_t C = size_t(num_classes);
  if (kind == OnnxOutputKind::kAuto) {
    bool in_range = true;
    std::vector<double> sum(n, 0.0);
    for (size_t k = 0; k < C; ++k) {
      const float* s = scores + k * n;
      for (size_t i = 0; i < n; ++i) {
        in_range &= s[i] >= -1e-6f && s[i] <= 1.0f + 1e-6f;
        sum[i] += s[i];
      }
    }
    bool sums_to_one = in_range;
    for (size_t i = 0; i < n && sums_to_one; ++i) sums_to_one = std::abs(sum[i] - 1.0) <= 1e-3;
    kind = sums_to_one ? OnnxOutputKind::kProbabilities : OnnxOutputKind::kLogits;
  }
  const bool logits = kind == OnnxOutputKind::kLogits;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 2048), [&](const tbb::blocked_range<size_t>& r) {
    const size_t b = r.begin(), m = r.end() - r.begin();
    std::vector<float> top(m, -INFINITY);
    std::vector<double> sum(m, 0.0);
    if (logits) {
      for (size_t k = 0; k < C; ++k) {
        const float* s = scores + k * n + b;
        for (size_t j = 0; j < m; ++j) top[j] = std::max(top[j], s[j]);
      }
    }
    for (size_t k = 0; k < C; ++k) {
      float* s = scores + k * n + b;
      if (logits) {
        for (size_t j = 0; j < m; ++j) s[j] = std::exp(s[j] - top[j]);
      } else {
        for (size_t j = 0; j < m; ++j) s[j] = std::max(0.0f, s[j]);
      }
      for (size_t j = 0; j < m; ++j) sum[j] += s[j];
    }
    bool all_positive = true;
    for (size_t j = 0; j < m; ++j) {
      all_positive &= sum[j] > 0;
      sum[j] = sum[j] > 0 ? 1.0 / sum[j] : 0.0;
    }
    for (size_t k = 0; k < C; ++k) {
      float* s = scores + k * n + b;
      for (size_t j = 0; j < m; ++j) s[j] = float(s[j] * sum[j]);
      if (!all_positive)  // Pixels with no mass at all (probabilities that are all 0): uniform.
        for (size_t j = 0; j < m; ++j)
          if (sum[j] == 0) s[j] = float(1.0 / double(C));
    }
  });
}

// Number of classes of a scene output ([1,C], [1,C,1,1] or [C]); 0 when the shape is not one of those.
int SceneOutputClasses(const cv::Mat& out) {
  int classes = 0;
  for (int d = 0; d < out.dims; ++d) {
    if (out.size[d] == 1) continue;
    if (classes != 0) return 0;
    classes = out.size[d];
  }
  return classes == 0 && out.total() == 1 ? 1 : classes;
}

std::string ShapeText(const cv::Mat& out) {
  std::string s = "[";
  for (int d = 0; d < out.dims; ++d) {
    if (d > 0) s += ",";
    s += std::to_string(out.size[d]);
  }
  return s + "]";
}

Status CheckLabelMapFits(const OnnxLabelMap& map, int num_classes, const std::string& label_path, const std::string& onnx_path) {
  if (int(map.target_of_class.size()) > num_classes)
    return Status::InvalidInput(FileError(label_path, "lists network class " + std::to_string(map.target_of_class.size() - 1) +
                                                          " but " + onnx_path + " outputs " + std::to_string(num_classes) + " classes (0-" +
                                                          std::to_string(num_classes - 1) + ")",
                                          "the label map belongs to another network"));
  return Status::Ok();
}

// A blank (mid-grey) view of the input size, for the probe pass.
ImageRgb8 ProbeImage(const OnnxPreprocessing& p) { return ImageRgb8(p.input_width, p.input_height, 3, 128); }

}  // namespace

// ---- scene model ----

struct OnnxSceneModel::Impl {
  Network network;
  OnnxLabelMap map;
  OnnxSceneModelOptions options;
  int num_classes = 0;
};

Result<OnnxSceneModel> OnnxSceneModel::Load(const std::string& onnx_path, const std::string& label_map_path,
                                            const OnnxSceneModelOptions& options) {
  auto impl = std::make_shared<Impl>();
  impl->options = options;
  SEMVOX_RETURN_IF_ERROR(ReadNetwork(onnx_path, options.preprocessing, &impl->network));
  Result<OnnxLabelMap> map = ReadOnnxLabelMap(label_map_path, LabelMapVocabulary::kRoomType);
  if (!map.ok()) return map.status();
  impl->map = std::move(map.value());
  QuietOpenCv quiet;
  Result<cv::Mat> probe = Forward(impl->network, ProbeImage(options.preprocessing));
  if (!probe.ok()) return probe.status();
  impl->num_classes = SceneOutputClasses(*probe);
  if (impl->num_classes < 1)
    return Status::InvalidInput(FileError(onnx_path, "a scene model must output one score per class ([1,C]), not " + ShapeText(*probe),
                                          "is this a segmentation network? pass it as --object-model"));
  SEMVOX_RETURN_IF_ERROR(CheckLabelMapFits(impl->map, impl->num_classes, label_map_path, onnx_path));
  return OnnxSceneModel(std::move(impl));
}

Result<std::vector<double>> OnnxSceneModel::NetworkProbabilities(const RenderedView& view) const {
  Result<cv::Mat> out = Forward(impl_->network, view.rgb);
  if (!out.ok()) return out.status();
  if (SceneOutputClasses(*out) != impl_->num_classes)
    return Status::Internal(impl_->network.path + ": output shape changed to " + ShapeText(*out));
  cv::Mat scores = out->reshape(1, 1);
  ToProbabilities(scores.ptr<float>(), impl_->num_classes, 1, impl_->options.preprocessing.output);
  std::vector<double> p(size_t(impl_->num_classes));
  for (int k = 0; k < impl_->num_classes; ++k) p[size_t(k)] = scores.ptr<float>()[k];
  return p;
}

Result<std::vector<double>> OnnxSceneModel::RoomTypeProbabilities(const RenderedView& view) const {
  Result<std::vector<double>> net = NetworkProbabilities(view);
  if (!net.ok()) return net.status();
  std::vector<double> rooms(size_t(kNumRoomTypeClasses), 0.0);
  double unmapped = 0;
  for (size_t k = 0; k < net->size(); ++k) {
    const int id = k < impl_->map.target_of_class.size() ? impl_->map.target_of_class[k] : -1;
    if (id >= 1 && id <= kNumRoomTypeClasses)
      rooms[size_t(id - 1)] += (*net)[k];
    else
      unmapped += (*net)[k];
  }
  if (impl_->options.unmapped_to_other) rooms[size_t(kOtherRoomTypeIndex)] += unmapped;
  double sum = 0;
  for (double v : rooms) sum += v;
  if (sum > 0) {
    for (double& v : rooms) v /= sum;
  } else {
    rooms[size_t(kOtherRoomTypeIndex)] = 1.0;
  }
  return rooms;
}

int OnnxSceneModel::num_network_classes() const { return impl_->num_classes; }
const OnnxSceneModelOptions& OnnxSceneModel::options() const { return impl_->options; }

// ---- object model ----

struct OnnxObjectModel::Impl {
  Network network;
  OnnxLabelMap map;
  LabelLevel level;
  OnnxObjectModelOptions options;
  int num_classes = 0;
};

Result<OnnxObjectModel> OnnxObjectModel::Load(const std::string& onnx_path, const std::string& label_map_path,
                                              const LabelLevel& level, const OnnxObjectModelOptions& options) {
  if (level.num_classes() < 1 || int(level.class_of_nyu40.size()) != kNumNyu40)
    return Status::Internal("OnnxObjectModel: label level '" + level.name + "' needs classes and " +
                            std::to_string(kNumNyu40) + " class_of_nyu40 entries");
  auto impl = std::make_shared<Impl>();
  impl->options = options;
  impl->level = level;
  SEMVOX_RETURN_IF_ERROR(ReadNetwork(onnx_path, options.preprocessing, &impl->network));
  Result<OnnxLabelMap> map = ReadOnnxLabelMap(label_map_path, LabelMapVocabulary::kNyu40);
  if (!map.ok()) return map.status();
  impl->map = std::move(map.value());
  QuietOpenCv quiet;
  Result<cv::Mat> probe = Forward(impl->network, ProbeImage(options.preprocessing));
  if (!probe.ok()) return probe.status();
  if (probe->dims != 4 || probe->size[0] != 1 || probe->size[1] < 1)
    return Status::InvalidInput(FileError(onnx_path, "a segmentation model must output [1,C,h,w], not " + ShapeText(*probe),
                                          "is this a scene classifier? pass it as --scene-model"));
  impl->num_classes = probe->size[1];
  SEMVOX_RETURN_IF_ERROR(CheckLabelMapFits(impl->map, impl->num_classes, label_map_path, onnx_path));
  return OnnxObjectModel(std::move(impl));
}

Result<ImageF32> OnnxObjectModel::Nyu40PixelProbabilities(const RenderedView& view) const {
  Result<cv::Mat> out = Forward(impl_->network, view.rgb);
  if (!out.ok()) return out.status();
  if (out->dims != 4 || out->size[0] != 1 || out->size[1] != impl_->num_classes)
    return Status::Internal(impl_->network.path + ": output shape changed to " + ShapeText(*out));
  const int C = impl_->num_classes, oh = out->size[2], ow = out->size[3];
  const int W = view.rgb.width, H = view.rgb.height;
  float* scores = out->ptr<float>();
  ToProbabilities(scores, C, size_t(ow) * size_t(oh), impl_->options.preprocessing.output);
  // Resize each class plane to the view (bilinear: a convex combination, so pixels still sum to one).
  std::vector<cv::Mat> planes(static_cast<size_t>(C));
  tbb::parallel_for(0, C, [&](int k) {
    cv::Mat plane(oh, ow, CV_32F, scores + size_t(k) * size_t(oh) * size_t(ow));
    if (ow == W && oh == H)
      planes[size_t(k)] = plane;
    else
      cv::resize(plane, planes[size_t(k)], cv::Size(W, H), 0, 0, cv::INTER_LINEAR);
  });
  std::vector<int> target(size_t(C), 0);  // NYU40 id per network class, 0 = mapped to nothing.
  for (int k = 0; k < C; ++k)
    if (size_t(k) < impl_->map.target_of_class.size() && impl_->map.target_of_class[size_t(k)] > 0)
      target[size_t(k)] = impl_->map.target_of_class[size_t(k)];
  ImageF32 nyu40(W, H, kNumNyu40, 0.0f);
  tbb::parallel_for(0, H, [&](int y) {
    for (int x = 0; x < W; ++x) {
      float* dst = &nyu40.at(x, y);
      for (int k = 0; k < C; ++k) dst[target[size_t(k)]] += planes[size_t(k)].at<float>(y, x);
    }
  });
  return nyu40;
}

ImageF32 Nyu40ToLevelProbabilities(const ImageF32& nyu40, const LabelLevel& level) {
  const int L = level.num_classes();
  ImageF32 out(nyu40.width, nyu40.height, L, 0.0f);
  if (nyu40.channels != kNumNyu40 || L < 1) return out;
  tbb::parallel_for(0, nyu40.height, [&](int y) {
    for (int x = 0; x < nyu40.width; ++x) {
      const float* src = &nyu40.at(x, y);
      float* dst = &out.at(x, y);
      double sum = 0;
      for (int id = 1; id < kNumNyu40 && id < int(level.class_of_nyu40.size()); ++id) {
        const int c = level.class_of_nyu40[size_t(id)];
        if (c < 0 || c >= L) continue;
        dst[c] += src[id];
        sum += src[id];
      }
      for (int c = 0; c < L; ++c) dst[c] = sum > 0 ? float(dst[c] / sum) : 1.0f / float(L);
    }
  });
  return out;
}

Result<ImageF32> OnnxObjectModel::PixelProbabilities(const RenderedView& view) const {
  Result<ImageF32> nyu40 = Nyu40PixelProbabilities(view);
  if (!nyu40.ok()) return nyu40.status();
  return Nyu40ToLevelProbabilities(*nyu40, impl_->level);
}

int OnnxObjectModel::num_network_classes() const { return impl_->num_classes; }
const LabelLevel& OnnxObjectModel::level() const { return impl_->level; }
const OnnxObjectModelOptions& OnnxObjectModel::options() const { return impl_->options; }

}  // namespace semvox
