// Loading scanned scenes: meshes (PLY, OBJ+MTL, glTF/GLB, OFF, STL, and what else assimp reads) and
// point clouds (PLY without faces, PCD, "x y z [r g b]" text files), into core types, metres, +Z up.
#pragma once

#include <string>

#include "core/geometry.h"
#include "core/option_table.h"
#include "core/status.h"

namespace semvox {

// The file's up axis: auto (+Y for glTF, +Z otherwise) or one of the six axis directions; -y is a camera's frame
// (x right, y down, z forward: PCL, OpenCV, Kinect and most SLAM tools).
enum class UpAxis { kAuto, kZ, kY, kNegY, kX, kNegX, kNegZ };
// "auto", "z", "y", "-y", "x", "-x", "-z" ("+z", "+y", "+x" too); false for other names.
bool ParseUpAxis(const std::string& name, UpAxis* up);

struct LoadOptions {
  UpAxis up = UpAxis::kAuto;
  double scale = 1.0;
  double millimetre_warning_extent_m = 200.0;
  // Fewest valid vertices / points a usable scene needs. >= 1.
  int min_valid_points = 3;
  bool canonical_frame = true;  // Read by `semvox run` (mapping/scene_frame.h), not by LoadScene.

  // The fields users set (section `input`): meaning, unit and range.
  static const OptionTable<LoadOptions>& Options() {
    using O = LoadOptions;
    static const OptionTable<O> table = {
        OptionChoice(&O::up, "up", {"auto", "z", "y", "-y", "x", "-x", "-z"}, ParseUpAxis,
                     "up axis of the input file: auto (+Y for glTF, +Z otherwise), or the axis pointing up: z, y, -y "
                     "(a camera's frame: x right, y down, z forward, as PCL, OpenCV and SLAM tools write), x, -x, -z; "
                     "the file is turned so that it points to +Z"),
        OptionNumber(&O::scale, "scale", 1e-6, 1e6, "", "multiplies coordinates into metres (0.001 for mm)"),
        OptionSwitch(&O::canonical_frame, "canonical_frame",
                     "level the scan, turn its walls onto the x / y axes and put the floor at z = 0 before mapping "
                     "(coordinate outputs stay in the input frame; false: use the input frame as it is)"),
        OptionNumber(&O::millimetre_warning_extent_m, "millimetre_warning_extent_m", 1, 1e9, "metres",
                     "warn about units when the scene is larger than this"),
    };
    return table;
  }
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
