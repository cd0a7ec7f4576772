#include "perception/view_augmentation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <vector>

#include "scenegen/random.h"

namespace semvox {

bool ViewAugmentationOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  auto prob = [](double p) { return p >= 0 && p <= 1; };
  if (!prob(recolour_probability) || !prob(texture_probability) || !prob(flying_pixel_probability))
    return fail("recolour_probability, texture_probability and flying_pixel_probability must lie in [0, 1]");
  if (max_lights < 1) return fail("max_lights = " + std::to_string(max_lights) + ". Violated constraint: max_lights >= 1");
  if (!(exposure_min > 0 && exposure_max >= exposure_min))
    return fail("exposure range [" + std::to_string(exposure_min) + ", " + std::to_string(exposure_max) +
                "]. Violated constraint: 0 < exposure_min <= exposure_max");
  if (!(white_balance >= 0 && white_balance < 1)) return fail("white_balance must lie in [0, 1)");
  if (!(max_blur_sigma_px >= 0) || !(max_colour_noise >= 0) || !(depth_noise_sigma_m >= 0) ||
      !(depth_noise_quadratic >= 0) || !(depth_quantisation >= 0))
    return fail("blur, colour noise, depth noise and depth quantisation must be >= 0");
  return true;
}

namespace {

using Vec3 = Eigen::Vector3d;

// HSV (h in degrees, s and v in [0, 1]) to RGB in [0, 1].
Vec3 HsvToRgb(double h, double s, double v) {
  h = std::fmod(std::fmod(h, 360.0) + 360.0, 360.0) / 60.0;
  const int i = int(std::floor(h));
  const double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  switch (i) {
    case 0: return {v, t, p};
    case 1: return {q, v, p};
    case 2: return {p, v, t};
    case 3: return {p, q, v};
    case 4: return {t, p, v};
    default: return {v, p, q};
  }
}

// A colour from wide interior palettes; none of them belongs to a class.
Vec3 PaletteColour(Rng& rng) {
  const double u = rng.Uniform01();
  if (u < 0.35) return HsvToRgb(rng.Uniform(0, 360), rng.Uniform(0.0, 0.15), rng.Uniform(0.2, 0.95));   // neutrals
  if (u < 0.60) return HsvToRgb(rng.Uniform(15, 50), rng.Uniform(0.25, 0.75), rng.Uniform(0.2, 0.85));  // woods, beiges
  if (u < 0.72) return HsvToRgb(rng.Uniform(0, 360), rng.Uniform(0.0, 0.5), rng.Uniform(0.03, 0.2));    // darks
  return HsvToRgb(rng.Uniform(0, 360), rng.Uniform(0.2, 0.9), rng.Uniform(0.2, 0.9));                   // anything
}

// Smooth 3D value noise in [0, 1] (trilinear interpolation of hashed lattice values).
double ValueNoise(const Vec3& p, uint64_t seed) {
  const Eigen::Vector3d f = p.array().floor();
  const Eigen::Vector3d t = p - f;
  const Eigen::Vector3d s = t.array() * t.array() * (3.0 - 2.0 * t.array());
  auto lattice = [&](int dx, int dy, int dz) {
    const uint64_t h = SplitMix64(seed ^ SplitMix64(uint64_t(int64_t(f.x()) + dx) * 0x9E3779B1ULL ^
                                                    SplitMix64(uint64_t(int64_t(f.y()) + dy) * 0x85EBCA77ULL ^
                                                               SplitMix64(uint64_t(int64_t(f.z()) + dz)))));
    return double(h >> 11) * 0x1.0p-53;
  };
  double v = 0;
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const double w = (dx ? s.x() : 1 - s.x()) * (dy ? s.y() : 1 - s.y()) * (dz ? s.z() : 1 - s.z());
        v += w * lattice(dx, dy, dz);
      }
  return v;
}

enum class Texture { kNone, kFabric, kWood, kTiles, kBands, kBlotches };

// What a surface looks like: drawn once per (scene, surface).
struct SurfaceLook {
  Vec3 albedo = Vec3::Constant(0.5);
  Vec3 second = Vec3::Constant(0.5);  // Grout, stain or band colour.
  Texture texture = Texture::kNone;
  double frequency = 10;   // Cycles per metre (fabric, wood), tile size or band width (metres).
  double amplitude = 0.2;
  Vec3 axis = Vec3::UnitX();  // Horizontal direction of wood grain and bands.
  uint64_t seed = 0;
};

