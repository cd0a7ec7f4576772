#include <chrono>
#include <filesystem>

#include "apps/commands.h"
#include "core/file_util.h"
#include "core/log.h"
#include "core/mesh_ply.h"
#include "scenegen/apartment.h"
#include "scenegen/apartment_io.h"
#include "scenegen/demo_scene.h"
#include "scenegen/scan_simulator.h"

namespace semvox {

Status RunGenerate(const GenerateArgs& args) {
  SEMVOX_RETURN_IF_ERROR(EnsureWritableDirectory(args.outdir));
  if (args.demo) {
    const Mesh mesh = BuildDemoApartment();
    const std::string path = (std::filesystem::path(args.outdir) / "mesh.ply").string();
    SEMVOX_RETURN_IF_ERROR(WriteMeshPly(path, mesh, "semvox demo apartment; face label = NYU40 id"));
    SEMVOX_INFO("wrote " << path << " (" << mesh.faces.size() << " triangles)");
    return Status::Ok();
  }
  if (args.seed < 0) return Status::InvalidInput("--seed = " + std::to_string(args.seed) + ". Violated constraint: seed >= 0");
  const auto t0 = std::chrono::steady_clock::now();
  ApartmentOptions options;
  options.seed = uint64_t(args.seed);
  Result<Apartment> apt = GenerateApartment(options);
  if (!apt.ok()) return apt.status();
  ScanArtefactOptions artefacts;
  artefacts.seed = options.seed;
  if (args.clean) {
    artefacts.remove_hidden = false;
    artefacts.holes_per_m2 = 0;
    artefacts.unscanned_ceiling_fraction = 0;
    artefacts.vertex_noise_m = 0;
  }
  SEMVOX_RETURN_IF_ERROR(WriteApartment(args.outdir, *apt, options, artefacts, GroundTruthOptions(), args.cloud));
  if (args.cloud) {
    ScanSimulationOptions scan;
    scan.seed = options.seed;
    Result<PointCloud> cloud = SimulateScan(*apt, scan);
    if (!cloud.ok()) return cloud.status();
    const std::string path = (std::filesystem::path(args.outdir) / "cloud.ply").string();
    SEMVOX_RETURN_IF_ERROR(WriteCloudPly(path, *cloud, "semvox simulated scan seed " + std::to_string(args.seed) +
                                                           "; point label = NYU40 id, instance, room"));
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  SEMVOX_INFO("apartment seed " << args.seed << ": " << apt->rooms.size() << " rooms, " << apt->objects.size()
                                << " objects, " << apt->mesh.faces.size() << " faces (clean) in " << seconds << " s -> "
                                << args.outdir);
  return Status::Ok();
}

}  // namespace semvox
