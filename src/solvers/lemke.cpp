// The exact 2D Signorini–Coulomb law as a mixed LCP, solved by Lemke's method
// (lemke_mlcp.hpp).
//
// In 2D the Coulomb cone is polyhedral, so the law of a time step is a linear
// complementarity problem (Stewart & Trinkle 1996; Anitescu & Potra 1997 show that
// Lemke's method solves it). Per unilateral frictional contact, with the posed velocity
// (ũ_n, u_t), r_t = a − b and a slip speed s:
//     ũ_n          ≥ 0  ⟂  r_n ≥ 0
//     u_t + s      ≥ 0  ⟂  a   ≥ 0
//    −u_t + s      ≥ 0  ⟂  b   ≥ 0
//     μ r_n − a − b ≥ 0  ⟂  s   ≥ 0
// Sticking: s = 0 and u_t = 0; sliding with u_t > 0: a = 0, b = μ r_n, s = u_t; this is
// exactly r_t = −μ r_n sign(u_t). A frictionless contact keeps the first pair only; a held
// (bilateral) contact has r_n = p − m with ũ_n ⟂ p and −ũ_n ⟂ m, i.e. ũ_n = 0, r_n free.
// The same law in a second form (ConeForm::kShiftedBox), three variables per contact:
// r_t = a − μ r_n with a ∈ [0, 2μ r_n],
//     u_t + σ      ≥ 0  ⟂  a ≥ 0
//     2μ r_n − a   ≥ 0  ⟂  σ ≥ 0
// (stick: 0 < a < 2μ r_n, σ = 0, u_t = 0; slide with u_t > 0: a = 0; with u_t < 0:
// a = 2μ r_n, σ = −u_t). In the first form a sticking contact has a or b at zero with its
// row u_t ± s also at zero: one degenerate basic variable per sticking contact, and a
// static packing is mostly sticking contacts. In this one a sticking contact is not
// degenerate, so fewer ties reach the floating-point lexicographic rule. Its matrix is
// not copositive, so Lemke's theory (a ray proves infeasibility) is lost: it is a
// fallback, run after the first form's paths have failed.
//
// The velocities stay free unknowns instead of being eliminated into W = H M⁻¹ Hᵀ:
//     v − M⁻¹Hᵀ r = v_free,   ũ = H v + offset,
// because W is dense under a pressure bath (the cell rate couples every contact) while H
// and M⁻¹ are sparse. A Delassus-form problem is the same with H = I, M⁻¹Hᵀ = W, v_free = q.
//
// What it gives: an exact solution (one basis, solved to round-off) whenever the method
// ends on one. The frictional law may have several solutions; Lemke's path picks one,
// the one reached from zero impulses by the covering-vector homotopy, which need not be
// the one nearest the warm start (the warm start is not used). A ray termination is
// reported as a numerical failure with its cause.
#include "lemke.hpp"
#include "deadline.hpp"
#include "lemke_mlcp.hpp"
#include "matrix_form.hpp"
#include "newton.hpp"
#include "splitmix64.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "unjam/solvers/residual.hpp"

