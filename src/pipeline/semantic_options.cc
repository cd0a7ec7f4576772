#include "pipeline/semantic_options.h"

#include <cmath>

#include "core/labels.h"
#include "perception/label_levels.h"

namespace semvox {

const char* ClassifyViewSelectionName(ClassifyViewSelection s) {
  return s == ClassifyViewSelection::kAll                  ? "all"
         : s == ClassifyViewSelection::kCover              ? "cover"
         : s == ClassifyViewSelection::kAllObjectsOnCover ? "all_objects_on_cover"
                                                           : "auto";
}

ClassifyViewSelection ResolveViewSelection(ClassifyViewSelection s, const Scene&) {
  return s == ClassifyViewSelection::kAuto ? ClassifyViewSelection::kCover : s;
}

const char* VoxelCrfModelChoiceName(VoxelCrfModelChoice c) {
  return c == VoxelCrfModelChoice::kMesh ? "mesh" : c == VoxelCrfModelChoice::kCloud ? "cloud" : "auto";
}

bool ParseVoxelCrfModelChoice(const std::string& name, VoxelCrfModelChoice* c) {
  if (name == "mesh") *c = VoxelCrfModelChoice::kMesh;
  else if (name == "cloud") *c = VoxelCrfModelChoice::kCloud;
  else if (name == "auto") *c = VoxelCrfModelChoice::kAuto;
  else return false;
  return true;
}

bool FlatColouredMesh(const Mesh& mesh) {
  if (mesh.faces.empty() || !mesh.has_vertex_colors() || mesh.has_texture()) return false;
  size_t flat = 0;
  for (const Eigen::Vector3i& f : mesh.faces) {
    const Rgb8 a = mesh.vertex_colors[size_t(f[0])], b = mesh.vertex_colors[size_t(f[1])], c = mesh.vertex_colors[size_t(f[2])];
    flat += a.r == b.r && a.g == b.g && a.b == b.b && a.r == c.r && a.g == c.g && a.b == c.b;
  }
  return 2 * flat >= mesh.faces.size();
}

bool ParseClassifyViewSelection(const std::string& name, ClassifyViewSelection* s) {
  if (name == "all") *s = ClassifyViewSelection::kAll;
  else if (name == "cover") *s = ClassifyViewSelection::kCover;
  else if (name == "all_objects_on_cover") *s = ClassifyViewSelection::kAllObjectsOnCover;
  else if (name == "auto") *s = ClassifyViewSelection::kAuto;
  else return false;
  return true;
}

bool SemanticStageOptions::Check(std::string* error) const {
  if (!CheckOptions(*this, Options(), error)) return false;
  if (std::abs(360.0 / classify_yaw_step_deg - std::round(360.0 / classify_yaw_step_deg)) > 1e-9) {
    if (error) *error = "classify_yaw_step_deg = " + std::to_string(classify_yaw_step_deg) + ". Violated constraint: divides 360";
    return false;
  }
  return selection.Check(error) && evidence.Check(error) && crf.Check(error);
}

std::vector<int> Nyu40OfClasses(const LabelLevel& level) {
  std::vector<int> nyu40;
  for (const std::string& name : level.class_names) nyu40.push_back(name == "other" ? nyu40::kOtherProp : Nyu40IdByName(name));
  return nyu40;
}

}  // namespace semvox
