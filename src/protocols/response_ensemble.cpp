#include "unjam/protocols/response_ensemble.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace unjam {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Coordinates in the frame with x along `axis`.
Vec2 ToFrame(Vec2 axis, Vec2 v) { return Vec2(v.dot(axis), v.dot(Perp(axis))); }

// A square grid of an odd number of boxes centred on the origin: the perturbation point is
// the centre of the middle box.
GridSpec CenteredGrid(double window, double side) {
  const int half = std::max(0, static_cast<int>(std::floor((window - 0.5 * side) / side)));
  GridSpec g;
  g.nx = g.ny = 2 * half + 1;
  g.side = Vec2(side, side);
  g.origin = Vec2(-0.5 * g.nx * side, -0.5 * g.ny * side);
  return g;
}

int BoxOf(const GridSpec& g, Vec2 p) {
  const int ix = static_cast<int>(std::floor((p.x() - g.origin.x()) / g.side.x()));
  const int iy = static_cast<int>(std::floor((p.y() - g.origin.y()) / g.side.y()));
  if (ix < 0 || iy < 0 || ix >= g.nx || iy >= g.ny) return -1;
  return iy * g.nx + ix;
}

std::vector<double> BinMeans(const std::vector<double>& r, const std::vector<double>& v,
                             const ResponseLayout& layout) {
  std::vector<double> out;
  for (const LogBin& b :
       LogBinned(r, v, layout.profile_min, layout.profile_max, layout.bins_per_decade)) {
    out.push_back(b.count > 0 ? b.mean : kNaN);
  }
  return out;
}

bool IsPerturbedContact(const PerturbationTarget& t, const ContactForceChange& c) {
  return t.kind == PerturbationTarget::Kind::kContactOpening && c.i == t.i && c.j == t.j &&
         c.image == t.image;
}

void ReduceDisplacements(const PerturbationBase& base, const PerturbationResult& result,
                         const ResponseLayout& layout, ReducedResponse& out) {
  std::vector<double> r, magnitude;
  out.field.assign(2 * layout.field.nx * layout.field.ny, 0.0);
  out.field_count.assign(layout.field.nx * layout.field.ny, 0);
  const std::vector<char> movable = MovableParticles(base.scene);
  for (std::size_t i = 0; i < result.displacement.size(); ++i) {
    if (!movable[i]) continue;
    const bool shifted = result.target.kind == PerturbationTarget::Kind::kParticleShift &&
                         static_cast<int>(i) == result.target.i;
    if (shifted) continue;
    const Vec2 rel =
        ToFrame(result.axis,
                MinimumImage(base.scene.cell, base.scene.particles[i].position - result.origin));
    const Vec2 d = ToFrame(result.axis, result.displacement[i]) / layout.gap;
    r.push_back(rel.norm());
    magnitude.push_back(d.norm());
    const int box = BoxOf(layout.field, rel);
    if (box < 0) continue;
    out.field[2 * box] += d.x();
    out.field[2 * box + 1] += d.y();
    ++out.field_count[box];
  }
  out.displacement_profile = BinMeans(r, magnitude, layout);
}

// A contact's force (fn, ft) on its centre-to-centre segment from particle i, in the
// contact frame of (origin, axis): what the coarse-grained stress shares among boxes.
StressSegment FrameSegment(const Scene& scene, int i, Vec2 branch, Vec2 normal, double fn,
                           double ft, Vec2 origin, Vec2 axis) {
  const Vec2 start = MinimumImage(scene.cell, scene.particles[i].position - origin);
  const Vec2 force = fn * normal + ft * Perp(normal);
  return {ToFrame(axis, start), ToFrame(axis, branch), ToFrame(axis, force)};
}

// arcsin(τ_max / P) where P > 0 and τ_max ≤ P; NaN otherwise.
double ShearAngle(double max_shear, double pressure) {
  return pressure > 0.0 && max_shear <= pressure ? std::asin(max_shear / pressure) : kNaN;
}

