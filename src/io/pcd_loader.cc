// PCD clouds through PCL's reader (ascii, binary, binary_compressed) into core types. Fields are read
// from the untyped PCLPointCloud2 so no PCL point-type template is instantiated here.
#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>

#include <cstring>
#include <sstream>
#include <vector>

#include "core/file_util.h"
#include "io/load_scene.h"

namespace semvox {
namespace {

double ReadField(const uint8_t* p, uint8_t datatype) {
  switch (datatype) {
    case pcl::PCLPointField::INT8: { int8_t v; std::memcpy(&v, p, 1); return v; }
    case pcl::PCLPointField::UINT8: { uint8_t v; std::memcpy(&v, p, 1); return v; }
    case pcl::PCLPointField::INT16: { int16_t v; std::memcpy(&v, p, 2); return v; }
    case pcl::PCLPointField::UINT16: { uint16_t v; std::memcpy(&v, p, 2); return v; }
    case pcl::PCLPointField::INT32: { int32_t v; std::memcpy(&v, p, 4); return v; }
    case pcl::PCLPointField::UINT32: { uint32_t v; std::memcpy(&v, p, 4); return v; }
    case pcl::PCLPointField::FLOAT32: { float v; std::memcpy(&v, p, 4); return v; }
    case pcl::PCLPointField::FLOAT64: { double v; std::memcpy(&v, p, 8); return v; }
  }
  return 0;
}

int FieldSize(uint8_t datatype) {
  switch (datatype) {
    case pcl::PCLPointField::INT8: case pcl::PCLPointField::UINT8: return 1;
    case pcl::PCLPointField::INT16: case pcl::PCLPointField::UINT16: return 2;
    case pcl::PCLPointField::FLOAT64: return 8;
    default: return 4;
  }
}

// PCL's reader trusts the header (a COUNT larger than the values on an ascii line, a WIDTH beyond the
// data, a corrupt compressed block crash it; the fuzzer found such files). Everything it would index is
// checked here first; errors name the header line or data row.
Status ValidatePcd(const std::string& bytes, const std::string& path) {
  const std::string kHint = "the PCD file is corrupt; re-export it with PCL";
  std::istringstream is(bytes);
  std::string line;
  std::vector<std::string> fields;
  std::vector<int> sizes, counts;
  std::string types;
  long long width = -1, height = -1, points = -1;
  std::string data;
  size_t header_end = 0;
  int line_no = 0;
  while (std::getline(is, line)) {
    ++line_no;
    header_end += line.size() + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string key, tok;
    ls >> key;
    std::vector<std::string> vals;
    while (ls >> tok) vals.push_back(tok);
    auto bad = [&](const std::string& what) {
      return Status::InvalidInput(FileError(path, "PCD header line " + std::to_string(line_no) + ": " + what, kHint));
    };
    auto ints = [&](std::vector<int>* out) -> bool {
      for (const auto& v : vals) {
        char* end = nullptr;
        const long x = std::strtol(v.c_str(), &end, 10);
        if (*end != '\0' || x < 1 || x > 1 << 20) return false;
        out->push_back(int(x));
      }
      return true;
    };
    auto one = [&](long long* out) -> bool {
      if (vals.size() != 1) return false;
      char* end = nullptr;
      *out = std::strtoll(vals[0].c_str(), &end, 10);
      return *end == '\0' && *out >= 0;
    };
    if (key == "VERSION" || key == "VIEWPOINT") continue;
    if (key == "FIELDS" || key == "COLUMNS") fields = vals;
    else if (key == "SIZE") { if (!ints(&sizes)) return bad("SIZE values must be 1, 2, 4 or 8"); }
    else if (key == "TYPE") { for (const auto& v : vals) { if (v != "F" && v != "I" && v != "U") return bad("TYPE must be F, I or U"); types += v; } }
    else if (key == "COUNT") { if (!ints(&counts)) return bad("COUNT values must be positive integers"); }
    else if (key == "WIDTH") { if (!one(&width)) return bad("WIDTH must be a non-negative integer"); }
    else if (key == "HEIGHT") { if (!one(&height)) return bad("HEIGHT must be a non-negative integer"); }
    else if (key == "POINTS") { if (!one(&points)) return bad("POINTS must be a non-negative integer"); }
    else if (key == "DATA") { if (vals.size() != 1) return bad("DATA needs one of ascii, binary, binary_compressed"); data = vals[0]; break; }
    else return bad("unknown header keyword '" + key + "'");
  }
  if (data.empty()) return Status::InvalidInput(FileError(path, "PCD header has no DATA line", kHint));
  if (data != "ascii" && data != "binary" && data != "binary_compressed")
    return Status::InvalidInput(FileError(path, "unknown PCD DATA type '" + data + "'", kHint));
  if (fields.empty()) return Status::InvalidInput(FileError(path, "PCD header has no FIELDS", kHint));
  if (counts.empty()) counts.assign(fields.size(), 1);
  if (sizes.size() != fields.size() || types.size() != fields.size() || counts.size() != fields.size())
    return Status::InvalidInput(FileError(path, "PCD header: FIELDS, SIZE, TYPE and COUNT have different lengths", kHint));
  for (size_t i = 0; i < sizes.size(); ++i) {
    const int sz = sizes[i];
    if (sz != 1 && sz != 2 && sz != 4 && sz != 8) return Status::InvalidInput(FileError(path, "PCD SIZE must be 1, 2, 4 or 8", kHint));
    if (types[i] == 'F' && sz != 4 && sz != 8) return Status::InvalidInput(FileError(path, "PCD float fields must have SIZE 4 or 8", kHint));
    if (counts[i] > 4096) return Status::InvalidInput(FileError(path, "PCD COUNT above 4096", kHint));
  }
  if (width < 0 || height < 0) return Status::InvalidInput(FileError(path, "PCD header lacks WIDTH or HEIGHT", kHint));
  if (points >= 0 && points != width * height)
    return Status::InvalidInput(FileError(path, "PCD POINTS (" + std::to_string(points) + ") is not WIDTH x HEIGHT (" +
                                                    std::to_string(width * height) + ")", kHint));
  const long long n = width * height;
  size_t values_per_point = 0, point_step = 0;
  for (size_t i = 0; i < sizes.size(); ++i) values_per_point += size_t(counts[i]), point_step += size_t(counts[i]) * sizes[i];
  const size_t body = bytes.size() - std::min(bytes.size(), header_end);
  if (data == "binary") {
    if (double(n) * double(point_step) > double(body))
      return Status::InvalidInput(FileError(path, "PCD declares " + std::to_string(n) + " points of " +
                                                      std::to_string(point_step) + " bytes but holds " +
                                                      std::to_string(body) + " data bytes", "the file is truncated"));
  } else if (data == "binary_compressed") {
    if (body < 8) return Status::InvalidInput(FileError(path, "PCD compressed block header is missing", "the file is truncated"));
    uint32_t compressed = 0, uncompressed = 0;
    std::memcpy(&compressed, bytes.data() + header_end, 4);
    std::memcpy(&uncompressed, bytes.data() + header_end + 4, 4);
    if (size_t(compressed) + 8 > body || double(uncompressed) != double(n) * double(point_step))
      return Status::InvalidInput(FileError(path, "PCD compressed block sizes do not match the header", kHint));
  } else {
    // ascii: every data row holds exactly the declared number of values, and there are enough rows.
    long long rows = 0;
    while (rows < n && std::getline(is, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.find_first_not_of(" \t") == std::string::npos) continue;
      std::istringstream ls(line);
      std::string tok;
      size_t k = 0;
      while (ls >> tok) ++k;
      if (k != values_per_point)
        return Status::InvalidInput(FileError(path, "PCD data row " + std::to_string(rows + 1) + " has " + std::to_string(k) +
                                                        " values, the header declares " + std::to_string(values_per_point),
                                              kHint));
      ++rows;
    }
    if (rows < n)
      return Status::InvalidInput(FileError(path, "PCD declares " + std::to_string(n) + " points but holds " +
                                                      std::to_string(rows) + " rows", "the file is truncated"));
  }
  return Status::Ok();
}

}  // namespace

Result<Scene> LoadPcdScene(const std::string& path) {
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);  // Errors are reported through Status.
  {
    std::string bytes;
    SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
    const std::string head = bytes.substr(0, 4096);
    if (head.find("FIELDS") == std::string::npos || head.find("DATA") == std::string::npos)
      return Status::InvalidInput(FileError(path, "not a PCD file (no FIELDS / DATA header lines)",
                                            "save the cloud with PCL's PCD writer"));
    SEMVOX_RETURN_IF_ERROR(ValidatePcd(bytes, path));
  }
  pcl::PCLPointCloud2 blob;
  pcl::PCDReader reader;
  int rc = -1;
  try {
    rc = reader.read(path, blob);
  } catch (const std::exception& e) {
    return Status::InvalidInput(FileError(path, std::string("cannot read PCD: ") + e.what(), "the file is corrupt"));
  }
  if (rc < 0)
    return Status::InvalidInput(FileError(path, "cannot read PCD (PCL reader error " + std::to_string(rc) + ")",
                                          "the file is truncated or its header is corrupt"));
  const size_t n = size_t(blob.width) * blob.height;
  if (blob.point_step == 0 || blob.data.size() < n * blob.point_step)
    return Status::InvalidInput(FileError(path, "PCD holds fewer bytes than its header declares", "the file is truncated"));
  const pcl::PCLPointField *fx = nullptr, *fy = nullptr, *fz = nullptr, *frgb = nullptr, *flabel = nullptr;
  for (const auto& f : blob.fields) {
    if (f.offset + FieldSize(f.datatype) > blob.point_step) continue;
    if (f.name == "x") fx = &f;
    else if (f.name == "y") fy = &f;
    else if (f.name == "z") fz = &f;
    else if (f.name == "rgb" || f.name == "rgba") frgb = &f;
    else if (f.name == "label") flabel = &f;
  }
  if (!fx || !fy || !fz)
    return Status::InvalidInput(FileError(path, "PCD has no x, y, z fields", "save a cloud with positions"));
  Scene scene;
  PointCloud& cloud = scene.cloud;
  cloud.points.resize(n);
  if (frgb) cloud.colors.resize(n);
  if (flabel) cloud.point_attributes["label"].resize(n);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* p = blob.data.data() + i * blob.point_step;
    cloud.points[i] = Eigen::Vector3f(float(ReadField(p + fx->offset, fx->datatype)),
                                      float(ReadField(p + fy->offset, fy->datatype)),
                                      float(ReadField(p + fz->offset, fz->datatype)));
    if (frgb) {
      uint32_t packed;
      std::memcpy(&packed, p + frgb->offset, 4);  // PCL packs rgb as 0x00RRGGBB in a float or uint32.
      cloud.colors[i] = Rgb8{uint8_t((packed >> 16) & 0xff), uint8_t((packed >> 8) & 0xff), uint8_t(packed & 0xff)};
    }
    if (flabel) cloud.point_attributes["label"][i] = int32_t(ReadField(p + flabel->offset, flabel->datatype));
  }
  if (n == 0) return Status::InvalidInput(FileError(path, "PCD holds no points", "the cloud is empty"));
  return scene;
}

}  // namespace semvox
