// Perturbations decided before their step is solved: blocked (no motion obeys the step's
// non-penetration) or dynamic (no static network holds the packing: the rate solve's
// static LP).
#include <chrono>
#include <cmath>

#include "perturbation_internal.hpp"

namespace unjam {
namespace perturbation_internal {

// A perturbation decided before any solve: no force is measured (F_crit is NaN) and nothing
// moves. `decided_by` is reported as its backend, `why` as its message.
PerturbationResult DecidedWithoutSolving(const PerturbationBase& base,
                                         const std::string& decided_by, const std::string& why,
                                         PerturbationResult r, Clock::time_point start) {
  const std::size_t n = base.scene.particles.size();
  r.f_crit = std::nan("");
  r.displacement.assign(n, Vec2::Zero());
  r.rotation.assign(n, 0.0);
  r.solve.backend = decided_by;
  r.solve.message = why;
  r.quasi_static = false;
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}

PerturbationResult Blocked(const PerturbationBase& base, const std::string& decided_by,
                           const std::string& why, PerturbationResult r, Clock::time_point start) {
  r.solve.status = SolveStatus::kNumericalFailure;
  r.resolved = false;
  r.status = PerturbationStatus::kBlocked;
  return DecidedWithoutSolving(base, decided_by, why, std::move(r), start);
}

}  // namespace perturbation_internal
}  // namespace unjam
