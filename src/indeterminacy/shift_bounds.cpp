#include "unjam/indeterminacy/shift_bounds.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

#include <ClpSimplex.hpp>

#include "ensemble_lp.hpp"
#include "unjam/parallel/for_each_index.hpp"

namespace unjam {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A contact with a fixed body opens when the shift moves P away from it by more than this
// fraction of ξ; a contact the shift slides along (ŝ ⟂ n) stays closed and keeps its law.
constexpr double kOpeningFraction = 1e-9;

// What one shift changes in the ensemble's LP.
struct ShiftLp {
  std::vector<std::pair<int, double>>
      objective;                       // F_crit = Σ c·f (columns in units of the force scale)
  std::vector<int> released_rows;      // P's balance
  std::vector<int> unloaded_contacts;  // opened contacts with fixed bodies
};

// Particles that balance (have rows) in the system.
std::vector<char> Balancing(const EquilibriumSystem& s) {
  int largest = -1;
  for (const Contact& c : s.contacts) largest = std::max({largest, c.i, c.WithWall() ? -1 : c.j});
  std::vector<char> out(largest + 1, 0);
  for (int p : s.row_particle) {
    if (p >= 0 && p < static_cast<int>(out.size())) out[p] = 1;
  }
  return out;
}

ShiftLp Describe(const EquilibriumSystem& s, const std::vector<char>& balancing,
                 const ShiftTarget& t) {
  ShiftLp lp;
  for (int r = 0; r < s.NumRows(); ++r) {
    if (s.row_particle[r] == t.particle) lp.released_rows.push_back(r);
  }
  const int stride = s.UnknownsPerContact();
  for (int k = 0; k < static_cast<int>(s.contacts.size()); ++k) {
    const Contact& c = s.contacts[k];
    const bool p_is_i = c.i == t.particle;
    if (!p_is_i && (c.WithWall() || c.j != t.particle)) continue;
    // The force on P is −(f_n n + f_t t) when P is i and +(f_n n + f_t t) when P is j, and
    // F_crit = −ŝ·(force on P).
    const double sign = p_is_i ? 1.0 : -1.0;
    lp.objective.emplace_back(stride * k, sign * t.direction.dot(c.normal));
    if (s.frictional)
      lp.objective.emplace_back(stride * k + 1, sign * t.direction.dot(Perp(c.normal)));
    const int other = p_is_i ? c.j : c.i;
    const bool other_fixed = (p_is_i && c.WithWall()) ||
                             other >= static_cast<int>(balancing.size()) || !balancing[other];
    // The gap grows at (v_j − v_i)·n, P moving along ŝ and the fixed body at rest.
    const double opening = (p_is_i ? -1.0 : 1.0) * t.direction.dot(c.normal);
    if (other_fixed && opening > kOpeningFraction) lp.unloaded_contacts.push_back(k);
  }
  return lp;
}

double ReferenceValue(const ShiftLp& lp, const Eigen::VectorXd& reference) {
  if (reference.size() == 0) return 0.0;
  double sum = 0.0;
  for (auto [column, c] : lp.objective) sum += c * reference[column];
  return sum;
}

// A shift's LP is never infeasible: the static network with the opened contacts' forces
// removed still balances every grain but P, whose balance is released. CLP's dual simplex
// from the slack basis (Simplex's confirmation) has reported one infeasible all the same
// (a bottom shift of the μ = 1 pile whose min is unbounded), so such an outcome is
// checked once more by the primal simplex from the slack basis, which finds its feasible
// point first.
Bound Optimise(ClpSimplex& model, const ShiftLp& lp, double sign, bool warm, double scale,
               long long& iterations) {
  for (auto [column, c] : lp.objective) model.setObjectiveCoefficient(column, sign * c);
  if (!warm) model.allSlackBasis(true);
  indeterminacy_internal::Simplex(model, false, 0, true, iterations);
  if (model.isProvenPrimalInfeasible()) {
    model.allSlackBasis(true);
    model.primal();
    iterations += model.numberIterations();
  }
  return indeterminacy_internal::Outcome(model, sign, scale);
}

// The min and max of one shift, into b.
void BoundShift(const ClpSimplex& base, const EquilibriumSystem& s, const ShiftLp& lp,
                const BoundsOptions& o, ShiftBounds& b, long long& iterations) {
  ClpSimplex model(base);  // the unperturbed ensemble's optimal basis: the warm start
  for (int r : lp.released_rows) model.setRowBounds(r, -kInfinity, kInfinity);
  const int stride = s.UnknownsPerContact();
  for (int k : lp.unloaded_contacts) {
    for (int a = 0; a < stride; ++a) model.setColumnBounds(stride * k + a, 0.0, 0.0);
  }
  b.max = Optimise(model, lp, -1.0, o.warm_start, s.force_scale, iterations);
  b.min = Optimise(model, lp, 1.0, o.warm_start, s.force_scale, iterations);
}

}  // namespace

ShiftBoundsReport ComputeShiftBounds(const EquilibriumSystem& system,
                                     const std::vector<ShiftTarget>& shifts,
                                     const Eigen::VectorXd& reference,
                                     const BoundsOptions& options) {
  if (options.lp != LpBackend::kClp)
    throw std::invalid_argument("shift bounds are computed with CLP only");
  const auto start = std::chrono::steady_clock::now();
  ShiftBoundsReport report;
  std::unique_ptr<ClpSimplex> base =
      indeterminacy_internal::EnsembleModel(system, options.lp_tolerance);
  indeterminacy_internal::Simplex(*base, false, 0, true, report.lp_iterations);
  report.feasible = base->isProvenOptimal();
  report.bounds.resize(shifts.size());
  const std::vector<char> balancing = Balancing(system);
  std::vector<ShiftLp> lps;
  for (std::size_t a = 0; a < shifts.size(); ++a) {
    lps.push_back(Describe(system, balancing, shifts[a]));
    report.bounds[a].target = shifts[a];
    report.bounds[a].reference = ReferenceValue(lps[a], reference);
    report.bounds[a].unloaded_contacts = static_cast<int>(lps[a].unloaded_contacts.size());
  }
  if (!report.feasible) {
    report.message =
        base->isProvenPrimalInfeasible()
            ? "no admissible force network: the packing is not static within the gap tolerance"
            : "CLP stopped with status " + std::to_string(base->status());
    for (ShiftBounds& b : report.bounds) b.min.status = b.max.status = BoundStatus::kInfeasible;
  } else {
    const int blocks = std::max(1, std::min<int>(options.threads, static_cast<int>(shifts.size())));
    std::vector<long long> iterations(blocks, 0);
    auto run_block = [&](int block) {
      // Each thread copies the shared model once, as the contact bounds do, and every
      // shift of its block starts from that private copy: no two threads read one model.
      const ClpSimplex own(*base);
      for (std::size_t a = shifts.size() * block / blocks; a < shifts.size() * (block + 1) / blocks;
           ++a) {
        BoundShift(own, system, lps[a], options, report.bounds[a], iterations[block]);
      }
    };
    parallel::ForEachIndex(blocks, parallel::OnThreads(blocks), run_block);  // a thread each
    for (long long i : iterations) report.lp_iterations += i;
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace unjam
