#include "perception/training_data.h"

#include <cmath>

#include "core/labels.h"
#include "render/camera.h"
#include "scenegen/apartment.h"
#include "scenegen/scan_artefacts.h"

namespace semvox {

Image<int32_t> LabelLevel::Map(const Image<int32_t>& nyu40) const {
  Image<int32_t> out(nyu40.width, nyu40.height, 1, -1);
  for (size_t k = 0; k < nyu40.data.size(); ++k) {
    const int id = nyu40.data[k];
    out.data[k] = id >= 0 && id < int(class_of_nyu40.size()) ? class_of_nyu40[size_t(id)] : -1;
  }
  return out;
}

LabelLevel Nyu4Level() {
  LabelLevel level;
  level.name = "nyu4";
  level.class_names = {"ground", "structure", "furniture", "props"};
  level.class_of_nyu40.assign(kNumNyu40, -1);
  for (const LabelInfo& info : Nyu40Labels())
    if (info.id > 0 && info.nyu4_id >= 1 && info.nyu4_id <= 4) level.class_of_nyu40[size_t(info.id)] = info.nyu4_id - 1;
  return level;
}

LabelLevel SecondLevel() {
  using namespace nyu40;
  // ScanNet-20 (the NYU40 ids its benchmark scores) plus ceiling.
  const int kept[] = {kWall, kFloor, kCabinet, kBed, kChair, kSofa, kTable, kDoor, kWindow, kBookshelf, kPicture,
                      kCounter, kDesk, kCurtain, kRefrigerator, kShowerCurtain, kToilet, kSink, kBathtub,
                      kOtherFurniture, kCeiling};
  LabelLevel level;
  level.name = "second";
  level.class_of_nyu40.assign(kNumNyu40, -1);
  for (int id : kept) {
    level.class_of_nyu40[size_t(id)] = int(level.class_names.size());
    level.class_names.push_back(Nyu40Labels()[size_t(id)].name);
  }
  const int other = int(level.class_names.size());
  level.class_names.push_back("other");
  for (int id = 1; id < kNumNyu40; ++id)
    if (level.class_of_nyu40[size_t(id)] < 0) level.class_of_nyu40[size_t(id)] = other;
  return level;
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
  return true;
}

Status ForEachApartmentView(uint64_t seed, const TrainingViewsOptions& options,
                            const std::function<Status(const LabelledView&)>& sink) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("training views: " + error);
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
  if (label_it == scene.mesh.face_attributes.end() || label_it->second.size() != scene.mesh.faces.size())
    return Status::Internal("training views: generated mesh has no per-face label");
  const std::vector<int32_t>& face_label = label_it->second;
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene);
  if (!renderer.ok()) return renderer.status();
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(options.width, options.height, options.horizontal_fov_deg);
  RenderedView view;
  Image<int32_t> nyu40;
  for (const RoomGt& room : apartment->rooms) {
    const Eigen::Vector3d eye(0.5 * (room.x0 + room.x1), 0.5 * (room.y0 + room.y1), apartment->floor_z_m + options.eye_height_m);
    for (int h = 0; h < options.yaws_per_room; ++h) {
      const double yaw = 360.0 * h / options.yaws_per_room;
      SEMVOX_RETURN_IF_ERROR(renderer->Render(camera, WorldFromCameraYawPitch(eye, yaw, options.pitch_deg), RenderOptions{}, &view));
      const size_t pixels = size_t(options.width) * size_t(options.height);
      double depth_sum = 0;
      for (float d : view.depth.data) depth_sum += d;
      if (view.hit_pixels < options.min_hit_fraction * double(pixels) ||
          (view.hit_pixels > 0 && depth_sum / double(view.hit_pixels) < options.min_mean_depth_m))
        continue;
      nyu40 = Image<int32_t>(options.width, options.height, 1, 0);
      for (size_t k = 0; k < pixels; ++k) {
        const int32_t f = view.primitive.data[k];
        nyu40.data[k] = f >= 0 ? face_label[size_t(f)] : 0;
      }
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