SurfaceLook DrawLook(uint64_t scene_seed, int32_t surface, const Vec3& own, const ViewAugmentationOptions& o) {
  Rng rng(SplitMix64(scene_seed ^ SplitMix64(uint64_t(int64_t(surface)) + 0x5eed5eedULL)));
  SurfaceLook look;
  if (rng.Bernoulli(o.recolour_probability)) {
    look.albedo = PaletteColour(rng);
  } else {
    look.albedo = (own.array() * Eigen::Array3d(rng.Uniform(0.7, 1.3), rng.Uniform(0.7, 1.3), rng.Uniform(0.7, 1.3))).matrix();
  }
  look.albedo = look.albedo.cwiseMax(0.02).cwiseMin(1.0);
  look.second = PaletteColour(rng);
  look.seed = rng.Next();
  const double a = rng.Uniform(0, 2 * M_PI);
  look.axis = Vec3(std::cos(a), std::sin(a), 0);
  if (rng.Bernoulli(o.texture_probability)) {
    switch (rng.UniformInt(0, 4)) {
      case 0: look.texture = Texture::kFabric, look.frequency = rng.Uniform(8, 45), look.amplitude = rng.Uniform(0.1, 0.45); break;
      case 1: look.texture = Texture::kWood, look.frequency = rng.Uniform(6, 30), look.amplitude = rng.Uniform(0.08, 0.3); break;
      case 2: look.texture = Texture::kTiles, look.frequency = rng.Uniform(0.1, 0.6), look.amplitude = rng.Uniform(0.006, 0.02); break;
      case 3: look.texture = Texture::kBands, look.frequency = rng.Uniform(0.03, 0.35), look.amplitude = rng.Uniform(0.3, 1.0); break;
      default: look.texture = Texture::kBlotches, look.frequency = rng.Uniform(1, 5), look.amplitude = rng.Uniform(0.2, 0.7); break;
    }
  }
  return look;
}

Vec3 Textured(const SurfaceLook& look, const Vec3& p, const Vec3& n) {
  switch (look.texture) {
    case Texture::kNone: return look.albedo;
    case Texture::kFabric: return look.albedo * (1 + look.amplitude * (2 * ValueNoise(p * look.frequency, look.seed) - 1));
    case Texture::kWood: {
      const double t = p.dot(look.axis) * look.frequency + 4 * ValueNoise(p * 1.5, look.seed);
      return look.albedo * (1 + look.amplitude * std::sin(2 * M_PI * t));
    }
    case Texture::kTiles: {
      // Grid lines on the two axes across the surface's dominant normal axis.
      int k = 0;
      n.cwiseAbs().maxCoeff(&k);
      const double s = look.frequency;
      bool grout = false;
      for (int a = 0; a < 3; ++a) {
        if (a == k) continue;
        const double u = p[a] / s - std::floor(p[a] / s);
        grout = grout || u * s < look.amplitude;
      }
      return grout ? look.second : look.albedo;
    }
    case Texture::kBands: {
      const int64_t band = int64_t(std::floor(p.dot(look.axis) / look.frequency));
      Rng rng(SplitMix64(look.seed ^ uint64_t(band)));
      return rng.Bernoulli(0.5) ? look.albedo : (1 - look.amplitude) * look.albedo + look.amplitude * PaletteColour(rng);
    }
    case Texture::kBlotches: {
      const double w = std::clamp((ValueNoise(p * look.frequency, look.seed) - 0.5) * 4 + 0.5, 0.0, 1.0) * look.amplitude;
      return (1 - w) * look.albedo + w * look.second;
    }
  }
  return look.albedo;
}

struct Light {
  Vec3 p;
  double intensity;
};

