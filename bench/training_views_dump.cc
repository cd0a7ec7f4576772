// Writes the training views of one generated apartment as PNGs, to look at what the per-view classifiers
// learn from (flat or randomised style; docs/perception.md).
//
//   training_views_dump SEED OUTDIR [flat|randomised]   -> OUTDIR/seedS_rRR_hH.png (RGB | depth)
#include <cstdio>
#include <cstdlib>
#include <string>

#include "io/image_io.h"
#include "perception/training_data.h"

int main(int argc, char** argv) {
  using namespace semvox;
  if (argc < 3) {
    std::fprintf(stderr, "usage: training_views_dump SEED OUTDIR [flat|randomised]\n");
    return 2;
  }
  TrainingViewsOptions views;
  if (argc > 3 && !ParseTrainingStyle(argv[3], &views.style)) {
    std::fprintf(stderr, "training_views_dump: style '%s' is not flat or randomised\n", argv[3]);
    return 2;
  }
  const uint64_t seed = std::strtoull(argv[1], nullptr, 10);
  const std::string out = argv[2];
  const Status st = ForEachApartmentView(seed, views, [&](const LabelledView& v) {
    const int w = v.view->camera.width, h = v.view->camera.height;
    ImageRgb8 image(2 * w, h, 3, 0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        for (int c = 0; c < 3; ++c) image.at(x, y, c) = v.view->rgb.at(x, y, c);
        const float d = v.view->depth.at(x, y);
        const uint8_t g = d > 0 ? uint8_t(std::min(255.0, 40.0 * d)) : 0;
        for (int c = 0; c < 3; ++c) image.at(w + x, y, c) = g;
      }
    char name[128];
    std::snprintf(name, sizeof(name), "/seed%llu_r%02d_h%d.png", static_cast<unsigned long long>(seed), v.room_id, v.heading);
    return WriteImage(out + name, image);
  });
  if (!st.ok()) {
    std::fprintf(stderr, "training_views_dump: %s\n", st.message().c_str());
    return 1;
  }
  return 0;
}
