#include <filesystem>

#include "apps/commands.h"
#include "core/file_util.h"
#include "core/log.h"
#include "core/mesh_ply.h"
#include "scenegen/demo_scene.h"

namespace semvox {

Status RunGenerate(const GenerateArgs& args) {
  SEMVOX_RETURN_IF_ERROR(EnsureWritableDirectory(args.outdir));
  if (!args.demo)
    return Status::InvalidInput("semvox generate: only --demo is implemented so far (the random apartment generator "
                                "is issue 3)");
  const Mesh mesh = BuildDemoApartment();
  const std::string path = (std::filesystem::path(args.outdir) / "mesh.ply").string();
  SEMVOX_RETURN_IF_ERROR(WriteMeshPly(path, mesh, "semvox demo apartment; face label = NYU40 id"));
  SEMVOX_INFO("wrote " << path << " (" << mesh.faces.size() << " triangles)");
  return Status::Ok();
}

}  // namespace semvox
