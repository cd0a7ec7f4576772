#include "crf/solvers.h"

#include <sstream>

namespace semvox {

bool AlphaExpansionOptions::Check(std::string* error) const {
  std::ostringstream os;
  if (max_sweeps <= 0) {
    os << "max_sweeps = " << max_sweeps << ". Violated constraint: max_sweeps > 0";
  } else if (!(consistency_tolerance > 0 && consistency_tolerance <= 1e-2)) {
    os << "consistency_tolerance = " << consistency_tolerance
       << ". Violated constraint: 0 < consistency_tolerance <= 1e-2";
  } else if (!(min_sweep_improvement >= 0 && min_sweep_improvement < 1)) {
    os << "min_sweep_improvement = " << min_sweep_improvement << ". Violated constraint: 0 <= min_sweep_improvement < 1";
  } else {
    return true;
  }
  if (error) *error = os.str();
  return false;
}

bool IcmOptions::Check(std::string* error) const {
  if (max_sweeps > 0) return true;
  if (error) *error = "max_sweeps = " + std::to_string(max_sweeps) + ". Violated constraint: max_sweeps > 0";
  return false;
}

std::string CrfSolverSummary::BriefReport() const {
  std::ostringstream os;
  os.precision(10);
  os << solver << ": E " << initial_energy << " -> " << final_energy << " in " << num_sweeps << " sweeps ("
     << (converged ? "converged" : "sweep limit") << "), " << num_moves << " moves";
  if (num_expansions > 0) {
    os << ", " << num_expansions << " max-flows (" << num_skipped_expansions << " skipped), max-flow "
       << max_flow_seconds << " s";
    if (num_pruned_nodes > 0) os << ", " << num_pruned_nodes << " node moves decided before the cut";
  }
  if (num_truncated_terms > 0) os << ", " << num_truncated_terms << " truncated terms";
  if (num_rejected_moves > 0) os << ", " << num_rejected_moves << " rejected moves";
  os << ", " << seconds << " s";
  return os.str();
}

Status InitializeLabels(const CrfEnergy& energy, InitialLabelling initial, std::vector<CrfLabel>* labels) {
  switch (initial) {
    case InitialLabelling::kUnaryArgmin:
      *labels = energy.UnaryArgmin();
      return Status::Ok();
    case InitialLabelling::kAllZero:
      labels->assign(energy.num_nodes(), 0);
      return Status::Ok();
    case InitialLabelling::kGiven:
      if (static_cast<int>(labels->size()) != energy.num_nodes()) {
        return Status::InvalidInput("initial labels: " + std::to_string(labels->size()) + " labels for " +
                                    std::to_string(energy.num_nodes()) + " nodes");
      }
      for (size_t i = 0; i < labels->size(); ++i) {
        if ((*labels)[i] < 0 || (*labels)[i] >= energy.num_labels()) {
          return Status::InvalidInput("initial labels: node " + std::to_string(i) + " has label " +
                                      std::to_string((*labels)[i]) + ", expected [0, " +
                                      std::to_string(energy.num_labels()) + ")");
        }
      }
      return Status::Ok();
  }
  return Status::Internal("unknown InitialLabelling");
}

}  // namespace semvox