// Ambient light plus Lambert point lights with inverse-square falloff at `p` (unit normal `n`; two_sided:
// light from either side of an unoriented normal), darkened near the floor (ambient occlusion).
double Shade(const Vec3& p, const Vec3& n, const std::vector<Light>& lights, double ambient, double occlusion, double floor_z,
             bool two_sided) {
  double shade = ambient;
  for (const Light& l : lights) {
    const Vec3 to = l.p - p;
    const double dist2 = to.squaredNorm();
    const double cosine = n.dot(to) / std::sqrt(dist2 + 1e-12);
    shade += l.intensity * (two_sided ? std::abs(cosine) : std::max(0.0, cosine)) / (1 + dist2 / 6.0);
  }
  return shade * (1 - occlusion * std::exp(-std::max(0.0, p.z() - floor_z) / 0.25));
}

void GaussianBlur(ImageF32* image, double sigma) {
  const int r = int(std::ceil(2.5 * sigma));
  std::vector<double> k(size_t(2 * r + 1));
  double sum = 0;
  for (int i = -r; i <= r; ++i) sum += k[size_t(i + r)] = std::exp(-0.5 * i * i / (sigma * sigma));
  for (double& v : k) v /= sum;
  const int w = image->width, h = image->height, c = image->channels;
  ImageF32 tmp(w, h, c);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int ch = 0; ch < c; ++ch) {
        double v = 0;
        for (int i = -r; i <= r; ++i) v += k[size_t(i + r)] * image->at(std::clamp(x + i, 0, w - 1), y, ch);
        tmp.at(x, y, ch) = float(v);
      }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int ch = 0; ch < c; ++ch) {
        double v = 0;
        for (int i = -r; i <= r; ++i) v += k[size_t(i + r)] * tmp.at(x, std::clamp(y + i, 0, h - 1), ch);
        image->at(x, y, ch) = float(v);
      }
}

}  // namespace

Status AugmentView(const Image<int32_t>& surface, uint64_t scene_seed, uint64_t view_seed,
                   const ViewAugmentationOptions& options, RenderedView* view) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("view augmentation: " + error);
  const int w = view->camera.width, h = view->camera.height;
  if (surface.width != w || surface.height != h || view->rgb.width != w || view->rgb.height != h || view->depth.width != w ||
      view->depth.height != h || view->normal.width != w || view->normal.height != h)
    return Status::InvalidInput("view augmentation: surface ids, rgb, depth and normals must have the view's size");
  Rng rng(SplitMix64(view_seed ^ 0xa09e667f3bcc908bULL));
  // Lights of this view: under the ceiling around the camera.
  const Vec3 eye = view->world_from_camera.translation();
  std::vector<Light> lights(size_t(rng.UniformInt(1, options.max_lights)));
  for (Light& l : lights)
    l = {Vec3(eye.x() + rng.Uniform(-3, 3), eye.y() + rng.Uniform(-3, 3), options.floor_z_m + rng.Uniform(1.9, 2.7)),
         rng.Uniform(0.4, 1.4)};
  const double ambient = rng.Uniform(0.25, 0.65);
  const double occlusion = rng.Uniform(0.0, 0.35);
  const double exposure = rng.Uniform(options.exposure_min, options.exposure_max);
  const Vec3 balance(rng.Uniform(1 - options.white_balance, 1 + options.white_balance),
                     rng.Uniform(1 - options.white_balance, 1 + options.white_balance),
                     rng.Uniform(1 - options.white_balance, 1 + options.white_balance));
  const double gamma = rng.Uniform(0.8, 1.25);
  const double blur = rng.Uniform(0, options.max_blur_sigma_px);
  const double noise = rng.Uniform(0, options.max_colour_noise) / 255.0;
  const double depth_noise_scale = rng.Uniform(0, 1);
  const bool quantise = rng.Bernoulli(0.5);

  std::unordered_map<int32_t, SurfaceLook> looks;
  ImageF32 colour(w, h, 3, 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float d = view->depth.at(x, y);
      if (!options.repaint_surfaces) {
        // Camera effects only: the view's own colours as albedo x 1.
        for (int ch = 0; ch < 3; ++ch)
          colour.at(x, y, ch) = float(std::pow(std::clamp(view->rgb.at(x, y, ch) / 255.0 * balance[ch] * exposure, 0.0, 1.0), 1.0 / gamma));
        continue;
      }
      const int32_t s = surface.at(x, y);
      if (!(d > 0) || s < 0) continue;
      auto it = looks.find(s);
      if (it == looks.end()) {
        const Vec3 own(view->rgb.at(x, y, 0) / 255.0, view->rgb.at(x, y, 1) / 255.0, view->rgb.at(x, y, 2) / 255.0);
        it = looks.emplace(s, DrawLook(scene_seed, s, own, options)).first;
      }
      const Vec3 p = view->world_from_camera * (view->camera.PixelRay(x, y) * double(d));
      const Vec3 n(view->normal.at(x, y, 0), view->normal.at(x, y, 1), view->normal.at(x, y, 2));
      const double shade = Shade(p, n, lights, ambient, occlusion, options.floor_z_m, /*two_sided=*/false);
      const Vec3 c = (Textured(it->second, p, n).array() * balance.array()).matrix() * shade * exposure;
      for (int ch = 0; ch < 3; ++ch) colour.at(x, y, ch) = float(std::pow(std::clamp(c[ch], 0.0, 1.0), 1.0 / gamma));
    }
  if (blur > 0.3) GaussianBlur(&colour, blur);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!(view->depth.at(x, y) > 0)) continue;
      const double lum = rng.Normal(0, noise);
      for (int ch = 0; ch < 3; ++ch) {
        const double v = colour.at(x, y, ch) + lum + rng.Normal(0, 0.5 * noise);
        view->rgb.at(x, y, ch) = uint8_t(std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
      }
    }
  // Depth: flying pixels at edges (from the clean depth), then axial noise and disparity quantisation.
  const ImageF32 clean = view->depth;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float d = clean.at(x, y);
      if (!(d > 0)) continue;
      if (options.flying_pixel_probability > 0) {
        const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
        for (int k = 0; k < 4; ++k) {
          if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
          const float e = clean.at(nx[k], ny[k]);
          if (e > d + 0.1f && rng.Bernoulli(options.flying_pixel_probability)) {
            d += float(rng.Uniform(0.2, 0.8)) * (e - d);
            break;
          }
        }
      }
      d += float(rng.Normal(0, depth_noise_scale * (options.depth_noise_sigma_m + options.depth_noise_quadratic * d * d)));
      const double step = options.depth_quantisation * d * d;
      if (quantise && step > 1e-6) d = float(std::round(d / step) * step);
      view->depth.at(x, y) = std::max(d, 0.01f);
    }
  return Status::Ok();
}

