// PCD clouds through PCL's reader (ascii, binary, binary_compressed) into core types. Fields are read
// from the untyped PCLPointCloud2 so no PCL point-type template is instantiated here.
#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>

#include <cstring>

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

}  // namespace

Result<Scene> LoadPcdScene(const std::string& path) {
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);  // Errors are reported through Status.
  std::string head;
  {
    std::string bytes;
    SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
    head = bytes.substr(0, 4096);
  }
  if (head.find("FIELDS") == std::string::npos || head.find("DATA") == std::string::npos)
    return Status::InvalidInput(FileError(path, "not a PCD file (no FIELDS / DATA header lines)",
                                          "save the cloud with PCL's PCD writer"));
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
