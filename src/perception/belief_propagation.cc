#include "perception/belief_propagation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace semvox {
namespace {

constexpr double kNegInf = -std::numeric_limits<double>::infinity();

double LogSumExp(std::span<const double> v) {
  double mx = kNegInf;
  for (double x : v) mx = std::max(mx, x);
  if (mx == kNegInf) return kNegInf;
  double s = 0;
  for (double x : v) s += std::exp(x - mx);
  return mx + std::log(s);
}

// Pairwise log potential of edge e with `from` at label a and the other end at label b.
inline double EdgeLog(const PairwiseModel::Edge& e, int from, int a, int b, int m) {
  return from == e.i ? e.log_pairwise[size_t(a) * size_t(m) + size_t(b)] : e.log_pairwise[size_t(b) * size_t(m) + size_t(a)];
}

struct Incidence {
  int edge;
  int other;
};

std::vector<std::vector<Incidence>> BuildIncidence(const PairwiseModel& model) {
  std::vector<std::vector<Incidence>> inc(static_cast<size_t>(model.num_nodes()));
  for (int e = 0; e < int(model.edges.size()); ++e) {
    inc[size_t(model.edges[size_t(e)].i)].push_back({e, model.edges[size_t(e)].j});
    inc[size_t(model.edges[size_t(e)].j)].push_back({e, model.edges[size_t(e)].i});
  }
  return inc;
}

// Rooted traversal of a forest: nodes in BFS order with their parent and the edge to it.
struct Forest {
  std::vector<int> order, parent, parent_edge;
};

Status BuildForest(const PairwiseModel& model, const std::vector<std::vector<Incidence>>& inc, Forest* f) {
  const int n = model.num_nodes();
  f->order.clear();
  f->parent.assign(size_t(n), -2);  // -2 unvisited, -1 root.
  f->parent_edge.assign(size_t(n), -1);
  for (int root = 0; root < n; ++root) {
    if (f->parent[size_t(root)] != -2) continue;
    f->parent[size_t(root)] = -1;
    size_t head = f->order.size();
    f->order.push_back(root);
    while (head < f->order.size()) {
      const int u = f->order[head++];
      for (const Incidence& in : inc[size_t(u)]) {
        if (in.edge == f->parent_edge[size_t(u)]) continue;
        if (f->parent[size_t(in.other)] != -2)
          return Status::InvalidInput("tree inference: the graph has a cycle through edge " + std::to_string(in.edge) +
                                      " (" + std::to_string(model.edges[size_t(in.edge)].i) + ", " +
                                      std::to_string(model.edges[size_t(in.edge)].j) + "); use loopy BP");
        f->parent[size_t(in.other)] = u;
        f->parent_edge[size_t(in.other)] = in.edge;
        f->order.push_back(in.other);
      }
    }
  }
  return Status::Ok();
}

Status Validate(const PairwiseModel& model) {
  std::string error;
  if (!model.Check(&error)) return Status::InvalidInput("pairwise model: " + error);
  return Status::Ok();
}

}  // namespace

bool PairwiseModel::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (num_labels < 1) return fail("num_labels = " + std::to_string(num_labels) + ". Violated constraint: num_labels >= 1");
  if (log_unary.size() % size_t(num_labels) != 0)
    return fail("log_unary has " + std::to_string(log_unary.size()) + " values, not a multiple of num_labels");
  for (double v : log_unary)
    if (!std::isfinite(v)) return fail("log_unary holds a non-finite value (floor the probabilities first)");
  const int n = num_nodes();
  for (size_t e = 0; e < edges.size(); ++e) {
    const Edge& ed = edges[e];
    if (ed.i < 0 || ed.j < 0 || ed.i >= n || ed.j >= n || ed.i == ed.j)
      return fail("edge " + std::to_string(e) + " = (" + std::to_string(ed.i) + ", " + std::to_string(ed.j) +
                  "). Violated constraint: distinct nodes in [0, " + std::to_string(n) + ")");
    if (ed.log_pairwise.size() != size_t(num_labels) * size_t(num_labels))
      return fail("edge " + std::to_string(e) + " has " + std::to_string(ed.log_pairwise.size()) +
                  " pairwise values, expected num_labels^2 = " + std::to_string(num_labels * num_labels));
    for (double v : ed.log_pairwise)
      if (!std::isfinite(v)) return fail("edge " + std::to_string(e) + " log_pairwise holds a non-finite value");
  }
  return true;
}