void RepaintScan(const std::vector<Eigen::Vector3f>& positions, const std::vector<Eigen::Vector3f>& normals,
                 const std::vector<int32_t>& surface, const std::vector<Eigen::Vector3d>& lights, uint64_t scene_seed,
                 const ViewAugmentationOptions& options, std::vector<Rgb8>* colours) {
  std::unordered_map<int32_t, SurfaceLook> looks;
  Rng rng(SplitMix64(scene_seed ^ 0x3c6ef372fe94f82bULL));
  const double ambient = rng.Uniform(0.3, 0.6), occlusion = rng.Uniform(0.0, 0.35);
  std::vector<Light> lit(lights.size());
  for (size_t l = 0; l < lights.size(); ++l) lit[l] = {lights[l], rng.Uniform(0.5, 1.3)};
  for (size_t i = 0; i < positions.size() && i < surface.size() && i < colours->size(); ++i) {
    const int32_t s = surface[i];
    if (s < 0) continue;
    auto it = looks.find(s);
    Rgb8& c8 = (*colours)[i];
    if (it == looks.end()) it = looks.emplace(s, DrawLook(scene_seed, s, Vec3(c8.r, c8.g, c8.b) / 255.0, options)).first;
    const Vec3 p = positions[i].cast<double>();
    const Vec3 n = i < normals.size() ? Vec3(normals[i].cast<double>()) : Vec3(Vec3::Zero());
    // Unoriented normals (clouds): light from either side.
    const Vec3 c = Textured(it->second, p, n) * Shade(p, n, lit, ambient, occlusion, options.floor_z_m, /*two_sided=*/true);
    c8 = Rgb8{uint8_t(std::lround(255 * std::clamp(c.x(), 0.0, 1.0))), uint8_t(std::lround(255 * std::clamp(c.y(), 0.0, 1.0))),
              uint8_t(std::lround(255 * std::clamp(c.z(), 0.0, 1.0)))};
  }
}

}  // namespace semvox
