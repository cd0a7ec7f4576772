// Domain randomisation of rendered training views (library semvox_perception_train).
//
//   Image<int32_t> surface = ...;   // per pixel: which surface it shows (object instance, or wall/floor of a room)
//   AugmentView(surface, Hash(apartment, surface ids), view_seed, ViewAugmentationOptions{}, &view);
//
// Generated apartments give every object one flat colour, and several classes always the same one (TVs
// black, windows pale blue, ceilings white). A classifier trained on that learns the colours, not the
// rooms: on a real scan, whose colours carry texture, baked lighting and exposure, it fails. This module
// repaints a rendered view so that colour no longer identifies a class and looks like a fused RGB-D scan:
//   1. albedo: each surface gets, with `recolour_probability`, a colour from wide palettes (drawn from a
//      hash of the apartment and surface, so a surface keeps its colour in every view), else its own
//      colour jittered;
//   2. texture: a procedural pattern in world coordinates per surface (fabric noise, wood grain, tiles,
//      poster / book-spine bands, or none);
//   3. shading: ambient light plus a few point lights under the ceiling (Lambert, inverse-square falloff)
//      and a darkening near the floor (ambient occlusion);
//   4. camera: exposure and white-balance gains, gamma, Gaussian blur, colour noise, 8-bit quantisation;
//   5. depth: axial noise growing with distance, disparity quantisation and flying pixels at depth edges.
// Everything is drawn from the seeds given (deterministic). Labels, primitives and voxel keys are kept.
#pragma once

#include <cstdint>
#include <string>

#include "core/geometry.h"
#include "core/image.h"
#include "render/view_renderer.h"

namespace semvox {

struct ViewAugmentationOptions {
  double recolour_probability = 0.85;  // A surface's colour is replaced by a palette colour. [0, 1].
  double texture_probability = 0.75;   // A surface gets a procedural texture. [0, 1].
  double floor_z_m = 0.0;              // Floor height (ambient occlusion and light heights), metres.
  int max_lights = 3;                  // Point lights per view, drawn in [1, max]. >= 1.
  double exposure_min = 0.55;          // Exposure gain drawn in [min, max]. > 0.
  double exposure_max = 1.35;
  double white_balance = 0.15;         // Per-channel gain drawn in [1 - wb, 1 + wb]. [0, 1).
  double max_blur_sigma_px = 1.2;      // Gaussian blur sigma drawn in [0, max], pixels. >= 0.
  double max_colour_noise = 7.0;       // Colour noise sigma drawn in [0, max], 8-bit units. >= 0.
  double depth_noise_sigma_m = 0.0012;      // Axial depth noise at zero range (scaled per view by [0, 1]). >= 0.
  double depth_noise_quadratic = 0.0019;    // ... growth per m² of range. >= 0.
  double depth_quantisation = 0.0028;       // Disparity step: depth quantised to multiples of this * d². >= 0.
  double flying_pixel_probability = 0.5;    // A pixel at a depth edge (> 0.1 m jump) takes a mixed depth. [0, 1].
  // Steps 1-3 (albedo, texture, shading) in AugmentView; false keeps the view's colours (a scan already
  // repainted by RepaintScan) and applies only the camera and depth effects.
  bool repaint_surfaces = true;

  bool Check(std::string* error) const;
};

// Repaints `view` (rgb and depth) in place. `surface` (same size as the view, -1 where nothing is hit)
// names the surface each pixel shows; `scene_seed` fixes the surfaces' colours and textures (use the same
// value for every view of one scene); `view_seed` fixes lights, camera and noise of this view.
Status AugmentView(const Image<int32_t>& surface, uint64_t scene_seed, uint64_t view_seed,
                   const ViewAugmentationOptions& options, RenderedView* view);

// Repaints a scan in 3D, as a fused RGB-D scan bakes its colours: every element (cloud point or mesh
// vertex) at `positions` with unit `normals` (may be empty: no shading but ambient) showing surface
// `surface` (-1: left as is) gets its surface's look (albedo and texture, as AugmentView draws them for
// `scene_seed`) lit by point `lights` (world positions) with ambient light and floor occlusion. Elements
// keep their order; `colours` must have one entry per position.
void RepaintScan(const std::vector<Eigen::Vector3f>& positions, const std::vector<Eigen::Vector3f>& normals,
                 const std::vector<int32_t>& surface, const std::vector<Eigen::Vector3d>& lights, uint64_t scene_seed,
                 const ViewAugmentationOptions& options, std::vector<Rgb8>* colours);

}  // namespace semvox