void ReduceForces(const PerturbationBase& base, const PerturbationResult& result,
                  const ResponseLayout& layout, ReducedResponse& out) {
  std::vector<double> r, change;
  std::vector<StressSegment> segments;
  for (const ContactForceChange& c : result.force_changes) {
    const double dn = c.normal_after - c.normal_before;
    const double dt = c.tangential_after - c.tangential_before;
    if (!IsPerturbedContact(result.target, c)) {
      r.push_back(MinimumImage(base.scene.cell, c.point - result.origin).norm());
      change.push_back(std::abs(dn));
    }
    if (dn == 0.0 && dt == 0.0) continue;
    segments.push_back(
        FrameSegment(base.scene, c.i, c.branch, c.normal, dn, dt, result.origin, result.axis));
  }
  out.force_profile = BinMeans(r, change, layout);
  const StressGrid grid = CoarseGrainedStress(layout.stress, segments);
  out.stress.clear();
  for (const Eigen::Matrix2d& s : grid.stress) {
    out.stress.insert(out.stress.end(), {s(0, 0), s(0, 1), s(1, 1)});
  }
}

// Profiles averaged over perturbations, bin by bin, skipping perturbations without
// particles in the bin.
std::vector<LogBin> AverageProfiles(const std::vector<const std::vector<double>*>& profiles,
                                    const ResponseLayout& layout) {
  std::vector<LogBin> bins =
      LogBinned({}, {}, layout.profile_min, layout.profile_max, layout.bins_per_decade);
  for (std::size_t b = 0; b < bins.size(); ++b) {
    std::vector<double> samples;
    for (const std::vector<double>* p : profiles) {
      if (b < p->size() && std::isfinite((*p)[b])) samples.push_back((*p)[b]);
    }
    const MeanAndError m = MeanWithError(samples);
    bins[b].r_mean = std::sqrt(bins[b].r_low * bins[b].r_high);
    bins[b].mean = m.mean;
    bins[b].error = m.error;
    bins[b].count = m.count;
  }
  return bins;
}

// Error of the ratio of two means of paired samples: the standard error of a − R b over ⟨b⟩.
double RatioError(const std::vector<double>& a, const std::vector<double>& b, double ratio,
                  double mean_b) {
  std::vector<double> z(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) z[k] = a[k] - ratio * b[k];
  return mean_b != 0.0 ? MeanWithError(z).error / std::abs(mean_b) : kNaN;
}

Histogram HistogramOf(const std::vector<double>& samples, double scale, int bins) {
  std::vector<double> scaled;
  double top = 0.0;
  for (double s : samples) {
    scaled.push_back(s / scale);
    top = std::max(top, s / scale);
  }
  const double low = std::min(0.0, *std::min_element(scaled.begin(), scaled.end()));
  // Every sample at zero (openings that need no force): one unit-wide range, all of them in
  // its first bin, rather than a range whose bins have no width.
  const double high =
      top > low ? std::nextafter(top, std::numeric_limits<double>::infinity()) : low + 1.0;
  return MakeHistogram(scaled, low, high, bins);
}

// ⟨σ_static⟩ over the used perturbations' frames plus ⟨Δσ⟩, and its angle of shearing.
void AddStaticStress(const PerturbationBase& base, const std::vector<const ReducedResponse*>& used,
                     const ResponseLayout& layout, EnsembleSummary& out) {
  if (used.empty()) return;
  std::vector<Eigen::Matrix2d> sum(out.stress.size(), Eigen::Matrix2d::Zero());
  for (const ReducedResponse* r : used) {
    const std::vector<Eigen::Matrix2d> s = StaticStressInFrame(base, r->origin, r->axis, layout);
    for (std::size_t b = 0; b < sum.size(); ++b) sum[b] += s[b];
  }
  for (std::size_t b = 0; b < sum.size(); ++b) {
    StressBox& box = out.stress[b];
    box.after = sum[b] / static_cast<double>(used.size()) + box.mean;
    box.pressure_after = Pressure(box.after);
    box.shear_angle_after = ShearAngle(MaxShear(box.after), box.pressure_after);
  }
}