double PairwiseModel::LogScore(std::span<const int> labels) const {
  const size_t m = size_t(num_labels);
  double s = 0;
  for (size_t i = 0; i < labels.size(); ++i) s += log_unary[i * m + size_t(labels[i])];
  for (const Edge& e : edges) s += e.log_pairwise[size_t(labels[size_t(e.i)]) * m + size_t(labels[size_t(e.j)])];
  return s;
}

bool LoopyBpOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (max_iterations < 1) return fail("max_iterations = " + std::to_string(max_iterations) + ". Violated constraint: max_iterations >= 1");
  if (!(damping >= 0 && damping < 1)) return fail("damping = " + std::to_string(damping) + ". Violated constraint: 0 <= damping < 1");
  if (!(tolerance > 0)) return fail("tolerance = " + std::to_string(tolerance) + ". Violated constraint: tolerance > 0");
  return true;
}

Status TreeSumProduct(const PairwiseModel& model, Marginals* marginals) {
  SEMVOX_RETURN_IF_ERROR(Validate(model));
  const int n = model.num_nodes(), m = model.num_labels;
  const auto inc = BuildIncidence(model);
  Forest f;
  SEMVOX_RETURN_IF_ERROR(BuildForest(model, inc, &f));
  // up[v]: log message from v to its parent (over the parent's labels), unnormalised so that the roots
  // collect log Z. down[v]: log message from the parent to v (over v's labels), normalised.
  std::vector<double> up(size_t(n) * size_t(m), 0.0), down(size_t(n) * size_t(m), 0.0);
  // inward[v] = log phi_v + sum of up-messages of v's children.
  std::vector<double> inward(model.log_unary);
  std::vector<double> term(static_cast<size_t>(m));
  for (auto it = f.order.rbegin(); it != f.order.rend(); ++it) {
    const int v = *it, p = f.parent[size_t(v)];
    if (p < 0) continue;
    const PairwiseModel::Edge& e = model.edges[size_t(f.parent_edge[size_t(v)])];
    for (int b = 0; b < m; ++b) {
      for (int a = 0; a < m; ++a) term[size_t(a)] = inward[size_t(v) * m + a] + EdgeLog(e, v, a, b, m);
      up[size_t(v) * m + b] = LogSumExp(term);
    }
    for (int b = 0; b < m; ++b) inward[size_t(p) * m + b] += up[size_t(v) * m + b];
  }
  marginals->num_labels = m;
  marginals->p.assign(size_t(n) * size_t(m), 0.0);
  marginals->log_partition = 0;
  for (int v : f.order) {
    const int p = f.parent[size_t(v)];
    if (p < 0) {
      marginals->log_partition += LogSumExp({&inward[size_t(v) * m], size_t(m)});
    } else {
      // Parent's belief without v's own up-message, sent down the edge.
      const PairwiseModel::Edge& e = model.edges[size_t(f.parent_edge[size_t(v)])];
      for (int b = 0; b < m; ++b) {
        for (int a = 0; a < m; ++a)
          term[size_t(a)] = inward[size_t(p) * m + a] - up[size_t(v) * m + a] + down[size_t(p) * m + a] + EdgeLog(e, p, a, b, m);
        down[size_t(v) * m + b] = LogSumExp(term);
      }
      const double z = LogSumExp({&down[size_t(v) * m], size_t(m)});
      for (int b = 0; b < m; ++b) down[size_t(v) * m + b] -= z;
    }
    // Belief of v: inward (unary + children) plus the message from its parent.
    for (int a = 0; a < m; ++a) term[size_t(a)] = inward[size_t(v) * m + a] + down[size_t(v) * m + a];
    const double z = LogSumExp(term);
    for (int a = 0; a < m; ++a) marginals->p[size_t(v) * m + a] = std::exp(term[size_t(a)] - z);
  }
  return Status::Ok();
}

