#include "crf/alpha_expansion_impl.h"
#include "crf/max_flow.h"
#include "crf/solvers.h"

namespace semvox {

Status MinimizeWithAlphaExpansion(const CrfEnergy& energy, const AlphaExpansionOptions& options,
                                  std::vector<CrfLabel>* labels, CrfSolverSummary* summary,
                                  const std::vector<uint8_t>* movable) {
  MaxFlowGraph<double> graph;
  return crf_internal::RunAlphaExpansion(energy, options, graph, labels, summary, movable);
}

}  // namespace semvox
