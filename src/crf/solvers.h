// Minimisers of a CrfEnergy (crf/energy.h): alpha-expansion with graph cuts, and ICM as a baseline.
//
//   CrfEnergy energy(num_nodes, num_labels);  ... unaries, edges, Robust P^n cliques ...
//   AlphaExpansionOptions options;             // defaults: start from the unary arg-min
//   std::vector<CrfLabel> labels;
//   CrfSolverSummary summary;
//   Status st = MinimizeWithAlphaExpansion(energy, options, &labels, &summary);
//   SEMVOX_INFO(summary.BriefReport());
//
// Alpha-expansion (Boykov, Veksler & Zabih, PAMI 2001): for each label alpha in turn, the best
// "expansion move" (every node keeps its label or takes alpha) is found exactly by one s-t min cut
// (semvox's Boykov-Kolmogorov max-flow, crf/max_flow.h); sweeps over all labels repeat until no move
// lowers the energy. Pairwise terms become graph edges (Kolmogorov & Zabih, PAMI 2004); Robust P^n
// cliques add two auxiliary nodes each (crf/robust_pn.h). For metric pairwise models the result is within
// 2 max V / min V (times the Robust P^n factor) of the optimum; with two labels and submodular terms it
// is the exact minimum. Non-submodular move terms (non-metric models) are truncated (Rother et al.
// 2005) and a move that would raise the true energy is rejected, so the energy never rises.
// Every move's energy change is recomputed directly and checked against the cut value (the check aborts
// on a solver bug, never on input).
//
// Starting from the unary arg-min matters: the reference figures (100^3 Potts grid, Boost BK) show 93 s
// from an all-zero start against 8.3 s from the arg-min; on semvox's 640x480 benchmark the all-zero start
// costs 1.4x the time and ends in a worse local minimum (docs/crf.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/status.h"
#include "crf/energy.h"

namespace semvox {

enum class InitialLabelling {
  kUnaryArgmin,  // Per node the label of least unary cost.
  kGiven,        // The labels passed in (size N, every label in [0, L)).
  kAllZero,      // Label 0 everywhere (for comparisons only; slow).
};

struct AlphaExpansionOptions {
  InitialLabelling initial_labelling = InitialLabelling::kUnaryArgmin;
  int max_sweeps = 100;                 // Sweeps over all labels at most. > 0.
  bool randomize_label_order = false;   // Shuffle the label order in every sweep (else 0, 1, ..., L-1).
  uint64_t seed = 0;                    // Seed of the label shuffle.
  double consistency_tolerance = 1e-6;  // Relative tolerance of the check "cut value = energy change"
                                        // and of "energy never rises". In (0, 1e-2].
  bool log_expansions = false;          // One debug log line per expansion (energy, label, changes).
  double min_sweep_improvement = 0;     // Stop once a sweep lowers the energy by less than this fraction of
                                        // |E| (0: sweep until no expansion moves, the classical rule). [0, 1).
  bool prune_decided_nodes = true;      // Before each cut, fix the nodes whose move their own terms decide
                                        // (strict dominance: switching costs more than all arcs could pay
                                        // back, or the reverse); exact, and most nodes of a typical move.

  bool Check(std::string* error) const;
};

struct IcmOptions {
  InitialLabelling initial_labelling = InitialLabelling::kUnaryArgmin;
  int max_sweeps = 100;  // Sweeps over all nodes at most. > 0.

  bool Check(std::string* error) const;
};

struct CrfSolverSummary {
  std::string solver;                       // "alpha-expansion" or "icm".
  double initial_energy = 0;                // E of the initial labelling.
  double final_energy = 0;                  // E of the result.
  std::vector<double> energy_per_sweep;     // E after each sweep (exact re-evaluation).
  std::vector<double> energy_per_expansion; // Alpha-expansion: E after each expansion move performed.
  std::vector<CrfLabel> expansion_labels;   // ... and its alpha.
  int num_sweeps = 0;
  int64_t num_moves = 0;           // Expansions (or node updates, for ICM) that lowered the energy.
  int64_t num_expansions = 0;      // Max-flow problems solved.
  int64_t num_skipped_expansions = 0;  // Expansions skipped because nothing changed since alpha's last one.
  int64_t num_truncated_terms = 0;     // Non-submodular move terms truncated (0 for metric models).
  int64_t num_rejected_moves = 0;      // Moves rejected because the true energy would rise.
  int64_t num_pruned_nodes = 0;        // Node moves decided before the cut (summed over expansions).
  bool converged = false;          // A full sweep changed nothing.
  double seconds = 0;              // Wall time of the whole minimisation.
  double max_flow_seconds = 0;     // ... of which in max-flow.
  size_t graph_bytes = 0;          // Memory of the cut graph.

  std::string BriefReport() const;
};

// Minimises `energy` by alpha-expansion. On kGiven, *labels is the start. Returns InvalidInput for bad
// options, an energy that fails CrfEnergy::Check, bad given labels, or `movable` of the wrong size.
// With `movable` (one flag per node), only the flagged nodes may change label: the result minimises the
// energy over those with the others fixed, and each move is built over the edges that touch a flagged node
// (a local re-solve after a local change of the energy costs about the size of the change).
Status MinimizeWithAlphaExpansion(const CrfEnergy& energy, const AlphaExpansionOptions& options,
                                  std::vector<CrfLabel>* labels, CrfSolverSummary* summary,
                                  const std::vector<uint8_t>* movable = nullptr);

// Iterated conditional modes (Besag 1986): visit nodes in order, give each its best label with the others
// fixed (unary + incident edges + its cliques), until a sweep changes nothing. Monotone, weak.
Status MinimizeWithIcm(const CrfEnergy& energy, const IcmOptions& options, std::vector<CrfLabel>* labels,
                       CrfSolverSummary* summary);

// Fills *labels per `initial`; InvalidInput for bad kGiven labels.
Status InitializeLabels(const CrfEnergy& energy, InitialLabelling initial, std::vector<CrfLabel>* labels);

}  // namespace semvox