void SummarizeFields(const std::vector<const ReducedResponse*>& used, const ResponseLayout& layout,
                     EnsembleSummary& out) {
  const int boxes = layout.field.nx * layout.field.ny;
  out.field.assign(boxes, {});
  for (int b = 0; b < boxes; ++b) {
    Vec2 sum = Vec2::Zero();
    for (const ReducedResponse* r : used) {
      sum += Vec2(r->field[2 * b], r->field[2 * b + 1]);
      out.field[b].count += r->field_count[b];
    }
    out.field[b].center = layout.field.BoxCenter(b);
    if (out.field[b].count > 0) out.field[b].mean = sum / out.field[b].count;
  }
  const int stress_boxes = layout.stress.nx * layout.stress.ny;
  out.stress.assign(stress_boxes, {});
  for (int b = 0; b < stress_boxes; ++b) {
    StressBox& box = out.stress[b];
    for (const ReducedResponse* r : used) {
      box.mean += Eigen::Matrix2d{{r->stress[3 * b], r->stress[3 * b + 1]},
                                  {r->stress[3 * b + 1], r->stress[3 * b + 2]}};
    }
    if (!used.empty()) box.mean /= static_cast<double>(used.size());
    box.center = layout.stress.BoxCenter(b);
    box.pressure_change = Pressure(box.mean);
    box.max_shear = MaxShear(box.mean);
    box.shear_angle = ShearAngle(box.max_shear, std::abs(box.pressure_change));
  }
}

// The paper's d(r) and α (EnsembleSummary::averaged_field_profile), with errors from a
// jackknife over kJackknifeBlocks contiguous blocks of perturbations: the field average is
// not a mean of independent per-perturbation numbers, so the bins' and α's errors come from
// how much they move when one block is left out.
constexpr std::size_t kJackknifeBlocks = 20;

// Per box of the field grid, Σ d/ξ and the particle count over some records.
struct FieldSums {
  std::vector<Vec2> sum;
  std::vector<int> count;
  explicit FieldSums(int boxes) : sum(boxes, Vec2::Zero()), count(boxes, 0) {}
};

// |mean d/ξ| per box with particles, averaged over the boxes of each radial bin (the
// scatter over angles is no error of the mean: the errors are left at 0).
std::vector<LogBin> MagnitudeProfile(const std::vector<Vec2>& mean, const std::vector<int>& count,
                                     const ResponseLayout& layout) {
  std::vector<double> r, magnitude;
  for (std::size_t b = 0; b < count.size(); ++b) {
    if (count[b] == 0) continue;
    r.push_back(layout.field.BoxCenter(static_cast<int>(b)).norm());
    magnitude.push_back(mean[b].norm());
  }
  std::vector<LogBin> bins =
      LogBinned(r, magnitude, layout.profile_min, layout.profile_max, layout.bins_per_decade);
  for (LogBin& bin : bins) bin.error = 0.0;
  return bins;
}

// The jackknife standard error of a quantity from its leave-one-block-out replicates.
double JackknifeError(const std::vector<double>& replicates) {
  const double n = static_cast<double>(replicates.size());
  if (n < 2) return 0.0;
  double mean = 0.0, square = 0.0;
  for (double x : replicates) mean += x / n;
  for (double x : replicates) square += (x - mean) * (x - mean);
  return std::sqrt((n - 1) / n * square);
}

// The profiles with one block of records left out each: the total minus the block's sums.
std::vector<std::vector<LogBin>> LeaveOneBlockOut(const std::vector<const ReducedResponse*>& used,
                                                  const ResponseLayout& layout) {
  const std::size_t blocks = std::min(kJackknifeBlocks, used.size());
  if (blocks < 2) return {};
  const int boxes = layout.field.nx * layout.field.ny;
  std::vector<FieldSums> block(blocks, FieldSums(boxes));
  FieldSums total(boxes);
  for (std::size_t j = 0; j < blocks; ++j) {
    for (std::size_t k = j * used.size() / blocks; k < (j + 1) * used.size() / blocks; ++k) {
      for (int b = 0; b < boxes; ++b) {
        block[j].sum[b] += Vec2(used[k]->field[2 * b], used[k]->field[2 * b + 1]);
        block[j].count[b] += used[k]->field_count[b];
      }
    }
  }
  for (const FieldSums& one : block) {
    for (int b = 0; b < boxes; ++b) {
      total.sum[b] += one.sum[b];
      total.count[b] += one.count[b];
    }
  }
  std::vector<std::vector<LogBin>> out;
  for (const FieldSums& one : block) {
    std::vector<Vec2> mean(boxes, Vec2::Zero());
    std::vector<int> count(boxes, 0);
    for (int b = 0; b < boxes; ++b) {
      count[b] = total.count[b] - one.count[b];
      if (count[b] > 0) mean[b] = (total.sum[b] - one.sum[b]) / count[b];
    }
    out.push_back(MagnitudeProfile(mean, count, layout));
  }
  return out;
}