Status TreeMaxProduct(const PairwiseModel& model, std::vector<int>* labels) {
  SEMVOX_RETURN_IF_ERROR(Validate(model));
  const int n = model.num_nodes(), m = model.num_labels;
  const auto inc = BuildIncidence(model);
  Forest f;
  SEMVOX_RETURN_IF_ERROR(BuildForest(model, inc, &f));
  std::vector<double> inward(model.log_unary);
  // best_child_label[v * m + b]: v's best label given its parent takes label b.
  std::vector<int> best_child_label(size_t(n) * size_t(m), 0);
  for (auto it = f.order.rbegin(); it != f.order.rend(); ++it) {
    const int v = *it, p = f.parent[size_t(v)];
    if (p < 0) continue;
    const PairwiseModel::Edge& e = model.edges[size_t(f.parent_edge[size_t(v)])];
    for (int b = 0; b < m; ++b) {
      double best = kNegInf;
      int arg = 0;
      for (int a = 0; a < m; ++a) {
        const double s = inward[size_t(v) * m + a] + EdgeLog(e, v, a, b, m);
        if (s > best) {
          best = s;
          arg = a;
        }
      }
      best_child_label[size_t(v) * m + b] = arg;
      inward[size_t(p) * m + b] += best;
    }
  }
  labels->assign(size_t(n), 0);
  for (int v : f.order) {
    const int p = f.parent[size_t(v)];
    if (p >= 0) {
      (*labels)[size_t(v)] = best_child_label[size_t(v) * m + (*labels)[size_t(p)]];
      continue;
    }
    const double* row = &inward[size_t(v) * m];
    (*labels)[size_t(v)] = int(std::max_element(row, row + m) - row);
  }
  return Status::Ok();
}

