#include "pipeline/object_removal_stage.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "core/label_aliases.h"
#include "core/labels.h"
#include "core/log.h"
#include "core/ply.h"
#include "io/image_io.h"
#include "mapping/occupancy_map.h"
#include "mapping/octomap_io.h"
#include "voxelcrf/object_removal.h"
#include "voxelcrf/semantic_map.h"

namespace semvox {
namespace fs = std::filesystem;
namespace {

std::string LabelName(int l) { return l > 0 && l < kNumNyu40 ? Nyu40Labels()[size_t(l)].name : std::to_string(l); }

}  // namespace

Status ReadRunOutputs(const std::string& outdir, RunOutputs* run) {
  const std::string hint = "OUTDIR must be the output directory of `semvox run` with the semantic stage enabled";
  if (!fs::is_directory(outdir)) return Status::InvalidInput(FileError(outdir, "not a directory", hint));
  const std::string summary_path = (fs::path(outdir) / "summary.json").string();
  std::string bytes;
  if (!fs::exists(summary_path)) return Status::InvalidInput(FileError(summary_path, "missing", hint));
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(summary_path, &bytes));
  nlohmann::json s = nlohmann::json::parse(bytes, nullptr, false);
  std::array<int, 3> dims{}, origin{};
  try {
    if (s.is_discarded()) throw std::runtime_error("not JSON");
    dims = s.at("grid").at("dims").get<std::array<int, 3>>();
    origin = s.at("grid").at("origin_key").get<std::array<int, 3>>();
    run->floor_z = s.at("floor").at("z").get<double>();
    run->ceiling_z = s.at("ceiling").at("z").get<double>();
    if (s.contains("frame") && s["frame"].value("applied", false)) {
      const auto m = s["frame"].at("input_from_canonical").get<std::vector<std::vector<double>>>();
      if (m.size() != 4) throw std::runtime_error("frame.input_from_canonical is not 4 x 4");
      for (int r = 0; r < 4; ++r) {
        if (m[size_t(r)].size() != 4) throw std::runtime_error("frame.input_from_canonical is not 4 x 4");
        for (int c = 0; c < 4; ++c) run->input_from_world.matrix()(r, c) = m[size_t(r)][size_t(c)];
      }
      // summary.json's heights are input z of canonical points above the origin: z_in = t(2,2) z + t(2,3).
      const Eigen::Matrix4d& t = run->input_from_world.matrix();
      if (!(std::fabs(t(2, 2)) > 0.1)) throw std::runtime_error("frame.input_from_canonical is not a levelling transform");
      run->floor_z = (run->floor_z - t(2, 3)) / t(2, 2);
      run->ceiling_z = (run->ceiling_z - t(2, 3)) / t(2, 2);
    }
  } catch (const std::exception& e) {
    return Status::InvalidInput(FileError(summary_path, std::string("no grid dims / origin_key / floor z / ceiling z (") + e.what() + ")", hint));
  }
  const std::string ot_path = (fs::path(outdir) / "map.ot").string();
  if (!fs::exists(ot_path)) return Status::InvalidInput(FileError(ot_path, "missing", hint));
  double resolution = 0;
  Result<std::vector<SemanticVoxel>> voxels = ReadSemanticOctree(ot_path, &resolution);
  if (!voxels.ok()) return voxels.status();
  if (!(resolution > 0) || dims[0] <= 0 || dims[1] <= 0 || dims[2] <= 0)
    return Status::InvalidInput(FileError(summary_path, "grid dims or map.ot resolution not positive", hint));
  run->grid = VoxelGrid(resolution, origin, dims);
  for (const SemanticVoxel& v : *voxels) {
    std::array<int, 3> c;
    if (!run->grid.CellOfKey(v.key, &c)) continue;
    run->grid.set_state(run->grid.Index(c[0], c[1], c[2]), v.occupied ? VoxelState::kOccupied : VoxelState::kFree);
  }
  const std::string ply_path = (fs::path(outdir) / "voxels.ply").string();
  if (!fs::exists(ply_path)) return Status::InvalidInput(FileError(ply_path, "missing", hint));
  Result<PlyData> ply = ReadPly(ply_path);
  if (!ply.ok()) return ply.status();
  const PlyElement* vertex = ply->Find("vertex");
  const char* names[] = {"x", "y", "z", "red", "green", "blue", "label", "confidence", "room", "completed"};
  const PlyProperty* p[10];
  for (int i = 0; i < 10; ++i) {
    p[i] = vertex ? vertex->Find(names[i]) : nullptr;
    if (!p[i]) return Status::InvalidInput(FileError(ply_path, std::string("no vertex property '") + names[i] + "'", hint));
  }
  std::vector<int32_t> record_of(run->grid.size(), -1);
  const bool identity = IsIdentity(run->input_from_world);
  const Eigen::Isometry3d world_from_input = run->input_from_world.inverse();
  for (size_t k = 0; k < vertex->count; ++k) {
    SemanticVoxelRecord r;
    r.centre = Eigen::Vector3f(float(p[0]->values[k]), float(p[1]->values[k]), float(p[2]->values[k]));
    if (!identity) r.centre = (world_from_input * r.centre.cast<double>()).cast<float>();
    const auto c = run->grid.CellOf(r.centre.cast<double>());
    if (!run->grid.Contains(c[0], c[1], c[2]))
      return Status::InvalidInput(FileError(ply_path, "vertex " + std::to_string(k) + " lies outside the grid of summary.json", hint));
    r.voxel = uint32_t(run->grid.Index(c[0], c[1], c[2]));
    r.centre = run->grid.CellCenter(c[0], c[1], c[2]).cast<float>();
    r.rgb = {uint8_t(p[3]->values[k]), uint8_t(p[4]->values[k]), uint8_t(p[5]->values[k])};
    r.label = uint16_t(p[6]->values[k]);
    r.confidence = float(p[7]->values[k]);
    r.room = int32_t(p[8]->values[k]);
    r.completed = uint8_t(p[9]->values[k]);
    if (record_of[r.voxel] >= 0) continue;  // One record per voxel.
    record_of[r.voxel] = int32_t(run->map.occupied.size());
    run->grid.set_state(r.voxel, VoxelState::kOccupied);
    run->map.occupied.push_back(r);
  }
  std::sort(run->map.occupied.begin(), run->map.occupied.end(),
            [](const SemanticVoxelRecord& a, const SemanticVoxelRecord& b) { return a.voxel < b.voxel; });
  return Status::Ok();
}

