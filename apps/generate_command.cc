#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>

#include "apps/commands.h"
#include "perception/training_data.h"
#include "core/file_util.h"
#include "core/labels.h"
#include "core/log.h"
#include "core/mesh_ply.h"
#include "scenegen/apartment.h"
#include "scenegen/apartment_io.h"
#include "scenegen/demo_scene.h"
#include "scenegen/plan_apartment.h"
#include "rooms/r2v_layout.h"
#include "scenegen/scan_simulator.h"

namespace semvox {
namespace {

struct GeneratorConfig {
  ApartmentOptions apartment;
  ScanArtefactOptions artefacts;
  ScanSimulationOptions scan;
};

// "section.name=value" overrides. Unknown names and unparsable values are errors naming the setting.
Status ApplySettings(const std::vector<std::string>& settings, GeneratorConfig* c) {
  std::map<std::string, std::function<bool(const std::string&)>> fields;
  auto num = [&](const std::string& key, double* field) {
    fields[key] = [field](const std::string& v) {
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !std::isfinite(x)) return false;
      *field = x;
      return true;
    };
  };
  auto integer = [&](const std::string& key, int* field) {
    fields[key] = [field](const std::string& v) {
      char* end = nullptr;
      const long x = std::strtol(v.c_str(), &end, 10);
      if (end == v.c_str() || *end != '\0') return false;
      *field = int(x);
      return true;
    };
  };
  auto flag = [&](const std::string& key, bool* field) {
    fields[key] = [field](const std::string& v) {
      if (v == "true" || v == "1") *field = true;
      else if (v == "false" || v == "0") *field = false;
      else return false;
      return true;
    };
  };
  ApartmentOptions& a = c->apartment;
  integer("apartment.min_rooms", &a.min_rooms);
  integer("apartment.max_rooms", &a.max_rooms);
  num("apartment.floor_z_m", &a.floor_z_m);
  num("apartment.min_ceiling_m", &a.min_ceiling_m);
  num("apartment.max_ceiling_m", &a.max_ceiling_m);
  num("apartment.min_wall_m", &a.min_wall_m);
  num("apartment.max_wall_m", &a.max_wall_m);
  num("apartment.surface_cell_m", &a.surface_cell_m);
  flag("apartment.furniture", &a.furniture);
  flag("apartment.props", &a.props);
  flag("apartment.shape_variety", &a.shape_variety);
  ScanArtefactOptions& r = c->artefacts;
  flag("artefacts.remove_hidden", &r.remove_hidden);
  num("artefacts.hidden_margin_m", &r.hidden_margin_m);
  num("artefacts.holes_per_m2", &r.holes_per_m2);
  num("artefacts.min_hole_radius_m", &r.min_hole_radius_m);
  num("artefacts.max_hole_radius_m", &r.max_hole_radius_m);
  num("artefacts.unscanned_ceiling_fraction", &r.unscanned_ceiling_fraction);
  num("artefacts.face_dropout", &r.face_dropout);
  num("artefacts.vertex_noise_m", &r.vertex_noise_m);
  num("artefacts.roughness_m", &r.roughness_m);
  num("artefacts.roughness_wavelength_m", &r.roughness_wavelength_m);
  ScanSimulationOptions& s = c->scan;
  num("scan.station_spacing_m", &s.station_spacing_m);
  num("scan.station_clearance_m", &s.station_clearance_m);
  num("scan.scanner_height_m", &s.scanner_height_m);
  integer("scan.azimuth_steps", &s.azimuth_steps);
  integer("scan.elevation_steps", &s.elevation_steps);
  num("scan.min_range_m", &s.min_range_m);
  num("scan.max_range_m", &s.max_range_m);
  num("scan.noise_sigma_m", &s.noise_sigma_m);
  num("scan.noise_quadratic", &s.noise_quadratic);
  num("scan.fuse_voxel_m", &s.fuse_voxel_m);
  for (const std::string& kv : settings) {
    const size_t eq = kv.find('=');
    const std::string key = kv.substr(0, eq);
    const auto it = fields.find(key);
    if (eq == std::string::npos || it == fields.end()) {
      std::string known;
      for (const auto& [name, fn] : fields) known += (known.empty() ? "" : ", ") + name;
      return Status::InvalidInput("--set " + kv + ": unknown setting (hint: one of " + known + ")");
    }
    if (!it->second(kv.substr(eq + 1)))
      return Status::InvalidInput("--set " + kv + ": cannot parse the value of " + key);
  }
  std::string error;
  if (!c->apartment.Check(&error)) return Status::InvalidInput("apartment options: " + error);
  if (!c->artefacts.Check(&error)) return Status::InvalidInput("artefacts options: " + error);
  if (!c->scan.Check(&error)) return Status::InvalidInput("scan options: " + error);
  return Status::Ok();
}


}  // namespace

