#include "perception/training_data.h"

#include <algorithm>
#include <cmath>

#include "core/labels.h"
#include "render/camera.h"
#include "scenegen/apartment.h"
#include "scenegen/random.h"
#include "scenegen/scan_artefacts.h"
#include "scenegen/scan_simulator.h"

namespace semvox {

const char* TrainingStyleName(TrainingStyle style) { return style == TrainingStyle::kFlat ? "flat" : "randomised"; }

bool ParseTrainingStyle(const std::string& name, TrainingStyle* style) {
  if (name == "flat") *style = TrainingStyle::kFlat;
  else if (name == "randomised" || name == "randomized") *style = TrainingStyle::kRandomised;
  else return false;
  return true;
}

bool TrainingViewsOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (width < 16 || height < 16) return fail("width x height = " + std::to_string(width) + "x" + std::to_string(height) + ". Violated constraint: both >= 16");
  if (!(horizontal_fov_deg > 0 && horizontal_fov_deg < 180))
    return fail("horizontal_fov_deg = " + std::to_string(horizontal_fov_deg) + ". Violated constraint: 0 < horizontal_fov_deg < 180");
  if (!(eye_height_m > 0)) return fail("eye_height_m = " + std::to_string(eye_height_m) + ". Violated constraint: eye_height_m > 0");
  if (yaws_per_room < 1) return fail("yaws_per_room = " + std::to_string(yaws_per_room) + ". Violated constraint: yaws_per_room >= 1");
  if (!(min_hit_fraction >= 0 && min_hit_fraction <= 1))
    return fail("min_hit_fraction = " + std::to_string(min_hit_fraction) + ". Violated constraint: 0 <= min_hit_fraction <= 1");
  if (!(min_mean_depth_m >= 0)) return fail("min_mean_depth_m = " + std::to_string(min_mean_depth_m) + ". Violated constraint: min_mean_depth_m >= 0");
  if (!(cloud_probability >= 0 && cloud_probability <= 1)) return fail("cloud_probability must lie in [0, 1]");
  if (!(min_point_spacing_m > 0 && max_point_spacing_m >= min_point_spacing_m))
    return fail("point spacing [" + std::to_string(min_point_spacing_m) + ", " + std::to_string(max_point_spacing_m) +
                "]. Violated constraint: 0 < min_point_spacing_m <= max_point_spacing_m");
  if (!(position_jitter >= 0 && position_jitter < 1)) return fail("position_jitter must lie in [0, 1)");
  if (!(eye_height_jitter_m >= 0 && pitch_jitter_deg >= 0)) return fail("eye_height_jitter_m and pitch_jitter_deg must be >= 0");
  return augmentation.Check(error);
}

namespace {
// One or two lights under the ceiling of every room.
std::vector<Eigen::Vector3d> RoomLights(const Apartment& apartment, Rng& rng) {
  std::vector<Eigen::Vector3d> lights;
  for (const RoomGt& room : apartment.rooms) {
    const int n = rng.UniformInt(1, 2);
    for (int k = 0; k < n; ++k)
      lights.emplace_back(rng.Uniform(room.x0, room.x1), rng.Uniform(room.y0, room.y1), apartment.ceiling_z_m - rng.Uniform(0.2, 0.6));
  }
  return lights;
}

// The surface an element shows: its object instance, else (structure) its label in its room.
int32_t SurfaceId(int32_t instance, int32_t label, int32_t room) { return instance >= 0 ? instance : 1000000 + 1000 * label + (room + 1); }
}  // namespace

