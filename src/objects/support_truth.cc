#include "objects/support_truth.h"

#include <unordered_map>

#include "core/labels.h"
#include "objects/support_clutter.h"
#include "render/camera.h"
#include "scenegen/apartment.h"
#include "scenegen/scan_artefacts.h"

namespace semvox {

bool SupportTruthOptions::Check(std::string* error) const {
  if (!(min_up_normal > 0 && min_up_normal <= 1)) {
    if (error) *error = "min_up_normal = " + std::to_string(min_up_normal) + ". Violated constraint: 0 < min_up_normal <= 1";
    return false;
  }
  if (!(min_height_m >= 0)) {
    if (error) *error = "min_height_m = " + std::to_string(min_height_m) + ". Violated constraint: min_height_m >= 0";
    return false;
  }
  return true;
}

std::vector<int8_t> SupportRoleOfFaces(const Apartment& apartment, const std::vector<int32_t>& face_label,
                                       const std::vector<int32_t>& face_instance) {
  using namespace nyu40;
  auto support_label = [](int l) {
    return l == kTable || l == kDesk || l == kCounter || l == kNightStand || l == kDresser || l == kShelves ||
           l == kBookshelf || l == kCabinet || l == kBed;
  };
  std::unordered_map<int, int8_t> role_of_instance;
  for (const ObjectGt& o : apartment.objects) {
    int8_t role = 0;
    if (support_label(o.label)) role = 1;
    const bool props = o.label > 0 && o.label < kNumNyu40 && Nyu40Labels()[size_t(o.label)].nyu4_id == 4;
    if (o.support_of >= 0 && props && o.label != kSink) role = 2;
    role_of_instance[o.instance] = role;
  }
  std::vector<int8_t> out(face_label.size(), 0);
  for (size_t f = 0; f < face_label.size(); ++f) {
    const auto it = role_of_instance.find(face_instance[f]);
    if (face_instance[f] >= 0 && it != role_of_instance.end()) out[f] = it->second;
  }
  return out;
}

Image<int32_t> SupportTruth(const RenderedView& view, const std::vector<int8_t>& face_role, double floor_z_m,
                            const SupportTruthOptions& options) {
  const int w = view.rgb.width, h = view.rgb.height;
  Image<int32_t> out(w, h, 1, -1);
  const Eigen::Matrix3d R = view.world_from_camera.linear();
  const Eigen::Vector3d t = view.world_from_camera.translation();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int32_t f = view.primitive.at(x, y);
      if (f < 0) continue;
      const int8_t role = size_t(f) < face_role.size() ? face_role[size_t(f)] : 0;
      int c = kOtherSurface;
      if (role == 2) {
        c = kClutter;
      } else if (role == 1 && view.normal.at(x, y, 2) >= options.min_up_normal) {
        const double z = (t + R * (view.camera.PixelRay(x, y) * double(view.depth.at(x, y)))).z();
        if (z - floor_z_m >= options.min_height_m) c = kSupportSurface;
      }
      out.at(x, y) = c;
    }
  return out;
}

Status ForEachSupportView(uint64_t seed, const TrainingViewsOptions& options, const SupportTruthOptions& truth_options,
                          const std::function<Status(const SupportView&)>& sink) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("support views: " + error);
  if (!truth_options.Check(&error)) return Status::InvalidInput("support truth: " + error);
  ApartmentOptions apartment_options;
  apartment_options.seed = seed;
  Result<Apartment> apartment = GenerateApartment(apartment_options);
  if (!apartment.ok()) return apartment.status();
  ScanArtefactOptions artefacts;
  artefacts.seed = seed;
  Scene scene;
  scene.format = "generated";
  scene.source_path = "seed " + std::to_string(seed);
  scene.mesh = ApplyScanArtefacts(*apartment, artefacts);
  const auto label_it = scene.mesh.face_attributes.find("label");
  const auto instance_it = scene.mesh.face_attributes.find("instance");
  if (label_it == scene.mesh.face_attributes.end() || instance_it == scene.mesh.face_attributes.end() ||
      label_it->second.size() != scene.mesh.faces.size() || instance_it->second.size() != scene.mesh.faces.size())
    return Status::Internal("support views: generated mesh has no per-face label and instance");
  const std::vector<int8_t> role = SupportRoleOfFaces(*apartment, label_it->second, instance_it->second);
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene);
  if (!renderer.ok()) return renderer.status();
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(options.width, options.height, options.horizontal_fov_deg);
  RenderedView view;
  Image<int32_t> nyu40, truth, instance;
  for (const RoomGt& room : apartment->rooms) {
    const Eigen::Vector3d eye(0.5 * (room.x0 + room.x1), 0.5 * (room.y0 + room.y1), apartment->floor_z_m + options.eye_height_m);
    for (int hd = 0; hd < options.yaws_per_room; ++hd) {
      const double yaw = 360.0 * hd / options.yaws_per_room;
      SEMVOX_RETURN_IF_ERROR(renderer->Render(camera, WorldFromCameraYawPitch(eye, yaw, options.pitch_deg), RenderOptions{}, &view));
      const size_t pixels = size_t(options.width) * size_t(options.height);
      double depth_sum = 0;
      for (float d : view.depth.data) depth_sum += d;
      if (view.hit_pixels < options.min_hit_fraction * double(pixels) ||
          (view.hit_pixels > 0 && depth_sum / double(view.hit_pixels) < options.min_mean_depth_m))
        continue;
      nyu40 = Image<int32_t>(options.width, options.height, 1, 0);
      instance = Image<int32_t>(options.width, options.height, 1, -1);
      for (size_t k = 0; k < pixels; ++k) {
        const int32_t f = view.primitive.data[k];
        nyu40.data[k] = f >= 0 ? label_it->second[size_t(f)] : 0;
        instance.data[k] = f >= 0 ? instance_it->second[size_t(f)] : -1;
      }
      truth = SupportTruth(view, role, apartment->floor_z_m, truth_options);
      SupportView sv;
      sv.seed = seed;
      sv.room_id = room.id;
      sv.heading = hd;
      sv.view = &view;
      sv.nyu40 = &nyu40;
      sv.truth = &truth;
      sv.instance = &instance;
      sv.apartment = &*apartment;
      SEMVOX_RETURN_IF_ERROR(sink(sv));
    }
  }
  return Status::Ok();
}

}  // namespace semvox