// The full profile from the ensemble's field (SummarizeFields), its errors and α's from the
// leave-one-block-out profiles.
void SummarizeAveragedFieldDecay(const std::vector<const ReducedResponse*>& used,
                                 const ResponseLayout& layout, double fit_min, double fit_max,
                                 EnsembleSummary& out) {
  std::vector<Vec2> mean;
  std::vector<int> count;
  for (const FieldBox& box : out.field) {
    mean.push_back(box.mean);
    count.push_back(box.count);
  }
  out.averaged_field_profile = MagnitudeProfile(mean, count, layout);
  std::vector<std::vector<LogBin>> left_out = LeaveOneBlockOut(used, layout);
  // Bin errors first (FitPowerLaw weights by them), then α's from the refits.
  std::vector<LogBin>& bins = out.averaged_field_profile;
  for (std::size_t b = 0; b < bins.size(); ++b) {
    std::vector<double> replicates;
    for (const std::vector<LogBin>& p : left_out) replicates.push_back(p[b].mean);
    bins[b].error = JackknifeError(replicates);
  }
  out.decay = FitPowerLaw(bins, fit_min, fit_max);
  if (left_out.empty() || out.decay.points < 3) return;
  std::vector<double> alphas;
  for (std::vector<LogBin>& p : left_out) {
    for (std::size_t b = 0; b < p.size(); ++b) p[b].error = bins[b].error;
    alphas.push_back(FitPowerLaw(p, fit_min, fit_max).alpha);
  }
  out.decay.alpha_error = JackknifeError(alphas);
}

}  // namespace

ResponseLayout MakeLayout(const PerturbationBase& base, const EnsembleOptions& options,
                          double gap) {
  ResponseLayout layout;
  layout.gap = gap;
  const Cell& cell = base.scene.cell;
  if (PeriodicY(cell.periodicity)) layout.window = 0.5 * std::min(cell.size.x(), cell.size.y());
  else if (PeriodicX(cell.periodicity)) layout.window = 0.5 * cell.size.x();
  else layout.window = 0.5 * std::max(cell.size.x(), cell.size.y());
  layout.profile_min = options.profile_min;
  layout.profile_max = std::max(layout.window, 1.01 * options.profile_min);
  layout.bins_per_decade = options.bins_per_decade;
  layout.field = CenteredGrid(layout.window, options.field_box);
  layout.stress = CenteredGrid(layout.window, options.stress_box);
  layout.mean_contact_force = base.mean_contact_force;
  if (base.scene.effects.pressure_bath)
    layout.f0 = 2.0 * base.mean_radius * base.scene.effects.pressure_bath->pressure;
  return layout;
}

ReducedResponse Reduce(const PerturbationBase& base, const PerturbationResult& result,
                       const ResponseLayout& layout, const EnsembleOptions& options) {
  ReducedResponse out;
  out.target = result.target;
  out.origin = result.origin;
  out.axis = result.axis;
  out.f_crit = result.f_crit;
  out.f_reference = result.f_reference;
  out.penetration_depth = result.penetration_depth;
  out.cell_strain = result.cell_strain;
  out.pressure_change = result.pressure_change;
  out.inertia_ratio = result.inertia_ratio;
  out.inertial_force = result.inertial_force;
  out.fcrit_10xi = result.fcrit_10xi;
  out.linearity_misfit = result.linearity_misfit;
  out.equilibrium_residual = result.equilibrium_residual;
  out.residual = result.solve.residual;
  out.iterations = result.solve.iterations;
  out.seconds = result.seconds;
  out.status = result.status;
  out.message = result.solve.message;
  out.backend = result.solve.backend;
  out.rattler = result.target.kind == PerturbationTarget::Kind::kParticleShift &&
                result.target.direction.y() > 0.0 &&
                result.f_crit < options.rattler_force * layout.mean_contact_force;
  ReduceDisplacements(base, result, layout, out);
  ReduceForces(base, result, layout, out);
  return out;
}