Status RunGenerate(const GenerateArgs& args) {
  if (args.seed < 0) return Status::InvalidInput("--seed = " + std::to_string(args.seed) + ". Violated constraint: seed >= 0");
  GeneratorConfig config;
  config.apartment.seed = config.artefacts.seed = config.scan.seed = uint64_t(args.seed);
  if (args.clean) {
    config.artefacts.remove_hidden = false;
    config.artefacts.holes_per_m2 = 0;
    config.artefacts.unscanned_ceiling_fraction = 0;
    config.artefacts.vertex_noise_m = 0;
  }
  // The randomised validation set has the randomised training scans' furniture shapes too.
  config.apartment.shape_variety = args.randomised;
  SEMVOX_RETURN_IF_ERROR(ApplySettings(args.settings, &config));
  if (args.demo) {
    SEMVOX_RETURN_IF_ERROR(EnsureWritableDirectory(args.outdir));
    const Mesh mesh = BuildDemoApartment();
    const std::string path = (std::filesystem::path(args.outdir) / "mesh.ply").string();
    SEMVOX_RETURN_IF_ERROR(WriteMeshPly(path, mesh, "semvox demo apartment; face label = NYU40 id"));
    SEMVOX_INFO("wrote " << path << " (" << mesh.faces.size() << " triangles)");
    return Status::Ok();
  }
  const auto t0 = std::chrono::steady_clock::now();
  Result<Apartment> apt = [&]() -> Result<Apartment> {
    if (args.plan.empty()) return GenerateApartment(config.apartment);
    int unclosed = 0;
    Result<PlanLayout> layout = LayoutOfR2vPlan(args.plan, &unclosed);
    if (!layout.ok()) return layout.status();
    if (unclosed > 0)
      SEMVOX_WARN(args.plan << ": " << unclosed << " room label(s) lie in regions open to the plan's border (walls do not "
                            << "close them); those regions are taken as outside, not as rooms");
    PlanApartmentOptions po;
    po.seed = uint64_t(args.seed);
    po.surface_cell_m = config.apartment.surface_cell_m;
    po.furniture = po.props = !args.no_furniture;
    Result<Apartment> a = ApartmentFromLayout(*layout, po);
    if (!a.ok()) return Status::InvalidInput(FileError(args.plan, a.status().message(), "pass a plan_*.txt of ../shared/data/r2v"));
    a->plan = args.plan;
    config.apartment.furniture = config.apartment.props = false;  // gt.json says what the apartment holds.
    return a;
  }();
  if (!apt.ok()) return apt.status();
  SEMVOX_RETURN_IF_ERROR(WriteApartment(args.outdir, *apt, config.apartment, config.artefacts, GroundTruthOptions(), args.cloud));
  if (args.cloud) {
    Result<PointCloud> cloud = SimulateScan(*apt, config.scan);
    if (!cloud.ok()) return cloud.status();
    const std::string path = (std::filesystem::path(args.outdir) / "cloud.ply").string();
    SEMVOX_RETURN_IF_ERROR(WriteCloudPly(path, *cloud, "semvox simulated scan seed " + std::to_string(args.seed) +
                                                           "; point label = NYU40 id, instance, room"));
  }
  if (args.randomised) {
    // The randomised validation style (perception/training_data.h, MakeTrainingScan): palette colours,
    // textures and lighting baked in, a fused cloud of random spacing or a mesh with random artefacts.
    TrainingViewsOptions style;
    style.style = TrainingStyle::kRandomised;
    Result<Scene> scan = MakeTrainingScan(*apt, uint64_t(args.seed), style);
    if (!scan.ok()) return scan.status();
    const std::string path = (std::filesystem::path(args.outdir) / "scan.ply").string();
    const std::string comment = "semvox randomised scan seed " + std::to_string(args.seed);
    SEMVOX_RETURN_IF_ERROR(scan->is_mesh() ? WriteMeshPly(path, scan->mesh, comment) : WriteCloudPly(path, scan->cloud, comment));
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  SEMVOX_INFO("apartment seed " << args.seed << ": " << apt->rooms.size() << " rooms, " << apt->objects.size()
                                << " objects, " << apt->mesh.faces.size() << " faces (clean) in " << seconds << " s -> "
                                << args.outdir);
  return Status::Ok();
}

}  // namespace semvox
