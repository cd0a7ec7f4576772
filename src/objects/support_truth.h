// Ground truth for support / clutter / other from generated apartments (library semvox_objects_train,
// which adds scenegen; the classifier itself does not depend on the generator).
//
//   ForEachSupportView(seed, TrainingViewsOptions{}, SupportTruthOptions{}, [&](const SupportView& v) { ... });
//
// A pixel is
//   support  when it hits an upward-facing surface (rendered normal z >= min_up_normal) at least
//            min_height_m above the floor of an object whose NYU40 label holds things in the generator: table,
//            desk, counter, night stand, dresser, shelves, bookshelf, cabinet, bed. The floor is never
//            support (the paper: "support structures can not lie on the ground"); chairs and sofas are not
//            support (nothing is put on them), the sides and fronts of a table are "other": the paper labels
//            "only the part of the structure which supports objects, for example the table top".
//   clutter  when it hits an object standing on another one (ObjectGt::support_of >= 0) whose NYU-4 class
//            is props (books, boxes, bags, clothes, paper, lamps, TVs, pillows, other props), sinks excepted
//            (they are part of the counter). Props on the floor are "other".
//   other    every other hit; pixels that hit nothing are -1 (ignored).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/status.h"
#include "perception/training_data.h"
#include "render/view_renderer.h"

namespace semvox {

struct Apartment;

struct SupportTruthOptions {
  double min_up_normal = 0.9;   // cos of the largest tilt of a support surface from horizontal. (0, 1].
  double min_height_m = 0.15;   // Support surfaces are at least this far above the floor, metres. >= 0.

  bool Check(std::string* error) const;
};

// Per face of `mesh` (whose face attributes `label` and `instance` come from `apartment`): 1 when the face
// belongs to a support-capable object, 2 when it belongs to clutter, 0 otherwise.
std::vector<int8_t> SupportRoleOfFaces(const Apartment& apartment, const std::vector<int32_t>& face_label,
                                       const std::vector<int32_t>& face_instance);

// SupportClass per pixel (-1 where nothing is hit) from the per-face roles, the rendered normals and
// heights (world z), and the floor height.
Image<int32_t> SupportTruth(const RenderedView& view, const std::vector<int8_t>& face_role, double floor_z_m,
                            const SupportTruthOptions& options);

struct SupportView {
  uint64_t seed = 0;
  int room_id = 0;
  int heading = 0;
  const RenderedView* view = nullptr;
  const Image<int32_t>* nyu40 = nullptr;  // Per pixel, 0 where nothing is hit.
  const Image<int32_t>* truth = nullptr;  // SupportClass per pixel, -1 where nothing is hit.
  const Image<int32_t>* instance = nullptr;  // Object instance per pixel, -1 for walls, floors, misses.
  const Apartment* apartment = nullptr;
};

// The training views of perception/training_data.h (room middles, eye height, `yaws_per_room` headings)
// with the support/clutter ground truth.
Status ForEachSupportView(uint64_t seed, const TrainingViewsOptions& views, const SupportTruthOptions& truth,
                          const std::function<Status(const SupportView&)>& sink);

}  // namespace semvox
