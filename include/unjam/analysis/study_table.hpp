// The tables of a friction study (docs/friction-study.md): one row per packing and kind of
// perturbation (StudyRun), and their aggregate per set of packings that differ only in
// their seed (StudyRow). Pure numbers: no scene, no solver, no files.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "unjam/analysis/statistics.hpp"

namespace unjam {

inline constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();
inline constexpr MeanAndError kNoMean{kNoValue, kNoValue, 0};  // a mean over no sample

// The parameters that make a set: every run of one set differs only in `seed`.
struct StudyKey {
  std::string protocol;  // "pressure" or "gravity"
  int n = 0;
  double width = kNoValue;     // gravity: cell width
  double pressure = kNoValue;  // pressure: P_ext
  double mu = 0.0;
  std::string kind;  // openings: the cell mode (fixed-pressure, fixed-volume); shifts: top, bottom
  bool operator==(const StudyKey& o) const;
};

// One packing, one kind of perturbation. A quantity that cannot be had is NaN (a mean over
// no sample), with count 0.
struct StudyRun {
  StudyKey key;
  std::uint64_t seed = 0;
  // The packing.
  double packing_fraction = kNoValue, z = kNoValue, z_with_rattlers = kNoValue;
  double height = kNoValue;              // gravity: top of the highest free disk above the bed
  double mean_contact_force = kNoValue;  // ⟨F⟩ over every force-carrying contact
  int rattlers = 0, particles = 0;
  // The perturbations (`unjam perturb`'s summary).
  int perturbations = 0, used = 0, dynamic = 0, nonlinear = 0, not_converged = 0, blocked = 0,
      shift_rattlers = 0;
  MeanAndError f_crit = kNoMean, f_reference = kNoMean,
               delta = kNoMean;      // over the used perturbations
  MeanAndError ratio = kNoMean;      // ⟨F_crit⟩/⟨F_reference⟩ over the used perturbations
  MeanAndError ratio_all = kNoMean;  // openings: ⟨F_crit⟩ of the used over ⟨F⟩ of every contact
  MeanAndError alpha = kNoMean;      // the paper's decay exponent of the averaged field
  MeanAndError tail_scale = kNoMean;  // exponential tail of F_crit/⟨F_crit⟩
  // Every perturbation whose step has a force (ok, nonlinear, and dynamic ones a backend
  // solved; not those the static LP decides): ⟨F_crit⟩ over them and ⟨F⟩ of every contact.
  MeanAndError f_crit_any = kNoMean;
  MeanAndError rattler_f_crit = kNoMean;  // shifts: F_crit of the rattlers
  // The LP interval of the same perturbations (docs/indeterminacy.md), over the used ones
  // with both bounds: means of min and max, and where F_crit lies in it, (F − min)/(max − min).
  MeanAndError lp_min = kNoMean, lp_max = kNoMean, lp_position = kNoMean;
  double seconds = 0.0;
};

// A set of runs (every seed) of one key.
struct StudyRow {
  StudyKey key;
  int packings = 0;
  int perturbations = 0, used = 0, dynamic = 0, nonlinear = 0, not_converged = 0, blocked = 0,
      shift_rattlers = 0, particles = 0, rattlers = 0;
  MeanAndError packing_fraction, z, z_with_rattlers, height, mean_contact_force;
  MeanAndError f_crit, f_reference, delta, ratio, ratio_all, alpha, tail_scale, f_crit_any,
      rattler_f_crit, lp_min, lp_max, lp_position;
  double dynamic_share = kNoValue;  // dynamic / perturbations
  double seconds = 0.0;
};

// Groups the runs by key (in the order keys first appear) and combines each quantity over
// the set's packings: with one packing, its own mean and error; with more, the mean of the
// packings' means and the standard error of that mean from their scatter (the packings are
// the independent samples; the perturbations of one packing are not). A packing without a
// value (NaN) is left out of that quantity; `count` is the number of samples behind it
// (perturbations for one packing, packings for several). Counts are summed.
std::vector<StudyRow> AggregateStudy(const std::vector<StudyRun>& runs);

}  // namespace unjam
