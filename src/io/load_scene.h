// Loading scanned scenes: meshes (PLY, OBJ+MTL, glTF/GLB, OFF, STL, and what else assimp reads) and
// point clouds (PLY without faces, PCD, "x y z [r g b]" text files), into core types, metres, +Z up.
#pragma once

#include <string>

#include "core/geometry.h"
#include "core/status.h"

namespace semvox {

enum class UpAxis { kAuto, kZ, kY };

struct LoadOptions {
  // Up axis of the file. kAuto: +Y for glTF/GLB (Y-up by the glTF specification), +Z otherwise.
  UpAxis up = UpAxis::kAuto;
  // Multiplies all coordinates (e.g. 0.001 for millimetres). Must be > 0.
  double scale = 1.0;
  // Largest extent (after scaling) in metres above which a "looks like millimetres" warning is issued.
  double millimetre_warning_extent_m = 200.0;
  // Fewest valid vertices / points a usable scene needs.
  int min_valid_points = 3;
  // `semvox run` only (not LoadScene): estimate the canonical frame (level, turn the walls onto the axes, floor
  // at z = 0; mapping/scene_frame.h) and work in it, mapping coordinate outputs back to the input frame.
  bool canonical_frame = true;

  bool Check(std::string* error) const;
};

// Loads `path`, picking the loader from the extension. Drops non-finite vertices or points (faces that
// use them go too) with a warning that counts them.
Result<Scene> LoadScene(const std::string& path, const LoadOptions& options = {});

// Extensions accepted by LoadScene, for messages.
std::string SupportedExtensions();

// Format-specific loaders (no axis or unit conversion). Used by LoadScene and by the fuzz targets.
Result<Scene> LoadPlyScene(const std::string& path);
Result<Scene> LoadAssimpScene(const std::string& path);
// `extension` tells assimp the format ("obj", "stl", ...); `name` appears in messages.
Result<Scene> LoadAssimpSceneFromMemory(const std::string& bytes, const std::string& extension, const std::string& name);
Result<Scene> LoadPcdScene(const std::string& path);
Result<Scene> LoadTextCloud(const std::string& path);
Result<Scene> ParseTextCloud(const std::string& bytes, const std::string& name);

}  // namespace semvox