Status LoopyBeliefPropagation(const PairwiseModel& model, const LoopyBpOptions& options, Marginals* marginals,
                              LoopyBpSummary* summary) {
  SEMVOX_RETURN_IF_ERROR(Validate(model));
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("loopy BP: " + error);
  const int n = model.num_nodes(), m = model.num_labels;
  const size_t num_edges = model.edges.size();
  const auto inc = BuildIncidence(model);
  // msg[(2e + dir) * m + label]: dir 0 is i -> j (over j's labels), dir 1 is j -> i. Normalised logs.
  std::vector<double> msg(2 * num_edges * size_t(m), -std::log(double(m))), next(msg.size());
  std::vector<double> belief(size_t(n) * size_t(m)), term(static_cast<size_t>(m));
  auto compute_beliefs = [&](const std::vector<double>& messages) {
    belief = model.log_unary;
    for (size_t e = 0; e < num_edges; ++e) {
      const auto& ed = model.edges[e];
      for (int a = 0; a < m; ++a) {
        belief[size_t(ed.j) * m + a] += messages[(2 * e) * m + a];
        belief[size_t(ed.i) * m + a] += messages[(2 * e + 1) * m + a];
      }
    }
  };
  // Potts edges (one log potential on the diagonal, one off it, as the view CRFs build them) take the
  // O(m) message sum_a exp(t_a + P(a, b)) = exp(off) (S - u_b) + exp(diag) u_b with u_a = exp(t_a), S = sum u;
  // other edges the general O(m^2) sum.
  std::vector<std::array<double, 2>> potts(num_edges, {0.0, 0.0});  // exp(diag), exp(off); {0, 0}: not Potts.
  for (size_t e = 0; e < num_edges; ++e) {
    const std::vector<double>& lp = model.edges[e].log_pairwise;
    const double diag = lp[0], off = m > 1 ? lp[1] : lp[0];
    bool is_potts = true;
    for (int a = 0; a < m && is_potts; ++a)
      for (int b = 0; b < m && is_potts; ++b) is_potts = lp[size_t(a) * m + size_t(b)] == (a == b ? diag : off);
    if (is_potts && std::exp(diag) > 0 && std::exp(off) > 0) potts[e] = {std::exp(diag), std::exp(off)};
  }
  std::vector<double> u(static_cast<size_t>(m));
  LoopyBpSummary local;
  for (int it = 0; it < options.max_iterations; ++it) {
    compute_beliefs(msg);
    double change = 0;
    for (size_t e = 0; e < num_edges; ++e) {
      const auto& ed = model.edges[e];
      for (int dir = 0; dir < 2; ++dir) {
        const int from = dir == 0 ? ed.i : ed.j;
        const size_t reverse = (2 * e + (1 - dir)) * m;  // Message into `from` along this edge.
        double* out = &next[(2 * e + dir) * m];
        double z;
        double mx = kNegInf;
        if (potts[e][0] > 0)
          for (int a = 0; a < m; ++a) {
            term[size_t(a)] = belief[size_t(from) * m + a] - msg[reverse + a];
            mx = std::max(mx, term[size_t(a)]);
          }
        if (potts[e][0] > 0 && std::isfinite(mx)) {
          double sum = 0;
          for (int a = 0; a < m; ++a) sum += u[size_t(a)] = std::exp(term[size_t(a)] - mx);
          const double same = potts[e][0], other = potts[e][1];
          for (int b = 0; b < m; ++b) out[b] = mx + std::log(other * (sum - u[size_t(b)]) + same * u[size_t(b)]);
          // sum_b of the messages' exponentials, without m more exps.
          z = mx + std::log(sum * (other * double(m - 1) + same));
        } else {
          for (int b = 0; b < m; ++b) {
            for (int a = 0; a < m; ++a)
              term[size_t(a)] = belief[size_t(from) * m + a] - msg[reverse + a] + EdgeLog(ed, from, a, b, m);
            out[b] = LogSumExp(term);
          }
          z = LogSumExp({out, size_t(m)});
        }
        for (int b = 0; b < m; ++b) {
          double v = out[b] - z;
          const double old = msg[(2 * e + dir) * m + b];
          if (options.damping > 0 && std::isfinite(old) && std::isfinite(v)) v = (1 - options.damping) * v + options.damping * old;
          out[b] = v;
          if (std::isfinite(v) || std::isfinite(old)) change = std::max(change, std::abs(v - old));
        }
      }
    }
    msg.swap(next);
    local.iterations = it + 1;
    local.max_message_change = change;
    if (change <= options.tolerance) {
      local.converged = true;
      break;
    }
  }
  compute_beliefs(msg);
  marginals->num_labels = m;
  marginals->p.assign(size_t(n) * size_t(m), 0.0);
  marginals->log_partition = std::numeric_limits<double>::quiet_NaN();
  for (int v = 0; v < n; ++v) {
    const double z = LogSumExp({&belief[size_t(v) * m], size_t(m)});
    for (int a = 0; a < m; ++a) marginals->p[size_t(v) * m + a] = std::exp(belief[size_t(v) * m + a] - z);
  }
  if (summary) *summary = local;
  return Status::Ok();
}

std::vector<int> DecodeMaxMarginals(const Marginals& marginals) {
  const int m = marginals.num_labels;
  const size_t n = m > 0 ? marginals.p.size() / size_t(m) : 0;
  std::vector<int> labels(n, 0);
  for (size_t v = 0; v < n; ++v) {
    const double* row = &marginals.p[v * size_t(m)];
    labels[v] = int(std::max_element(row, row + m) - row);
  }
  return labels;
}

}  // namespace semvox
