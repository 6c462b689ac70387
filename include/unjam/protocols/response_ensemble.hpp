// What an ensemble of perturbations of one packing measures (docs/perturbations.md).
//
// Each perturbation is first reduced to a fixed-size record (scalars, its radial profiles
// and its fields in the contact frame), so that long runs keep little memory and can be
// resumed from records saved as they go. The ensemble summary averages the records:
// profiles and fields are averaged over perturbations, and their errors come from the
// scatter between perturbations (particles within one response are correlated).
//
// Contact frame: the perturbation point (contact point, or the shifted particle's centre)
// at the origin, x along its axis (the contact normal, or the vertical), positions taken at
// their nearest periodic image. Displacements are in units of ξ.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "unjam/analysis/statistics.hpp"
#include "unjam/analysis/stress_field.hpp"
#include "unjam/protocols/perturbation.hpp"

namespace unjam {

struct EnsembleOptions {
  int bins_per_decade = 6;   // radial profiles
  double profile_min = 1.0;  // first bin edge, length units
  double fit_min = 2.0;      // power-law fit range of d(r); fit_max ≤ 0 = half
  double fit_max = 0.0;      //   the frame window's half-width
  double field_box = 1.0;    // displacement field grid (contact frame)
  double stress_box = 2.0;   // coarse-grained stress boxes (the side 2)
  int histogram_bins = 20;
  // A bottom (upward) shift needing less force than this fraction of the mean contact
  // force is a rattler's: excluded from the averages.
  double rattler_force = 1e-6;
};

// Everything that is the same for every perturbation of one base.
struct ResponseLayout {
  double gap = 0.0;     // ξ
  double window = 0.0;  // half-width of the contact-frame window
  double profile_min = 1.0, profile_max = 1.0;
  int bins_per_decade = 6;
  GridSpec field;   // displacement grid, contact frame
  GridSpec stress;  // stress grid, contact frame
  double mean_contact_force = 0.0;
  double f0 = 0.0;  // 2 R_avg P_ext (pressure bath), else 0
};
ResponseLayout MakeLayout(const PerturbationBase& base, const EnsembleOptions& options, double gap);

struct ReducedResponse {
  PerturbationTarget target;
  Vec2 origin = Vec2::Zero(), axis = Vec2(1.0, 0.0);
  double f_crit = 0.0, f_reference = 0.0, penetration_depth = 0.0;
  double cell_strain = 0.0, pressure_change = 0.0;
  double inertia_ratio = 0.0, inertial_force = 0.0, equilibrium_residual = 0.0, residual = 0.0,
         seconds = 0.0;
  double fcrit_10xi = std::numeric_limits<double>::quiet_NaN();  // unless checked (check_linearity)
  double linearity_misfit = std::numeric_limits<double>::quiet_NaN();
  int iterations = 0;
  PerturbationStatus status = PerturbationStatus::kNotConverged;
  std::string message;   // the solver's account of its run (why it stopped)
  std::string backend;   // the backend whose answer this is (the fallback's, after one)
  bool rattler = false;  // upward shift that needed no force
  bool Used() const { return status == PerturbationStatus::kOk && !rattler; }
  std::vector<double> displacement_profile;  // mean |d|/ξ per radial bin (NaN: empty bin)
  std::vector<double> force_profile;         // mean |Δf_n| per radial bin of contact points
  std::vector<double> field;                 // Σ d/ξ per box, (x, y) interleaved
  std::vector<int> field_count;              // particles per box
  std::vector<double> stress;                // Δσ per stress box, (xx, xy, yy) interleaved
};
ReducedResponse Reduce(const PerturbationBase& base, const PerturbationResult& result,
                       const ResponseLayout& layout, const EnsembleOptions& options);

struct FieldBox {
  Vec2 center = Vec2::Zero();
  Vec2 mean = Vec2::Zero();  // mean d/ξ over perturbations and particles
  int count = 0;
};
struct StressBox {
  Vec2 center = Vec2::Zero();
  Eigen::Matrix2d mean = Eigen::Matrix2d::Zero();  // ⟨Δσ⟩ over perturbations
  double pressure_change = 0.0;                    // ½ tr ⟨Δσ⟩
  double max_shear = 0.0;                          // τ_max of ⟨Δσ⟩
  double shear_angle = 0.0;  // arcsin(τ_max / |ΔP|), radians; NaN if τ_max > |ΔP|
  // The stress after the perturbation, the paper's: ⟨σ_static⟩ (the base's static forces,
  // coarse-grained in each used perturbation's contact frame) + ⟨Δσ⟩; its pressure and its
  // angle of shearing θ = arcsin(τ_max / P) (NaN where τ_max > P or P ≤ 0). Without the
  // base (Summarize's last argument) these stay NaN.
  Eigen::Matrix2d after = Eigen::Matrix2d::Constant(std::numeric_limits<double>::quiet_NaN());
  double pressure_after = std::numeric_limits<double>::quiet_NaN();
  double shear_angle_after = std::numeric_limits<double>::quiet_NaN();
};

struct EnsembleSummary {
  int perturbations = 0, used = 0, rattlers = 0, not_converged = 0, dynamic = 0, nonlinear = 0,
      blocked = 0;
  MeanAndError f_crit, f_reference, penetration_depth;
  double ratio = 0.0, ratio_error = 0.0;  // ⟨F_crit⟩ / ⟨F_reference⟩
  double f0 = 0.0;
  double corr_fcrit_delta = 0.0, corr_freference_delta = 0.0, corr_fcrit_freference = 0.0;
  // The paper's d(r) (METHOD.md, "Average displacement decay"): the displacement fields of
  // all used perturbations averaged as vectors in the contact frame (`field`), the
  // magnitude of that average per box, averaged over the angle at each r (boxes by the
  // distance of their centre); errors by a jackknife over blocks of perturbations.
  std::vector<LogBin> averaged_field_profile;
  PowerLawFit decay;  // the paper's α: d ∝ r^(−α) of averaged_field_profile (jackknife error)
  std::vector<LogBin> displacement_profile;  // ⟨|d|⟩/ξ vs r, the mean of each |d_i| per bin
  PowerLawFit magnitude_decay;               // its fit: another quantity than the paper's α
  std::vector<LogBin> force_profile;         // ⟨|Δf_n|⟩ vs r
  Histogram fcrit_raw, fcrit_over_f0, fcrit_over_mean;
  ExponentialTailFit fcrit_tail;  // of F_crit/⟨F_crit⟩ above 1
  std::vector<FieldBox> field;
  std::vector<StressBox> stress;
};
// `base`, if given, is the packing the records perturbed: it adds the static stress to the
// stress boxes (StressBox::after).
EnsembleSummary Summarize(const std::vector<ReducedResponse>& records, const ResponseLayout& layout,
                          const EnsembleOptions& options, const PerturbationBase* base = nullptr);

// The base's static stress coarse-grained on layout.stress in the contact frame of
// (origin, axis): each static contact force's dyad f ⊗ l shared among the boxes.
std::vector<Eigen::Matrix2d> StaticStressInFrame(const PerturbationBase& base, Vec2 origin,
                                                 Vec2 axis, const ResponseLayout& layout);

}  // namespace unjam
