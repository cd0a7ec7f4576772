#include "fuzz/fuzz_entries.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "apps/config.h"
#include "core/file_util.h"
#include "core/ply.h"
#include "io/image_io.h"
#include "io/load_scene.h"
#include "rooms/floor_plan.h"

namespace semvox::fuzz {
namespace {
std::string Bytes(const uint8_t* data, size_t size) { return std::string(reinterpret_cast<const char*>(data), size); }

// PCL reads files only: write the input to a per-process temporary file.
std::string TempFile(const std::string& ext) {
  return (std::filesystem::temp_directory_path() / ("semvox_fuzz_" + std::to_string(::getpid()) + "." + ext)).string();
}
}  // namespace

void FuzzPly(const uint8_t* data, size_t size) {
  Result<PlyData> r = ParsePly(Bytes(data, size), "fuzz.ply");
  (void)r;
  // The full scene conversion too (through a file, as LoadPlyScene reads one).
  const std::string path = TempFile("ply");
  if (WriteFileAtomic(path, Bytes(data, size)).ok()) {
    Result<Scene> s = LoadScene(path);
    (void)s;
    std::remove(path.c_str());
  }
}

void FuzzObj(const uint8_t* data, size_t size) {
  Result<Scene> s = LoadAssimpSceneFromMemory(Bytes(data, size), "obj", "fuzz.obj");
  (void)s;
}

void FuzzPcd(const uint8_t* data, size_t size) {
  const std::string path = TempFile("pcd");
  if (!WriteFileAtomic(path, Bytes(data, size)).ok()) return;
  Result<Scene> s = LoadPcdScene(path);
  (void)s;
  std::remove(path.c_str());
}

void FuzzTextCloud(const uint8_t* data, size_t size) {
  Result<Scene> s = ParseTextCloud(Bytes(data, size), "fuzz.txt");
  (void)s;
}

void FuzzMapImage(const uint8_t* data, size_t size) {
  Result<ImageRgb8> a = DecodeImageRgb8(Bytes(data, size), "fuzz.png");
  (void)a;
  const std::string path = TempFile("png");
  if (!WriteFileAtomic(path, Bytes(data, size)).ok()) return;
  Result<ImageU16> b = ReadImageU16(path);
  Result<Image<uint8_t>> c = ReadGreyMap(path);  // What `semvox rooms` reads.
  (void)b, (void)c;
  std::remove(path.c_str());
}

void FuzzConfig(const uint8_t* data, size_t size) {
  PipelineConfig config;
  Status st = ParseConfig(Bytes(data, size), "fuzz.yaml", &config);
  (void)st;
}

const std::vector<Target>& Targets() {
  static const std::vector<Target> kTargets = {{"ply", FuzzPly},       {"obj", FuzzObj},
                                               {"pcd", FuzzPcd},       {"text_cloud", FuzzTextCloud},
                                               {"map_image", FuzzMapImage}, {"config", FuzzConfig}};
  return kTargets;
}

}  // namespace semvox::fuzz
