// Entry points shared by the libFuzzer targets (fuzz/*_fuzzer.cc) and the regression test that replays
// every input kept under tests/fuzz_regressions/<target>/. Each must return normally for any input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace semvox::fuzz {

void FuzzPly(const uint8_t* data, size_t size);         // PLY parser + PLY scene conversion.
void FuzzObj(const uint8_t* data, size_t size);         // assimp OBJ through LoadAssimpSceneFromMemory.
void FuzzPcd(const uint8_t* data, size_t size);         // PCL's PCD reader through LoadPcdScene.
void FuzzTextCloud(const uint8_t* data, size_t size);   // x y z [r g b] text clouds.
void FuzzMapImage(const uint8_t* data, size_t size);    // 2D map images (PNG/PGM) as `semvox rooms` reads them.
void FuzzConfig(const uint8_t* data, size_t size);      // The YAML configuration.

struct Target {
  const char* name;
  void (*fn)(const uint8_t*, size_t);
};
const std::vector<Target>& Targets();

}  // namespace semvox::fuzz