Result<Scene> MakeTrainingScan(const Apartment& apartment, uint64_t seed, const TrainingViewsOptions& options) {
  const bool randomised = options.style == TrainingStyle::kRandomised;
  Rng rng(SplitMix64(seed ^ 0x7261'6e64'6f6d'6973ULL));
  Scene scene;
  scene.format = "generated";
  scene.source_path = "seed " + std::to_string(seed);
  if (randomised && rng.Bernoulli(options.cloud_probability)) {
    // A fused RGB-D / lidar scan: points on a grid of random spacing, no normals (as real fused clouds come),
    // holes, and the ceiling missing in patches or entirely.
    ScanSimulationOptions scan;
    scan.seed = seed;
    scan.fuse_voxel_m = rng.Uniform(options.min_point_spacing_m, options.max_point_spacing_m);
    scan.station_spacing_m = rng.Uniform(1.4, 2.6);
    scan.scanner_height_m = rng.Uniform(1.2, 1.6);
    Result<PointCloud> cloud = SimulateScan(apartment, scan);
    if (!cloud.ok()) return cloud.status();
    const std::vector<int32_t>& label = cloud->point_attributes["label"];
    {  // Colours as a fused RGB-D scan bakes them: palette, texture and lighting in 3D.
      std::vector<int32_t> surface(cloud->points.size());
      const auto& instance = cloud->point_attributes["instance"];
      const auto& room = cloud->point_attributes["room"];
      for (size_t i = 0; i < surface.size(); ++i) surface[i] = SurfaceId(instance[i], label[i], room[i]);
      if (cloud->colors.size() != cloud->points.size()) cloud->colors.assign(cloud->points.size(), Rgb8{128, 128, 128});
      RepaintScan(cloud->points, cloud->normals, surface, RoomLights(apartment, rng), rng.Next(), options.augmentation, &cloud->colors);
    }
    const double ceiling_keep = rng.Bernoulli(0.4) ? 0.0 : rng.Uniform(0.3, 1.0);
    struct Hole {
      Eigen::Vector3f c;
      float r2;
    };
    std::vector<Hole> holes(size_t(rng.UniformInt(0, 12)));
    for (Hole& hole : holes) {
      const Eigen::Vector3f lo = apartment.bounds.min, hi = apartment.bounds.max;
      hole.c = Eigen::Vector3f(float(rng.Uniform(lo.x(), hi.x())), float(rng.Uniform(lo.y(), hi.y())), float(rng.Uniform(lo.z(), hi.z())));
      const float r = float(rng.Uniform(0.1, 0.5));
      hole.r2 = r * r;
    }
    const uint64_t patch_seed = rng.Next();
    PointCloud kept;
    for (auto& [name, values] : cloud->point_attributes) kept.point_attributes[name];
    for (size_t i = 0; i < cloud->points.size(); ++i) {
      const Eigen::Vector3f& p = cloud->points[i];
      if (label[i] == nyu40::kCeiling) {
        // Patches of about a metre: hash of the cell.
        const uint64_t cell = SplitMix64(patch_seed ^ (uint64_t(int64_t(std::floor(p.x()))) * 73856093ULL) ^
                                         (uint64_t(int64_t(std::floor(p.y()))) * 19349663ULL));
        if (double(cell >> 11) * 0x1.0p-53 >= ceiling_keep) continue;
      }
      bool in_hole = false;
      for (const Hole& hole : holes) in_hole = in_hole || (p - hole.c).squaredNorm() < hole.r2;
      if (in_hole) continue;
      kept.points.push_back(p);
      if (cloud->has_colors()) kept.colors.push_back(cloud->colors[i]);
      for (auto& [name, values] : cloud->point_attributes) kept.point_attributes[name].push_back(values[i]);
    }
    scene.cloud = std::move(kept);
  } else {
    ScanArtefactOptions artefacts;
    artefacts.seed = seed;
    if (randomised) {
      artefacts.holes_per_m2 = rng.Uniform(0.0, 0.1);
      artefacts.unscanned_ceiling_fraction = rng.Bernoulli(0.3) ? 1.0 : rng.Uniform(0.0, 0.6);
      artefacts.vertex_noise_m = rng.Uniform(0.0, 0.01);
    }
    scene.mesh = ApplyScanArtefacts(apartment, artefacts);
    if (randomised) {  // Per-vertex palette colours and lighting (AugmentView adds texture per pixel).
      Mesh& m = scene.mesh;
      std::vector<int32_t> surface(m.vertices.size(), -1);
      std::vector<Eigen::Vector3f> normals(m.vertices.size(), Eigen::Vector3f::Zero());
      const auto& label = m.face_attributes["label"];
      const auto& instance = m.face_attributes["instance"];
      const auto& room = m.face_attributes["room"];
      for (size_t f = 0; f < m.faces.size(); ++f) {
        const Eigen::Vector3i& t = m.faces[f];
        const Eigen::Vector3f n = (m.vertices[size_t(t[1])] - m.vertices[size_t(t[0])]).cross(m.vertices[size_t(t[2])] - m.vertices[size_t(t[0])]);
        for (int k = 0; k < 3; ++k) {
          if (surface[size_t(t[k])] >= 0) continue;
          surface[size_t(t[k])] = SurfaceId(instance[f], label[f], room[f]);
          normals[size_t(t[k])] = n.normalized();
        }
      }
      if (m.vertex_colors.size() != m.vertices.size()) m.vertex_colors.assign(m.vertices.size(), Rgb8{128, 128, 128});
      RepaintScan(m.vertices, normals, surface, RoomLights(apartment, rng), rng.Next(), options.augmentation, &m.vertex_colors);
    }
  }
  return scene;
}

namespace {

// Where a room is seen from: its box middle when that is on its floor, else the point of its floor nearest
// the middle with 0.3 m of floor around it (or its floor point nearest the middle).
Eigen::Vector2d RoomViewpoint(const Apartment& apartment, const RoomGt& room) {
  const Eigen::Vector2d middle(0.5 * (room.x0 + room.x1), 0.5 * (room.y0 + room.y1));
  const ImageU16& r = apartment.room_raster;
  if (r.data.empty() || RoomIdAt(apartment, middle.x(), middle.y()) == room.id) return middle;
  const double res = apartment.room_raster_m;
  const int margin = std::max(1, int(std::lround(0.3 / res)));
  // Rows of the room's pixels with `margin` of room around them (a square): a box sum over the room mask.
  std::vector<int> sum(size_t(r.width + 1) * size_t(r.height + 1), 0);
  auto S = [&](int c, int row) -> int& { return sum[size_t(row) * size_t(r.width + 1) + size_t(c)]; };
  for (int row = 0; row < r.height; ++row)
    for (int c = 0; c < r.width; ++c) S(c + 1, row + 1) = (r.at(c, row) == room.id) + S(c, row + 1) + S(c + 1, row) - S(c, row);
  double best_deep = 1e300, best_any = 1e300;
  Eigen::Vector2d deep = middle, any = middle;
  for (int row = 0; row < r.height; ++row)
    for (int c = 0; c < r.width; ++c) {
      if (r.at(c, row) != room.id) continue;
      const Eigen::Vector2d p = apartment.room_raster_origin + res * Eigen::Vector2d(c + 0.5, row + 0.5);
      const double d = (p - middle).squaredNorm();
      if (d < best_any) best_any = d, any = p;
      const int c0 = c - margin, r0 = row - margin, c1 = c + margin + 1, r1 = row + margin + 1;
      if (c0 < 0 || r0 < 0 || c1 > r.width || r1 > r.height) continue;
      const int n = S(c1, r1) - S(c0, r1) - S(c1, r0) + S(c0, r0);
      if (n == (2 * margin + 1) * (2 * margin + 1) && d < best_deep) best_deep = d, deep = p;
    }
  return best_deep < 1e300 ? deep : any;
}

}  // namespace

Status ForEachApartmentView(uint64_t seed, const TrainingViewsOptions& options,
                            const std::function<Status(const LabelledView&)>& sink) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("training views: " + error);
  ApartmentOptions apartment_options;
  apartment_options.seed = seed;
  apartment_options.shape_variety = options.style == TrainingStyle::kRandomised;
  Result<Apartment> apartment = GenerateApartment(apartment_options);
  if (!apartment.ok()) return apartment.status();
  return ForEachViewOfApartment(*apartment, seed, options, sink);
}

Status ForEachViewOfApartment(const Apartment& apartment, uint64_t seed, const TrainingViewsOptions& options,
                              const std::function<Status(const LabelledView&)>& sink) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("training views: " + error);
  const bool randomised = options.style == TrainingStyle::kRandomised;
  Result<Scene> scan = MakeTrainingScan(apartment, seed, options);
  if (!scan.ok()) return scan.status();
  Scene scene = std::move(scan).value();
  const char* per_element = scene.is_mesh() ? "face" : "point";
  // Draws of the views (positions, headings, augmentation seeds), apart from those of the scan.
  Rng rng(SplitMix64(seed ^ 0x7669'6577'7365'6564ULL));
  auto& attributes = scene.is_mesh() ? scene.mesh.face_attributes : scene.cloud.point_attributes;
  const size_t elements = scene.is_mesh() ? scene.mesh.faces.size() : scene.cloud.points.size();
  const auto label_it = attributes.find("label");
  if (label_it == attributes.end() || label_it->second.size() != elements)
    return Status::Internal(std::string("training views: generated scene has no per-") + per_element + " label");
  const std::vector<int32_t>& element_label = label_it->second;
  const std::vector<int32_t>* element_instance = attributes.count("instance") ? &attributes.at("instance") : nullptr;
  const std::vector<int32_t>* element_room = attributes.count("room") ? &attributes.at("room") : nullptr;
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene);
  if (!renderer.ok()) return renderer.status();
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(options.width, options.height, options.horizontal_fov_deg);
  const uint64_t scene_seed = rng.Next();
  ViewAugmentationOptions augmentation = options.augmentation;
  augmentation.floor_z_m = apartment.floor_z_m;
  augmentation.repaint_surfaces = scene.is_mesh();  // Clouds were repainted in 3D (MakeTrainingScan).
  RenderedView view;
  Image<int32_t> nyu40, surface;
  for (const RoomGt& room : apartment.rooms) {
    const Eigen::Vector2d middle = RoomViewpoint(apartment, room);
    for (int h = 0; h < options.yaws_per_room; ++h) {
      Eigen::Vector3d eye(middle.x(), middle.y(), apartment.floor_z_m + options.eye_height_m);
      double yaw = 360.0 * h / options.yaws_per_room, pitch = options.pitch_deg;
      if (randomised) {
        eye.x() += options.position_jitter * 0.5 * (room.x1 - room.x0) * rng.Uniform(-1, 1);
        eye.y() += options.position_jitter * 0.5 * (room.y1 - room.y0) * rng.Uniform(-1, 1);
        eye.z() += rng.Uniform(-options.eye_height_jitter_m, options.eye_height_jitter_m);
        eye.z() = std::min(eye.z(), apartment.ceiling_z_m - 0.2);
        yaw += rng.Uniform(0, 360.0 / options.yaws_per_room);
        pitch += rng.Uniform(-options.pitch_jitter_deg, options.pitch_jitter_deg);
      }
      const uint64_t view_seed = rng.Next();
      SEMVOX_RETURN_IF_ERROR(renderer->Render(camera, WorldFromCameraYawPitch(eye, yaw, pitch), RenderOptions{}, &view));
      const size_t pixels = size_t(options.width) * size_t(options.height);
      double depth_sum = 0;
      for (float d : view.depth.data) depth_sum += d;
      if (view.hit_pixels < options.min_hit_fraction * double(pixels) ||
          (view.hit_pixels > 0 && depth_sum / double(view.hit_pixels) < options.min_mean_depth_m))
        continue;
      nyu40 = Image<int32_t>(options.width, options.height, 1, 0);
      surface = Image<int32_t>(options.width, options.height, 1, -1);
      for (size_t k = 0; k < pixels; ++k) {
        const int32_t f = view.primitive.data[k];
        if (f < 0) continue;
        nyu40.data[k] = element_label[size_t(f)];
        // The surface a pixel shows: the object instance, else (structure) its label in its room.
        const int32_t instance = element_instance ? (*element_instance)[size_t(f)] : -1;
        const int32_t r = element_room ? (*element_room)[size_t(f)] : -1;
        surface.data[k] = SurfaceId(instance, nyu40.data[k], r);
      }
      if (randomised) SEMVOX_RETURN_IF_ERROR(AugmentView(surface, scene_seed, view_seed, augmentation, &view));
      LabelledView lv;
      lv.seed = seed;
      lv.room_id = room.id;
      lv.room_type = room.type_id;
      lv.heading = h;
      lv.view = &view;
      lv.nyu40 = &nyu40;
      SEMVOX_RETURN_IF_ERROR(sink(lv));
    }
  }
  return Status::Ok();
}

}  // namespace semvox
