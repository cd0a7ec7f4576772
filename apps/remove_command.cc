// `semvox remove OUTDIR (--class NAME | --instance ID | --all-furniture) -o OUT2` and `semvox remove OUTDIR
// --list`: object removal with scene completion on the outputs of `semvox run` (pipeline/object_removal_stage.h).
#include <cstdio>
#include <filesystem>

#include "apps/commands.h"
#include "apps/config.h"
#include "pipeline/object_removal_stage.h"

namespace semvox {
namespace fs = std::filesystem;

Status RunRemove(const RemoveArgs& args) {
  if (args.list) {
    Result<std::vector<RunInstance>> instances = ListRunInstances(args.outdir);
    if (!instances.ok()) return instances.status();
    std::printf("%-8s %-6s %-16s %8s  %-24s %-24s\n", "instance", "label", "name", "voxels", "min (m)", "max (m)");
    for (const RunInstance& r : *instances)
      std::printf("%-8d %-6d %-16s %8zu  %7.2f %7.2f %7.2f  %7.2f %7.2f %7.2f\n", r.instance.id, int(r.instance.label), r.name.c_str(),
                  r.instance.voxels, r.min.x(), r.min.y(), r.min.z(), r.max.x(), r.max.y(), r.max.z());
    return Status::Ok();
  }
  ObjectRemovalRequest request;
  request.outdir = args.outdir;
  request.output = args.output;
  request.classes = args.classes;
  request.instances = args.instances;
  request.all_furniture = args.all_furniture;
  // The run's own options: the occupancy band and the planes of its Voxel-CRF.
  PipelineConfig config;
  const std::string config_path = (fs::path(args.outdir) / "config_used.yaml").string();
  if (fs::exists(config_path)) SEMVOX_RETURN_IF_ERROR(LoadConfigFile(config_path, &config));
  request.occupancy = config.occupancy;
  request.planes = config.semantic.crf.planes;
  return RemoveObjectsFromRun(request);
}

}  // namespace semvox