std::vector<Eigen::Matrix2d> StaticStressInFrame(const PerturbationBase& base, Vec2 origin,
                                                 Vec2 axis, const ResponseLayout& layout) {
  std::vector<StressSegment> segments;
  for (std::size_t a = 0; a < base.contacts.size(); ++a) {
    const Contact& c = base.contacts[a];
    const double fn = base.forces[a][0], ft = base.forces[a][1];
    if (fn == 0.0 && ft == 0.0) continue;
    segments.push_back(
        FrameSegment(base.scene, c.i, c.center_to_center, c.normal, fn, ft, origin, axis));
  }
  return CoarseGrainedStress(layout.stress, segments).stress;
}

EnsembleSummary Summarize(const std::vector<ReducedResponse>& records, const ResponseLayout& layout,
                          const EnsembleOptions& options, const PerturbationBase* base) {
  EnsembleSummary out;
  out.perturbations = static_cast<int>(records.size());
  out.f0 = layout.f0;
  std::vector<const ReducedResponse*> used;
  std::vector<double> fc, fr, delta;
  for (const ReducedResponse& r : records) {
    if (r.status == PerturbationStatus::kNotConverged) ++out.not_converged;
    if (r.status == PerturbationStatus::kDynamic) ++out.dynamic;
    if (r.status == PerturbationStatus::kNonlinear) ++out.nonlinear;
    if (r.status == PerturbationStatus::kBlocked) ++out.blocked;
    if (r.status == PerturbationStatus::kOk && r.rattler) ++out.rattlers;
    if (!r.Used()) continue;
    used.push_back(&r);
    fc.push_back(r.f_crit);
    fr.push_back(r.f_reference);
    delta.push_back(r.penetration_depth);
  }
  out.used = static_cast<int>(used.size());
  out.f_crit = MeanWithError(fc);
  out.f_reference = MeanWithError(fr);
  out.penetration_depth = MeanWithError(delta);
  out.ratio = out.f_reference.mean != 0.0 ? out.f_crit.mean / out.f_reference.mean : kNaN;
  out.ratio_error = RatioError(fc, fr, out.ratio, out.f_reference.mean);
  out.corr_fcrit_delta = PearsonCorrelation(fc, delta);
  out.corr_freference_delta = PearsonCorrelation(fr, delta);
  out.corr_fcrit_freference = PearsonCorrelation(fc, fr);

  std::vector<const std::vector<double>*> d_profiles, f_profiles;
  for (const ReducedResponse* r : used) {
    d_profiles.push_back(&r->displacement_profile);
    f_profiles.push_back(&r->force_profile);
  }
  out.displacement_profile = AverageProfiles(d_profiles, layout);
  out.force_profile = AverageProfiles(f_profiles, layout);
  const double fit_max = options.fit_max > 0.0 ? options.fit_max : 0.5 * layout.window;
  out.magnitude_decay = FitPowerLaw(out.displacement_profile, options.fit_min, fit_max);

  if (!fc.empty()) {
    out.fcrit_raw = HistogramOf(fc, 1.0, options.histogram_bins);
    if (layout.f0 > 0.0) out.fcrit_over_f0 = HistogramOf(fc, layout.f0, options.histogram_bins);
    if (out.f_crit.mean > 0.0) {
      out.fcrit_over_mean = HistogramOf(fc, out.f_crit.mean, options.histogram_bins);
      std::vector<double> normalised;
      for (double f : fc) normalised.push_back(f / out.f_crit.mean);
      out.fcrit_tail = FitExponentialTail(normalised, 1.0);
    }
  }
  SummarizeFields(used, layout, out);
  if (base != nullptr) AddStaticStress(*base, used, layout, out);
  SummarizeAveragedFieldDecay(used, layout, options.fit_min, fit_max, out);
  return out;
}

}  // namespace unjam
