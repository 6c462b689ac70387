// The admissible force network nearest to a given one: a static certificate.
//
// Given forces f⁰ that nearly balance a packing (the last quench step of a packing run, or
// forces read from a file), find forces f with A f = b exactly (to round-off), f_n ≥ 0 and
// |f_t| ≤ μ f_n (equilibrium_system.hpp). If they exist, the packing is static: one
// contact-dynamics step from rest leaves every particle at rest, and f are its forces.
//
// Two stages:
//  1. Projection: keep every contact in its region of the cone (no force, inside, on the
//     edge ± with f_t = ±μ f_n) and take the least-squares correction of smallest norm,
//     Δ = Bᵀ (B Bᵀ)⁻¹ (b − A f⁰) with B = A restricted to the region's directions (sparse
//     Cholesky, CHOLMOD; two steps of iterative refinement). It succeeds when f⁰ is close
//     and the regions are right, which is the common case: cost of one factorisation.
//  2. Linear program: the admissible forces nearest to f⁰ in the L1 norm (COIN-OR CLP,
//     dual simplex). Exact and robust to degeneracy; it also proves infeasibility. Its
//     solution is polished by stage 1 with the regions it found.
// Hyperstatic (frictional) packings have many admissible networks; the nearest one to f⁰
// keeps the path-dependent forces of the dynamics.
#pragma once

#include <string>

#include <Eigen/Core>

#include "unjam/indeterminacy/equilibrium_system.hpp"

namespace unjam {

enum class AdmissibleStatus { kAdmissible, kInfeasible, kFailed };
const char* ToString(AdmissibleStatus status);

// kAuto: projection, then the linear program if it fails; or one stage only.
enum class AdmissibleMethod { kAuto, kProjection, kLinearProgram };

struct AdmissibleOptions {
  // Largest |A f − b| accepted, relative to the system's force scale.
  double balance_tolerance = 1e-12;
  // A reference force with |f_t| ≥ μ f_n (1 − edge_tolerance) is taken to be on the edge.
  double edge_tolerance = 1e-9;
  AdmissibleMethod method = AdmissibleMethod::kAuto;
};

struct AdmissibleForces {
  AdmissibleStatus status = AdmissibleStatus::kFailed;
  Eigen::VectorXd forces;         // the system's unknowns
  double balance_residual = 0.0;  // max |A f − b| / force scale
  std::string method;             // "projection", "linear-program", or "" if none found
  std::string message;
  double seconds = 0.0;
};

AdmissibleForces NearestAdmissibleForces(const EquilibriumSystem& system,
                                         const Eigen::VectorXd& reference,
                                         const AdmissibleOptions& options = {});

// max |A f − b| / force scale.
double BalanceResidual(const EquilibriumSystem& system, const Eigen::VectorXd& forces);

}  // namespace unjam