namespace unjam {

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

using solvers_internal::MatrixForm;
using solvers_internal::MatrixFormOf;

// The complementarity form of a frictional contact's law (the table at the top).
enum class ConeForm { kSlipSpeed, kShiftedBox };

// The complementarity rows and variables of the contact laws (the table at the top).
struct Encoding {
  Triplets impulse;            // r = T z: (unknown, variable, coefficient)
  Triplets velocity;           // S: (row, unknown, coefficient), so that w = S ũ + E z
  Triplets coupling;           // E: (row, variable, coefficient)
  std::vector<char> cone_row;  // per row: 1 for μ r_n − a − b (an impulse), 0 for a velocity
  int variables = 0;
};

Encoding Encode(const MatrixForm& k, ConeForm form) {
  Encoding enc;
  for (int c = 0; c < static_cast<int>(k.laws.size()); ++c) {
    const int n = k.per_contact * c, t = n + 1, z = enc.variables;
    if (k.laws[c].kind == ConstraintKind::kBilateral) {
      enc.impulse.insert(enc.impulse.end(), {{n, z, 1.0}, {n, z + 1, -1.0}});
      enc.velocity.insert(enc.velocity.end(), {{z, n, 1.0}, {z + 1, n, -1.0}});
      enc.variables += 2;
      enc.cone_row.insert(enc.cone_row.end(), {0, 0});
    } else if (k.per_contact == 1 || k.laws[c].mu == 0.0) {
      enc.impulse.emplace_back(n, z, 1.0);
      enc.velocity.emplace_back(z, n, 1.0);
      enc.variables += 1;
      enc.cone_row.push_back(0);
    } else if (form == ConeForm::kShiftedBox) {  // variables r_n, a, σ at z … z+2
      const double mu = k.laws[c].mu;
      enc.impulse.insert(enc.impulse.end(), {{n, z, 1.0}, {t, z + 1, 1.0}, {t, z, -mu}});
      enc.velocity.insert(enc.velocity.end(), {{z, n, 1.0}, {z + 1, t, 1.0}});
      enc.coupling.insert(enc.coupling.end(),
                          {{z + 1, z + 2, 1.0}, {z + 2, z, 2.0 * mu}, {z + 2, z + 1, -1.0}});
      enc.variables += 3;
      enc.cone_row.insert(enc.cone_row.end(), {0, 0, 1});
    } else {  // variables r_n, a, b, s at z … z+3
      enc.impulse.insert(enc.impulse.end(), {{n, z, 1.0}, {t, z + 1, 1.0}, {t, z + 2, -1.0}});
      enc.velocity.insert(enc.velocity.end(), {{z, n, 1.0}, {z + 1, t, 1.0}, {z + 2, t, -1.0}});
      enc.coupling.insert(enc.coupling.end(), {{z + 1, z + 3, 1.0},
                                               {z + 2, z + 3, 1.0},
                                               {z + 3, z, k.laws[c].mu},
                                               {z + 3, z + 1, -1.0},
                                               {z + 3, z + 2, -1.0}});
      enc.variables += 4;
      enc.cone_row.insert(enc.cone_row.end(), {0, 0, 0, 1});
    }
  }
  return enc;
}

// The complementarity variables of contact c in the slip-speed form (Encode).
int SlipFormVariables(const MatrixForm& k, int c) {
  if (k.laws[c].kind == ConstraintKind::kBilateral) return 2;
  return k.per_contact == 1 || k.laws[c].mu == 0.0 ? 1 : 4;
}

// A basis per contact (SolverGuess::basis: bit k for the contact's k-th
// variable) as flags per variable of the slip-speed form, or empty if it does not fit.
std::vector<char> ExpandBasis(const MatrixForm& k, const std::vector<std::uint8_t>& per_contact,
                              int variables) {
  if (static_cast<int>(per_contact.size()) != k.NumContacts()) return {};
  std::vector<char> flags;
  flags.reserve(variables);
  for (int c = 0; c < k.NumContacts(); ++c) {
    for (int v = 0; v < SlipFormVariables(k, c); ++v) flags.push_back((per_contact[c] >> v) & 1);
  }
  return flags;
}

std::vector<std::uint8_t> CompressBasis(const MatrixForm& k, const std::vector<char>& flags) {
  std::vector<std::uint8_t> per_contact(k.NumContacts(), 0);
  int variable = 0;
  for (int c = 0; c < k.NumContacts(); ++c) {
    for (int v = 0; v < SlipFormVariables(k, c); ++v, ++variable) {
      if (flags[variable]) per_contact[c] |= static_cast<std::uint8_t>(1u << v);
    }
  }
  return per_contact;
}

// The slip-speed form's basis that an answer's stick/slide/open pattern implies, for an
// answer that is not one basis's solution (polished by Newton, or of the box form): per
// contact r_n basic if it carries force; a sliding contact (|u_t| above 1 % of the
// velocity scale, the accuracy the solve is asked for) holds s and the multiplier at the
// cone's edge, a sticking one the multiplier of r_t's sign, and s too if r_t is at the
// edge. Degenerate choices are guesses; a singular or infeasible basis is rejected where
// it is used.
std::vector<std::uint8_t> BasisOfPattern(const MatrixForm& k, const Eigen::VectorXd& r,
                                         double velocity_scale) {
  const Eigen::VectorXd u = k.h * (k.v_free + k.g * r) + k.offset;
  const double force_floor =
      1e-12 * std::max(r.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  std::vector<std::uint8_t> basis(k.NumContacts(), 0);
  for (int c = 0; c < k.NumContacts(); ++c) {
    const double rn = r[k.per_contact * c];
    if (k.laws[c].kind == ConstraintKind::kBilateral) {
      basis[c] = rn >= 0.0 ? 1 : 2;
      continue;
    }
    if (!(rn > force_floor)) continue;
    basis[c] = 1;
    if (SlipFormVariables(k, c) == 1) continue;
    const double rt = r[k.per_contact * c + 1], ut = u[k.per_contact * c + 1];
    const bool at_edge = std::abs(rt) >= k.laws[c].mu * rn * (1.0 - 1e-6);
    if (at_edge && std::abs(ut) > 1e-2 * velocity_scale && ut * rt < 0.0) {
      basis[c] |= ut > 0.0 ? (4 | 8) : (2 | 8);
      continue;
    }
    if (rt > 0.0) basis[c] |= 2;
    if (rt < 0.0) basis[c] |= 4;
    if (at_edge) basis[c] |= 8;
  }
  return basis;
}

// A pseudo-random number in [1, 2) from an index (splitmix64): the same perturbation on
// every run, thread and machine.
double GenericWeight(int index) {
  return 1.0 + static_cast<double>(
                   solvers_internal::SplitMix64Hash(static_cast<std::uint64_t>(index)) >> 11) *
                   0x1.0p-53;
}

// The generic right-hand side perturbation of a perturbed run (lemke_mlcp.hpp): every
// velocity row (w = ũ_n, ±u_t + s) is loosened by `size` × a weight in [1, 2) of the
// velocity scale: the caller's (ξ/Δt on a perturbation step), else the largest |offset|.
// The cone rows (μ r_n − a − b) are impulse rows and stay exact.
Eigen::VectorXd PerturbationOf(const MatrixForm& k, const Encoding& enc, const SolverOptions& o,
                               double size, double velocity_unit) {
  const double largest_offset = k.offset.size() > 0 ? k.offset.cwiseAbs().maxCoeff() : 0.0;
  const double scale = (o.lemke.velocity_scale > 0.0 ? o.lemke.velocity_scale
                        : largest_offset > 0.0       ? largest_offset
                                                     : 1.0) /
                       velocity_unit;
  Eigen::VectorXd perturbation = Eigen::VectorXd::Zero(enc.variables);
  for (int row = 0; row < enc.variables; ++row) {
    if (!enc.cone_row[row]) perturbation[row] = size * scale * GenericWeight(row);
  }
  return perturbation;
}

std::string Scientific(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1e", value);
  return text;
}

SparseMatrix FromTriplets(int rows, int cols, const Triplets& t) {
  SparseMatrix m(rows, cols);
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

SolveResult SolveWithNewton(const ContactProblem& p, const SolverOptions& o,
                            const SolverGuess& guess) {
  return NewtonSolver().Solve(p, o, guess);
}
SolveResult SolveWithNewton(const DelassusProblem& p, const SolverOptions& o,
                            const SolverGuess& guess) {
  return NewtonSolver().SolveDelassus(p, o, guess);
}

template <class Problem>
SolveResult Polish(const Problem& problem, const Eigen::VectorXd& impulses,
                   const SolverOptions& o) {
  return SolveWithNewton(problem, o, {impulses, {}});
}

// The mixed LCP of one complementarity form, and the map r = T z back to impulses.
struct Posed {
  Encoding enc;
  SparseMatrix t;
  lemke_internal::Mlcp mlcp;
  double velocity_unit = 1.0;  // the velocities' unit V (Pose): 1 in the step's own units
};

// `velocity_unit` V: the velocities (the free variables, the velocity rows and the slip
// speeds) in units of V, the impulses as they are (the rate form, see SolveLemke):
// x/V − (P/V) z = x0/V, and w/V on the velocity rows, whose coupling E to the slip speeds
// s/V is unchanged; the cone rows μ r_n − a − b are impulse rows and stay as they are.
Posed Pose(const MatrixForm& k, ConeForm form, double velocity_unit = 1.0) {
  Posed posed;
  posed.enc = Encode(k, form);
  const int unknowns = static_cast<int>(k.h.rows());
  posed.t = FromTriplets(unknowns, posed.enc.variables, posed.enc.impulse);
  const SparseMatrix s = FromTriplets(posed.enc.variables, unknowns, posed.enc.velocity);
  posed.mlcp.p = k.g * posed.t;
  posed.mlcp.x0 = k.v_free;
  posed.mlcp.d = s * k.h;
  posed.mlcp.e_matrix = FromTriplets(posed.enc.variables, posed.enc.variables, posed.enc.coupling);
  posed.mlcp.e = s * k.offset;
  posed.velocity_unit = velocity_unit;
  if (velocity_unit != 1.0) {
    posed.mlcp.p /= velocity_unit;
    posed.mlcp.x0 /= velocity_unit;
    posed.mlcp.e /= velocity_unit;  // only velocity rows carry an offset
  }
  return posed;
}

bool HasFriction(const MatrixForm& k) {
  if (k.per_contact == 1) return false;
  return std::any_of(k.laws.begin(), k.laws.end(), [](const ContactLaw& law) {
    return law.kind != ConstraintKind::kBilateral && law.mu > 0.0;
  });
}

// One run of Lemke's method: its path, form and tie tolerance.
struct Run {
  double tie;
  const char* name;
  double perturbation = 0.0;
  ConeForm form = ConeForm::kSlipSpeed;
  bool basis_only = false;  // the given basis solved as it is, no path
  bool rate = false;        // velocities in units of the velocity scale
};

// Runs tried in turn: the given basis (the answer at another gap), then paths from zero
// impulses, each with tie tolerances 1e-16, then 1e-14 and 1e-12 (lemke_mlcp.hpp); a
// path that ends on a ray, cycles or misses the tolerance is followed by the next run.
// Right after the first path from zero come paths from zero in the rate form (when the
// caller gives a velocity scale V, i.e. on a perturbation: ξ/Δt): the velocities, the
// velocity rows and the slip speeds in units of V, the impulses as they are (Pose). Its
// paths are other ones, since the covering vector is 1 in the new units: in the
// slip-speed form (ties 1e-16), in the box form (below), then in the slip-speed form
// with ties 1e-14. On tall piles they end where the paths in the step's own units
// cycle: on a 400-disk pile 24 diameters high, 13 of 17 top shifts and 6 of 17 bottom
// ones that no plain run solved exactly (the plain runs cycled at every tie tolerance,
// and the perturbed ones needed Newton's polish, which stalled); where both solve, the
// same answer. On the periodic μ = 0.1 packing the slip-speed form's rate paths do no
// better than the plain ones (4 of 10 openings alone), so they come after the first
// plain path, which keeps every answer it gave (docs/backends.md, "The rate form").
// Then come two perturbed runs (lemke_mlcp.hpp), of 1e-2 and then 1e-1 of the velocity
// scale (ξ/Δt for a perturbation): after the plain paths, so that an answer the plain
// paths reach is theirs, the end of the path from zero impulses. On the hyperstatic μ = 0.1
// packing the lexicographic order cannot be told in double precision: the impulses are
// O(1) and the network amplifies their round-off 10⁴–10⁵ times, so the velocities are
// known to about 1e-11, 1 % of ξ = 1e-9. With perturbations of 1e-3 ξ the four
// cycling openings tried still cycle, with 1e-2 ξ half of them, and with 1e-1 ξ none of
// five. The polished basis then misses the given problem by up to 3e-8 in the
// impulses, and Newton (newton.cpp) polishes the answer from there on the given
// problem. Only an answer within the tolerance is reported converged.
// Last, on frictional problems, the shifted-box form (top of the file): a path from zero
// and a perturbed one of 1e-2. Last, so that every answer of the first form stays
// as it was. Of the 21 openings of the μ = 0.1 sample that the first form left
// unresolved, the box form's path from zero solved 17 exactly, and its perturbed run
// with the polish the other 4 (docs/perturbations.md).
// Each run is bounded by 20 pivots per complementarity row and by the caller's
// lemke.max_pivots overall. Solving paths took up to 3.4 pivots per row on the periodic
// N = 500 packing and 7.5 on the N = 100 pile (whose gravity load every contact must
// take up from zero); the earlier bound of 3 cut 6 of the pile's 10 top shifts short.
// Runs in the rate form get 200 per row: on the first 6 top shifts of the 1600-disk pile
// (gravity-n1600-mu0.1) its box-form path from zero solved the step after 77–108 pivots
// per row, where 20 stopped it; the bound of 100 that came first left 2 of the 6
// unresolved, at 101 and 108 (--max-iter must allow it: the default 100 000 pivots do
// not). A user may set another bound for every run (SolverOptions::lemke.pivots_per_row,
// --lemke-row-pivots).
// A cycling path is stopped by the cycle check (lemke_mlcp.hpp), not by this bound.
// The rate form is the slip-speed form itself when no velocity scale is given (rate_form
// false).
std::vector<Run> PlanRuns(bool given_basis, bool rate_form, bool frictional) {
  std::vector<Run> runs;
  if (given_basis) runs.push_back({0.0, "none", 0.0, ConeForm::kSlipSpeed, true});
  runs.push_back({1e-16, "1e-16"});
  if (rate_form) {
    runs.push_back({1e-16, "1e-16", 0.0, ConeForm::kSlipSpeed, false, true});
    if (frictional) runs.push_back({1e-16, "1e-16", 0.0, ConeForm::kShiftedBox, false, true});
    runs.push_back({1e-14, "1e-14", 0.0, ConeForm::kSlipSpeed, false, true});
  }
  runs.insert(runs.end(),
              {{1e-14, "1e-14"}, {1e-12, "1e-12"}, {1e-16, "1e-16", 1e-2}, {1e-16, "1e-16", 1e-1}});
  if (frictional) {
    runs.insert(runs.end(), {{1e-16, "1e-16", 0.0, ConeForm::kShiftedBox},
                             {1e-16, "1e-16", 1e-2, ConeForm::kShiftedBox}});
  }
  if (rate_form) runs.push_back({1e-16, "1e-16", 1e-2, ConeForm::kSlipSpeed, false, true});
  return runs;
}

// What a run did, for the solver's message.
std::string RunAccount(const Run& run, const lemke_internal::LemkeResult& lemke, double residual) {
  const bool solved = lemke.outcome == lemke_internal::LemkeOutcome::kSolved;
  const std::string failure =
      std::string(lemke_internal::ToString(lemke.outcome)) + " (" + lemke.message + ")";
  if (run.basis_only)
    return "the given basis: " + (solved ? "residual " + Scientific(residual) : failure);
  const bool perturbed = run.perturbation > 0.0;
  return std::string(run.rate ? "rate form, " : "") +
         (run.form == ConeForm::kShiftedBox ? "box form, " : "") +
         (perturbed ? "perturbed " + Scientific(run.perturbation) : std::string("cold")) +
         ", ties " + run.name + ": " + (solved ? std::string("solved") : failure) + " after " +
         std::to_string(lemke.pivots) + " pivots";
}

template <class Problem>
SolveResult SolveLemke(const Problem& problem, const MatrixForm& k, const SolverOptions& o,
                       const SolverGuess& given, const std::string& name) {
  const solvers_internal::Deadline deadline(o.time_limit);
  const int unknowns = static_cast<int>(k.h.rows());
  if (unknowns == 0) {  // no contact: nothing to pivot, the empty impulse vector solves it
    SolveResult empty;
    empty.report.backend = name;
    empty.report.status = SolveStatus::kConverged;
    return empty;
  }
  Posed slip = Pose(k, ConeForm::kSlipSpeed);
  const bool frictional = HasFriction(k);
  Posed box = frictional ? Pose(k, ConeForm::kShiftedBox) : Posed{};
  SolveResult result;
  SolveReport& report = result.report;
  report.backend = name;
  std::string history;
  int pivots = 0;
  const double velocity_scale = o.lemke.velocity_scale > 0.0 ? o.lemke.velocity_scale : 1.0;
  const std::vector<char> given_basis = ExpandBasis(k, given.basis, slip.enc.variables);
  const bool rate_form = velocity_scale != 1.0;
  const std::vector<Run> runs = PlanRuns(!given_basis.empty(), rate_form, frictional);
  std::optional<Posed> rate_slip, rate_box;  // the rate form, posed when its first run comes
  auto posed_for = [&](const Run& run) -> Posed& {
    const bool is_box = run.form == ConeForm::kShiftedBox;
    if (!run.rate) return is_box ? box : slip;
    std::optional<Posed>& lazy = is_box ? rate_box : rate_slip;
    if (!lazy) lazy = Pose(k, run.form, velocity_scale);
    return *lazy;
  };
  for (const Run& run : runs) {
    const bool perturbed = run.perturbation > 0.0;
    Posed& posed = posed_for(run);
    lemke_internal::Mlcp& mlcp = posed.mlcp;  // the run's basis and perturbation are set in place
    mlcp.given_basis = run.basis_only ? given_basis : std::vector<char>();
    mlcp.perturbation = perturbed
                            ? PerturbationOf(k, posed.enc, o, run.perturbation, posed.velocity_unit)
                            : Eigen::VectorXd();
    const int per_row = o.lemke.pivots_per_row > 0 ? o.lemke.pivots_per_row : run.rate ? 200 : 20;
    const int per_run = static_cast<int>(
        std::min<long long>(o.lemke.max_pivots, 1LL * per_row * posed.enc.variables + 100));
    const lemke_internal::LemkeResult lemke = lemke_internal::SolveMlcp(
        mlcp, std::min(per_run, o.lemke.max_pivots - pivots), run.tie, deadline.SecondsLeft());
    pivots += lemke.pivots;
    Eigen::VectorXd impulses = posed.t * lemke.z;
    double residual = ComputeResidual(problem, impulses).residual;
    const bool solved = lemke.outcome == lemke_internal::LemkeOutcome::kSolved;
    bool exact = solved;
    if (!history.empty()) history += "; ";
    history += RunAccount(run, lemke, residual);
    if (perturbed && solved) {
      history += " (without the perturbation, basic values down to " +
                 Scientific(-lemke.polish_violation) + ")";
      if (residual > o.tolerance) {
        // The perturbed problem's solution, polished by Newton on the given problem. Where
        // the perturbation left its active set right Newton converges from it (34 of the
        // 56 cycling openings at μ = 0.1); elsewhere it stalls near 1e-11 and says so.
        const SolveResult newton = Polish(problem, impulses, o);
        history += "; Newton polish from it: residual " + Scientific(newton.report.residual) +
                   " after " + std::to_string(newton.report.iterations) + " iterations";
        exact = newton.report.converged();
        if (newton.report.residual < residual)
          impulses = newton.impulses, residual = newton.report.residual;
      }
    }
    if (report.status != SolveStatus::kConverged &&
        (result.impulses.size() == 0 || residual < report.residual)) {
      result.impulses = impulses;
      // The run's basis where the answer is that basis's solution, else the pattern's.
      const bool basis_answer = solved && run.form == ConeForm::kSlipSpeed &&
                                lemke.polish_violation == 0.0 && impulses == posed.t * lemke.z;
      result.basis = basis_answer ? CompressBasis(k, lemke.z_basic)
                                  : BasisOfPattern(k, impulses, velocity_scale);
      report.residual = residual;
      report.status = exact && residual <= o.tolerance ? SolveStatus::kConverged
                                                       : SolveStatus::kNumericalFailure;
    }
    if (report.converged() || pivots >= o.lemke.max_pivots || deadline.Passed()) break;
  }
  report.iterations = pivots;
  if (!report.converged() && (pivots >= o.lemke.max_pivots || deadline.Passed()))
    report.status = SolveStatus::kIterationLimit;
  report.message = "Lemke: " + history;
  if (!report.converged() && deadline.Passed())
    report.message = solvers_internal::TimeLimitMessage(o.time_limit) + "; " + report.message;
  return result;
}

}  // namespace

SolveResult LemkeSolver::DoSolve(const ContactProblem& p, const SolverOptions& options,
                                 const SolverGuess& guess) {
  return SolveLemke(p, MatrixFormOf(p), options, guess, Name());
}

SolveResult LemkeSolver::DoSolveDelassus(const DelassusProblem& p, const SolverOptions& options,
                                         const SolverGuess& guess) {
  return SolveLemke(p, MatrixFormOf(p), options, guess, Name());
}

}  // namespace unjam