Result<std::vector<RunInstance>> ListRunInstances(const std::string& outdir) {
  RunOutputs run;
  SEMVOX_RETURN_IF_ERROR(ReadRunOutputs(outdir, &run));
  std::vector<ObjectInstance> instances;
  LabelInstances(run.grid, run.map, &instances);
  std::vector<RunInstance> out;
  for (const ObjectInstance& in : instances) {
    RunInstance r;
    r.instance = in;
    r.name = LabelName(in.label);
    // The bounding box in the run's input frame (of the canonical box's corners when the frame was applied).
    r.min = in.min.cast<double>(), r.max = in.max.cast<double>();
    if (!IsIdentity(run.input_from_world)) {
      Eigen::AlignedBox3d box;
      for (int c = 0; c < 8; ++c)
        box.extend(run.input_from_world * Eigen::Vector3d(c & 1 ? in.max.x() : in.min.x(), c & 2 ? in.max.y() : in.min.y(),
                                                          c & 4 ? in.max.z() : in.min.z()));
      r.min = box.min(), r.max = box.max();
    }
    out.push_back(r);
  }
  return out;
}

Status RemoveObjectsFromRun(const ObjectRemovalRequest& args) {
  const auto t0 = std::chrono::steady_clock::now();
  // Class names first: bad input fails before anything is read or written.
  RemovalSelection selection;
  for (const std::string& name : args.classes) {
    int id = Nyu40IdByAlias(name);  // Case, '_' / '-' and spelling variants ("night_stand", "refrigerator").
    if (id < 0 && !name.empty() && std::all_of(name.begin(), name.end(), ::isdigit)) id = std::stoi(name);
    if (id <= 0 || id >= kNumNyu40) {
      std::string valid;
      for (size_t l = 1; l < size_t(kNumNyu40); ++l) valid += (l > 1 ? ", " : "") + std::string(Nyu40Labels()[l].name);
      return Status::InvalidInput("--class '" + name + "': not an NYU40 class (valid: " + valid + "; see `semvox labels`)");
    }
    selection.classes.push_back(id);
  }
  selection.instances = args.instances;
  selection.all_furniture = args.all_furniture;
  if (selection.classes.empty() && selection.instances.empty() && !selection.all_furniture)
    return Status::InvalidInput("nothing to remove (hint: give --class NAME, --instance ID or --all-furniture; --list shows the instances)");
  if (args.output.empty()) return Status::InvalidInput("no output directory (hint: -o OUT2)");

  RunOutputs run;
  SEMVOX_RETURN_IF_ERROR(ReadRunOutputs(args.outdir, &run));
  std::vector<ObjectInstance> instances;
  const std::vector<int32_t> instance = LabelInstances(run.grid, run.map, &instances);
  for (int id : selection.instances)
    if (id < 1 || id > int(instances.size()))
      return Status::InvalidInput("--instance " + std::to_string(id) + ": no such instance in " + args.outdir + " (valid: 1.." +
                                  std::to_string(instances.size()) + "; see `semvox remove " + args.outdir + " --list`)");
  const std::vector<uint8_t> remove = SelectForRemoval(run.map, instance, selection);
  if (std::find(remove.begin(), remove.end(), 1) == remove.end()) {
    std::map<int, size_t> present;
    for (const auto& r : run.map.occupied) ++present[r.label];
    std::string names;
    for (const auto& [l, n] : present) names += (names.empty() ? "" : ", ") + LabelName(l);
    return Status::InvalidInput(FileError((fs::path(args.outdir) / "voxels.ply").string(), "no voxel matches the selection",
                                          "classes present: " + names));
  }
  std::error_code ec;
  if (fs::exists(args.output) && fs::equivalent(args.output, args.outdir, ec))
    return Status::InvalidInput("-o " + args.output + ": same as OUTDIR (hint: write the edited map into another directory)");

  ObjectRemovalOptions options;
  options.planes = args.planes;
  ObjectRemovalResult out;
  SEMVOX_RETURN_IF_ERROR(RemoveObjects(run.grid, run.map, remove, options, &out));
  SEMVOX_INFO("removed " << out.removed_voxels << " voxels; " << out.nodes << " completion nodes (" << out.unknown_nodes
                         << " unseen); " << out.completed_voxels << " voxels completed; " << out.planes << " planes; "
                         << out.seconds << " s");

  fs::create_directories(args.output, ec);
  if (ec) return Status::InvalidInput(FileError(args.output, "cannot create the directory: " + ec.message()));
  const fs::path o(args.output);
  // Coordinates in the run's input frame, grids (map.ot, top views) on its canonical grid, as `semvox run`.
  SEMVOX_RETURN_IF_ERROR(WriteVoxelsPly(out.map, (o / "voxels.ply").string(), run.input_from_world));
  VoxelMeshStats mesh;
  SEMVOX_RETURN_IF_ERROR(WriteVoxelMesh(out.grid, out.map, (o / "mesh.ply").string(), (o / "mesh.obj").string(), &mesh,
                                        run.input_from_world));
  std::vector<SemanticVoxel> voxels;
  std::vector<int32_t> record(out.grid.size(), -1);
  for (size_t k = 0; k < out.map.occupied.size(); ++k) record[out.map.occupied[k].voxel] = int32_t(k);
  const auto& d = out.grid.dims();
  for (int iz = 0; iz < d[2]; ++iz)
    for (int iy = 0; iy < d[1]; ++iy)
      for (int ix = 0; ix < d[0]; ++ix) {
        const size_t i = out.grid.Index(ix, iy, iz);
        if (out.grid.state(i) == VoxelState::kUnknown) continue;
        SemanticVoxel v;
        v.key = out.grid.KeyOf(ix, iy, iz);
        v.occupied = out.grid.state(i) == VoxelState::kOccupied;
        if (record[i] >= 0) v.label = out.map.occupied[size_t(record[i])].label, v.confidence = out.map.occupied[size_t(record[i])].confidence;
        voxels.push_back(v);
      }
  SEMVOX_RETURN_IF_ERROR(WriteSemanticOctree(voxels, out.grid.resolution(), (o / "map.ot").string()));
  const OccupancyMap occ = ComputeOccupancy(out.grid, run.floor_z, args.occupancy);
  OccupancyMap occ_out = occ;
  if (!IsIdentity(run.input_from_world)) {
    const Eigen::Vector3d corner = run.input_from_world * Eigen::Vector3d(occ.origin_x, occ.origin_y, 0.0);
    const Eigen::Vector3d x = run.input_from_world.linear() * Eigen::Vector3d::UnitX();
    occ_out.origin_x = corner.x(), occ_out.origin_y = corner.y(), occ_out.origin_yaw = std::atan2(x.y(), x.x());
  }
  SEMVOX_RETURN_IF_ERROR(WriteOccupancyMap(occ_out, args.output, "occupancy"));
  const ImageU16 top = SemanticTopView(out.map, out.grid, run.floor_z, args.occupancy.band_min_above_floor_m,
                                       args.occupancy.band_max_above_floor_m);
  SEMVOX_RETURN_IF_ERROR(WriteImage((o / "semantic_topview_labels.png").string(), top));
  SEMVOX_RETURN_IF_ERROR(WriteImage((o / "semantic_topview.png").string(), ColourSemanticTopView(top, occ.image)));

  nlohmann::ordered_json j;
  j["source"] = args.outdir;
  nlohmann::ordered_json sel;
  nlohmann::ordered_json cls = nlohmann::ordered_json::array();
  for (int c : selection.classes) cls.push_back(LabelName(c));
  sel["classes"] = cls;
  sel["instances"] = selection.instances;
  sel["all_furniture"] = selection.all_furniture;
  j["selection"] = sel;
  j["voxel_size_m"] = out.grid.resolution();
  j["grid"] = {{"dims", out.grid.dims()}, {"origin_key", out.grid.origin_key()}};
  const Eigen::Matrix4d& t = run.input_from_world.matrix();
  auto input_z = [&](double z) { return IsIdentity(run.input_from_world) ? z : t(2, 2) * z + t(2, 3); };
  j["floor"] = {{"z", input_z(run.floor_z)}};  // Input frame, as the run's summary.json.
  j["ceiling"] = {{"z", input_z(run.ceiling_z)}};
  j["removed_voxels"] = out.removed_voxels;
  j["completion_nodes"] = {{"total", out.nodes}, {"unseen", out.unknown_nodes}};
  j["completed_voxels"] = out.completed_voxels;
  nlohmann::ordered_json cl = nlohmann::ordered_json::object();
  for (const auto& [l, n] : out.completed_labels) cl[LabelName(l)] = n;
  j["completed_labels"] = cl;
  j["planes"] = {{"detected", out.planes}, {"covering_nodes", out.planes_used}};
  j["energy"] = {{"initial", out.energy_initial}, {"final", out.energy_final}};
  j["occupied_voxels"] = out.map.occupied.size();
  j["mesh"] = {{"vertices", mesh.vertices}, {"quads", mesh.quads}};
  j["seconds"] = {{"completion", out.seconds},
                  {"total", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()}};
  j["files"] = {"voxels.ply", "map.ot", "mesh.ply", "mesh.obj", "mesh.mtl", "occupancy.pgm", "occupancy.yaml",
                "semantic_topview.png", "semantic_topview_labels.png", "summary.json"};
  return WriteFileAtomic((o / "summary.json").string(), j.dump(2) + "\n");
}

}  // namespace semvox
