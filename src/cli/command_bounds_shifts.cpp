// `unjam bounds FILE (--top | --bottom | --shift-down P | --shift-up P) [--compare-perturb]`: the
// interval of each particle shift's critical force over the admissible networks (shift_bounds.hpp),
// beside the stored network's value and, on request, the F_crit that `unjam perturb` finds.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include "command_bounds.hpp"
#include "unjam/indeterminacy/shift_bounds.hpp"
#include "unjam/io/output_lock.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/perturbation.hpp"
#include "unjam/protocols/response_ensemble.hpp"

namespace unjam::cli {

namespace {

using Clock = std::chrono::steady_clock;

struct ShiftComparison {
  std::vector<double> f_crit;  // resolved quasi-static answers (`ok` or `nonlinear`); NaN otherwise
  std::vector<double> f_crit_10xi;  // the answer at 10ξ of the small-gap check
  std::vector<PerturbationStatus> status;
  std::vector<int>
      inside;  // 1 / 0: a quasi-static F_crit inside [min, max] or not; −1: no such F_crit
  int WithStatus(PerturbationStatus s) const {
    return static_cast<int>(std::count(status.begin(), status.end(), s));
  }
  int WithInside(int value) const {
    return static_cast<int>(std::count(inside.begin(), inside.end(), value));
  }
};

// Both sides carry the LP's and the step's tolerances (about 1e-6 of the forces), and
// F_crit its inertial part, of order ξ (10 times that at 10ξ). An unbounded side bounds
// nothing. Every quasi-static answer counts, `nonlinear` ones with both of theirs: a
// solver's member of the step's family, at ξ or at 10ξ, is an admissible network.
bool Inside(const ShiftBounds& b, double f_y, double f_crit, double inertial_force) {
  const double tol = 1e-6 * (std::abs(b.max.ok() ? b.max.value : 0.0) + f_y) + inertial_force;
  return (!b.min.ok() || f_crit >= b.min.value - tol) &&
         (!b.max.ok() || f_crit <= b.max.value + tol);
}

bool Decided(const Bound& b) { return b.ok() || b.status == BoundStatus::kUnbounded; }

int InsideInterval(const ShiftBounds& b, double f_y, const PerturbationResult& r) {
  if (!r.resolved || !r.quasi_static) return -1;
  if (!Decided(b.min) || !Decided(b.max) || !Inside(b, f_y, r.f_crit, r.inertial_force)) return 0;
  return std::isnan(r.fcrit_10xi) || Inside(b, f_y, r.fcrit_10xi, 10.0 * r.inertial_force) ? 1 : 0;
}

ShiftComparison CompareShifts(const PerturbationBase& base,
                              const std::vector<PerturbationTarget>& targets,
                              const ShiftBoundsReport& report, const std::vector<double>& f_y,
                              int threads) {
  ShiftComparison out;
  out.f_crit.assign(targets.size(), std::nan(""));
  out.f_crit_10xi.assign(targets.size(), std::nan(""));
  out.status.assign(targets.size(), PerturbationStatus::kNotConverged);
  out.inside.assign(targets.size(), -1);
  PerturbAll(base, targets, PerturbationOptions{}, threads,
             [&](int k, const PerturbationResult& r) {
               out.status[k] = r.status;
               out.inside[k] = InsideInterval(report.bounds[k], f_y[k], r);
               if (!r.resolved || !r.quasi_static) return;
               out.f_crit[k] = r.f_crit;
               out.f_crit_10xi[k] = r.fcrit_10xi;
             });
  return out;
}

std::string Csv(const Scene& scene, const ShiftBoundsReport& r, const std::vector<double>& f_y,
                const ShiftComparison* cmp) {
  auto number = [](const Bound& b) { return b.ok() ? ExactNumber(b.value) : std::string(); };
  std::ostringstream os;
  os << "particle,direction_x,direction_y,x,y,f_y,f_static,min,max,status_min,status_max,unloaded_"
        "contacts";
  if (cmp) os << ",f_crit,f_crit_10xi,perturbation_status,inside_interval";
  os << "\n";
  for (std::size_t a = 0; a < r.bounds.size(); ++a) {
    const ShiftBounds& b = r.bounds[a];
    const Vec2& x = scene.particles[b.target.particle].position;
    os << b.target.particle << ',' << b.target.direction.x() << ',' << b.target.direction.y() << ','
       << ExactNumber(x.x()) << ',' << ExactNumber(x.y()) << ',' << ExactNumber(f_y[a]) << ','
       << ExactNumber(b.reference) << ',' << number(b.min) << ',' << number(b.max) << ','
       << ToString(b.min.status) << ',' << ToString(b.max.status) << ',' << b.unloaded_contacts;
    if (cmp)
      os << ',' << ExactNumber(cmp->f_crit[a]) << ',' << ExactNumber(cmp->f_crit_10xi[a]) << ','
         << ToString(cmp->status[a]) << ','
         << (cmp->inside[a] < 0 ? "" : std::to_string(cmp->inside[a]));
    os << "\n";
  }
  return os.str();
}

struct Means {
  double f_y = 0.0, f_static = 0.0, min = 0.0, max = 0.0;  // over the bounded shifts
  int bounded = 0, no_lower_bound = 0, no_upper_bound = 0, failed = 0;
  // Shifts that no admissible network resists by `perturb`'s rattler threshold (a bottom
  // grain nothing rests on): rattlers whatever member of the step a solver picks.
  int need_no_force = 0;
};

Means Summarise(const ShiftBoundsReport& r, const std::vector<double>& f_y, double rattler_force) {
  Means m;
  for (std::size_t a = 0; a < r.bounds.size(); ++a) {
    const ShiftBounds& b = r.bounds[a];
    m.need_no_force += b.max.ok() && b.max.value < rattler_force;
    m.no_lower_bound += b.min.status == BoundStatus::kUnbounded;
    m.no_upper_bound += b.max.status == BoundStatus::kUnbounded;
    if (!Decided(b.min) || !Decided(b.max)) ++m.failed;
    if (!b.min.ok() || !b.max.ok()) continue;
    m.f_y += f_y[a];
    m.f_static += b.reference;
    m.min += b.min.value;
    m.max += b.max.value;
    ++m.bounded;
  }
  if (m.bounded > 0) {
    for (double* x : {&m.f_y, &m.f_static, &m.min, &m.max}) *x /= m.bounded;
  }
  return m;
}

nlohmann::json MeanOrNull(const Means& m, double value) {
  return m.bounded > 0 ? NumberOrNull(value) : nlohmann::json(nullptr);
}

// The shifts the flags ask for (chosen by the library, as for `unjam perturb`), and how the
// summary names them.
struct SelectedShifts {
  std::vector<PerturbationTarget> targets;
  std::string side;         // JSON "side": top, bottom, down or up
  std::string description;  // the summary's line
};

SelectedShifts SelectShifts(const ShiftSelection& selection, const PerturbationBase& base) {
  std::vector<PerturbationTarget> targets = ShiftTargets(base, selection);
  const std::string particle = "of particle " + std::to_string(selection.particle);
  switch (selection.kind) {
    case ShiftSelection::Kind::kTop: return {std::move(targets), "top", "top (pushed down)"};
    case ShiftSelection::Kind::kBottom: return {std::move(targets), "bottom", "bottom (pushed up)"};
    case ShiftSelection::Kind::kDown:
      return {std::move(targets), "down", particle + " (pushed down)"};
    case ShiftSelection::Kind::kUp: return {std::move(targets), "up", particle + " (pushed up)"};
  }
  return {};
}

// The text summary of a run.
void PrintShiftBounds(const SelectedShifts& selection, std::size_t shifts,
                      const ShiftBoundsReport& report, const Means& m,
                      const std::optional<ShiftComparison>& cmp, double seconds, bool cold) {
  std::printf("shifts             %zu %s\n", shifts, selection.description.c_str());
  std::printf("ensemble           %s%s%s\n", report.feasible ? "feasible" : "INFEASIBLE",
              report.message.empty() ? "" : ": ", report.message.c_str());
  std::printf(
      "bounded            %d of %zu (no upper bound, a network resists any push: %d; no lower "
      "bound: %d; failed: %d)\n",
      m.bounded, shifts, m.no_upper_bound, m.no_lower_bound, m.failed);
  std::printf(
      "need no force      %d (max below perturb's rattler threshold: rattlers whatever the "
      "solver)\n",
      m.need_no_force);
  if (m.bounded > 0) {
    std::printf(
        "means              F_y %.6g, F_crit of the stored network %.6g, LP min %.6g, LP max "
        "%.6g\n",
        m.f_y, m.f_static, m.min, m.max);
  }
  if (cmp) {
    std::printf(
        "perturb            %d ok, %d nonlinear (quasi-static: %d inside [LP min, LP max], %d "
        "outside), %d dynamic, %d blocked\n",
        cmp->WithStatus(PerturbationStatus::kOk), cmp->WithStatus(PerturbationStatus::kNonlinear),
        cmp->WithInside(1), cmp->WithInside(0), cmp->WithStatus(PerturbationStatus::kDynamic),
        cmp->WithStatus(PerturbationStatus::kBlocked));
  }
  std::printf("seconds            %.3f (LPs %.3f, %lld simplex iterations, %s)\n", seconds,
              report.seconds, report.lp_iterations, cold ? "cold" : "warm");
}

}  // namespace

int RunShiftBounds(const BoundsFlags& f) {
  const auto start = Clock::now();
  if (LpBackendFromString(f.lp) != LpBackend::kClp)
    throw std::invalid_argument(
        "--lp: shift bounds (--top, --bottom, --shift-down, --shift-up) use clp only");
  const EquilibriumSystemOptions so = f.SystemOptions();
  std::optional<OutputLock> lock;  // one run per output, as for contacts
  if (!f.output.empty()) lock.emplace(f.output + ".lock", f.output);
  const Scene scene = ReadPacking(f.file);
  if (scene.forces.empty()) {
    throw InputError(
        f.file, 0,
        "stores no static forces, from which the shifts are chosen: run `unjam solve " + f.file +
            " -o FILE` first");
  }
  const PerturbationBase base = PreparePerturbations(scene, PerturbationOptions{});
  const SelectedShifts selection = SelectShifts(*f.shifts.Selection(), base);
  const std::vector<PerturbationTarget>& targets = selection.targets;
  const EquilibriumSystem system = BuildEquilibriumSystem(scene, so);
  std::vector<ShiftTarget> shifts;
  std::vector<double> f_y;
  for (const PerturbationTarget& t : targets) {
    shifts.push_back({t.i, t.direction});
    f_y.push_back(EffectiveWeightOf(base, t.i));
  }
  const int threads = ThreadsFromOption(f.threads);
  BoundsOptions bo;
  bo.warm_start = !f.cold;
  bo.threads = threads;
  const ShiftBoundsReport report =
      ComputeShiftBounds(system, shifts, StoredForcesOf(system, scene.forces), bo);
  std::optional<ShiftComparison> cmp;
  if (f.compare_perturb && report.feasible)
    cmp = CompareShifts(base, targets, report, f_y, threads);
  if (!f.output.empty())
    WriteFileAtomically(f.output, Csv(scene, report, f_y, cmp ? &*cmp : nullptr));

  const Means m = Summarise(report, f_y, EnsembleOptions{}.rattler_force * base.mean_contact_force);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  nlohmann::json out = {{"file", f.file},
                        {"shifts", shifts.size()},
                        {"side", selection.side},
                        {"feasible", report.feasible},
                        {"message", report.message},
                        {"bounded", m.bounded},
                        {"no_lower_bound", m.no_lower_bound},
                        {"no_upper_bound", m.no_upper_bound},
                        {"failed", m.failed},
                        {"need_no_force", m.need_no_force},
                        {"mean_fy", MeanOrNull(m, m.f_y)},
                        {"mean_fstatic", MeanOrNull(m, m.f_static)},
                        {"mean_min", MeanOrNull(m, m.min)},
                        {"mean_max", MeanOrNull(m, m.max)},
                        {"lp", "clp"},
                        {"warm_start", !f.cold},
                        {"lp_iterations", report.lp_iterations},
                        {"lp_seconds", report.seconds},
                        {"threads", threads},
                        {"seconds", seconds}};
  if (cmp) {
    out["quasi_static"] = cmp->WithStatus(PerturbationStatus::kOk);
    out["nonlinear"] = cmp->WithStatus(PerturbationStatus::kNonlinear);
    out["dynamic"] = cmp->WithStatus(PerturbationStatus::kDynamic);
    out["blocked"] = cmp->WithStatus(PerturbationStatus::kBlocked);
    out["inside_interval"] = cmp->WithInside(1);
    out["outside_interval"] = cmp->WithInside(0);
  }
  if (!f.output.empty()) out["output"] = f.output;
  if (f.summary && f.json) std::printf("%s\n", out.dump().c_str());
  else if (f.summary) PrintShiftBounds(selection, shifts.size(), report, m, cmp, seconds, f.cold);
  return report.feasible ? kOk : kNotConverged;
}

}  // namespace unjam::cli
