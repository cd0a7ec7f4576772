// Scan artefacts: what a real scanned mesh has that the clean generated one does not.
//
//   Apartment --ApplyScanArtefacts--> Mesh (labels, instances and rooms kept per surviving face)
//
// Each artefact is configurable and can be turned off (0 / false): faces hidden inside or against other
// solids removed (nothing behind or under furniture, as a scanner never sees there), holes in surfaces,
// unscanned ceiling patches, random face dropout, vertex noise and low-frequency roughness. Noise and
// roughness are functions of the clean vertex position, so faces that shared a corner still do.
#pragma once

#include <cstdint>
#include <string>

#include "core/geometry.h"
#include "scenegen/apartment.h"

namespace semvox {

struct ScanArtefactOptions {
  uint64_t seed = 0;                       // Artefacts are drawn from this (the generator passes its own seed).
  bool remove_hidden = true;               // Drop faces wholly inside or against another solid (behind /
                                           // under furniture, furniture backs against walls, inside walls).
  double hidden_margin_m = 0.015;          // A face is hidden when its centroid is within this of another solid. >= 0.
  double holes_per_m2 = 0.03;              // Holes per m² of wall and floor surface. >= 0.
  double min_hole_radius_m = 0.15;         // Hole radius drawn in [min, max], metres. > 0.
  double max_hole_radius_m = 0.45;
  double unscanned_ceiling_fraction = 0.15;  // Fraction of the ceiling area left unscanned, in patches. [0, 1].
  double face_dropout = 0.0;               // Probability of losing any single face. [0, 1).
  double vertex_noise_m = 0.003;           // Standard deviation of per-vertex Gaussian noise, metres. >= 0.
  double roughness_m = 0.0;                // Amplitude of smooth surface undulation, metres. >= 0.
  double roughness_wavelength_m = 0.6;     // Its wavelength, metres. > 0.

  bool Check(std::string* error) const;
};

// The mesh of `apartment` as a scanner would deliver it. Unused vertices are dropped.
Mesh ApplyScanArtefacts(const Apartment& apartment, const ScanArtefactOptions& options);

}  // namespace semvox
