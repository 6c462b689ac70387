// `unjam perturb FILE (--contact K | --all | --sample N | --top | --bottom
//                     | --shift-down P | --shift-up P) ...`
#include "command_perturb.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "mpi_session.hpp"
#include "output_paths.hpp"
#include "unjam/io/json_lines.hpp"
#include "unjam/io/output_lock.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/io/particle_export.hpp"
#include "unjam/io/response_records.hpp"
#include "unjam/io/run_records.hpp"
#include "unjam/protocols/perturbation.hpp"
#include "unjam/protocols/response_ensemble.hpp"
#include "unjam/solvers/contact_solver.hpp"

namespace unjam::cli {

void PerturbFlags::Register(CLI::App& a) {
  app = &a;
  a.add_option("FILE", file, "static packing with stored forces (.unjam)")->required();
  a.add_option("--contact", contact,
               "open the K-th force-carrying contact (0-based, in the file's force order)");
  a.add_flag("--all", all, "open every force-carrying contact, one by one");
  a.add_option("--sample", sample, "open N contacts drawn at random (see --seed)");
  a.add_option("--seed", seed, "seed of --sample")->capture_default_str();
  a.add_flag("--top", shifts.top, "gravity packings: push the highest particle of each bin down");
  a.add_flag("--bottom", shifts.bottom,
             "gravity packings: push the lowest particle of each bin up");
  a.add_option("--shift-down", shifts.down,
               "push particle P (0-based, in the file's order) down by xi");
  a.add_option("--shift-up", shifts.up, "push particle P (0-based, in the file's order) up by xi");
  a.add_option("--mode", mode, "contact opening: fixed-pressure or fixed-volume")
      ->capture_default_str();
  a.add_option("--gap", gap, "perturbation size xi (gap opened, or shift), length units")
      ->capture_default_str();
  a.add_option("--dt", dt, "time step of the quasi-static perturbation step")
      ->capture_default_str();
  a.add_option("--response-tol", response_tol,
               "solver tolerance as a fraction of xi (unless --tol)")
      ->capture_default_str();
  a.add_flag("--check-linearity,!--no-check-linearity", check_linearity,
             "solve each quasi-static response again at 10 xi; keep it only if linear in xi (else "
             "status nonlinear); "
             "on by default, --no-check-linearity saves the second solve")
      ->capture_default_str();
  a.add_flag("--cold-check", cold_check,
             "the 10 xi check solves from zero impulses, as at xi, instead of continuing the "
             "answer at xi on its "
             "stick/slide/open pattern: it then also asks that the solver pick the same member of "
             "the step's solutions at both gaps");
  a.add_option("--member", member,
               "which solution of a step whose solutions form a family: path (the backend's), or "
               "nearest (the solution "
               "with the same motion pattern nearest the static forces, by a linear program)")
      ->check(CLI::IsMember({"path", "nearest"}))
      ->capture_default_str();
  a.add_option("--threads", threads, "perturbations solved in parallel (0: all cores)")
      ->check(cli::NonNegative())
      ->capture_default_str();
  solver.backend = "auto";  // resolved by PerturbationBackend
  solver.backend_may_be_auto = true;
  solver.Register(a);
  a.remove_option(a.get_option("--max-seconds"));  // a perturbation runs many solves
  a.get_option("--backend")
      ->description(
          "contact solver backend; auto: the rate solve (the quasi-rigid loading path over the "
          "self-stresses, then the step solved exactly on its contact states; "
          "docs/perturbations.md), and where it gives no definite answer the whole step by lemke "
          "on frictional packings of up to " +
          std::to_string(kLemkeAutoContacts) +
          " force-carrying contacts or when a lemke option is given (newton above, and at fixed "
          "volume), newton on frictionless ones");
  a.get_option("--tol")
      ->description("the solver tolerance itself (default: set by --response-tol)")
      ->default_str("");
  auto* output = a.add_option("-o,--output", output_dir,
                              "directory for the results (CSV, fields, records to resume from)");
  a.add_option(
       "--time-limit", time_limit,
       "start no perturbation after S seconds of this run; those started finish, and the results "
       "are written "
       "for all done so far (summary \"complete\": false); rerun the same command to continue")
      ->needs(output);
  a.add_flag("--json", json, "one JSON object on stdout");
  a.add_flag("--quiet", quiet, "no progress on stderr");
}

namespace {

using Clock = std::chrono::steady_clock;

struct Selection {
  std::vector<PerturbationTarget> targets;
  std::string description;
  bool Shifts() const {
    return !targets.empty() && targets[0].kind == PerturbationTarget::Kind::kParticleShift;
  }
};

Selection SelectTargets(const PerturbFlags& f, const PerturbationBase& base) {
  const int chosen = f.contact.has_value() + f.all + f.sample.has_value() + f.shifts.Given();
  if (chosen != 1) {
    throw std::invalid_argument(
        "choose exactly one of --contact, --all, --sample, --top, --bottom, --shift-down, "
        "--shift-up");
  }
  if (const std::optional<ShiftSelection> shifts = f.shifts.Selection())
    return {ShiftTargets(base, *shifts), ToString(*shifts)};
  std::vector<PerturbationTarget> contacts = ContactTargets(base);
  if (f.all) return {contacts, "all"};
  if (f.sample) {
    if (*f.sample < 1) throw std::invalid_argument("--sample: need at least 1 contact");
    if (static_cast<std::size_t>(*f.sample) > contacts.size()) {
      throw std::invalid_argument("--sample " + std::to_string(*f.sample) +
                                  ": the packing has only " + std::to_string(contacts.size()) +
                                  " force-carrying contacts (--all opens every one)");
    }
    return {SampleTargets(contacts, *f.sample, f.seed),
            "sample " + std::to_string(*f.sample) + " seed " + std::to_string(f.seed)};
  }
  const int k = *f.contact;
  if (k < 0 || k >= static_cast<int>(contacts.size())) {
    throw std::invalid_argument("--contact " + std::to_string(k) + ": the packing has " +
                                std::to_string(contacts.size()) + " force-carrying contacts (0.." +
                                std::to_string(static_cast<int>(contacts.size()) - 1) + ")");
  }
  return {{contacts[k]}, "contact " + std::to_string(k)};
}

PerturbationOptions OptionsFrom(const PerturbFlags& f) {
  PerturbationOptions o;
  o.gap = f.gap;
  o.dt = f.dt;
  o.cell = CellConditionFromString(f.mode);
  o.backend = f.solver.backend;
  o.solver = f.solver.Resolve();
  o.response_tolerance = f.response_tol;
  o.check_linearity = f.check_linearity;
  o.check_by_continuation = !f.cold_check;
  o.nearest_member = f.member == "nearest";
  if (f.app != nullptr && f.app->count("--tol") > 0)
    o.solver_tolerance = f.solver.options.tolerance;
  Validate(o);
  return o;
}

// The backends' own options that change their answers.
void AddBackendOptions(const SolverOptions& o, nlohmann::json& header) {
  header["lemke_pivots_per_row"] = o.lemke.pivots_per_row;
  header["newton_iterations"] = o.newton.max_iterations;
  header["warmup_tol"] = o.newton.warmup_tolerance;
  header["ipopt_iterations"] = o.ipopt.max_iterations;
  header["nlopt_algorithm"] = ToString(o.nlopt.algorithm);
  header["nlopt_evaluations"] = o.nlopt.max_evaluations;
  header["convex_relaxation"] = o.de_saxce.convex_relaxation;
}

// Every parameter that changes a record: records of a run with another value of any of
// them are refused, naming it (RequireHeader).
nlohmann::json Header(const PerturbFlags& f, const Selection& s, const PerturbationOptions& o,
                      const PerturbationBase& base) {
  nlohmann::json header = {{"unjam_perturb_records", 2},
                           {"packing", std::filesystem::path(f.file).filename().string()},
                           {"packing_fnv1a", FileFingerprint(f.file)},
                           {"selection", s.description},
                           {"targets", s.targets.size()},
                           {"mode", ToString(o.cell)},
                           {"gap", o.gap},
                           {"dt", o.dt},
                           {"tolerance", SolverToleranceFor(o, base)},
                           {"backend", o.backend},
                           {"max_iterations", o.solver.nsgs.max_sweeps},  // --max-iter
                           {"relaxation", o.solver.nsgs.relaxation},
                           {"order", ToString(o.solver.nsgs.order)},
                           {"sweep_seed", o.solver.nsgs.seed},
                           {"check_linearity", o.check_linearity},
                           {"check_by_continuation", o.check_linearity && o.check_by_continuation},
                           {"fallback", o.fallback},
                           {"member", o.nearest_member ? "nearest" : "path"}};
  AddBackendOptions(o.solver, header);
  // A backend whose answers changed raises its revision (ContactSolver::AnswerRevision):
  // records of its earlier answers are not mixed with new ones.
  for (const std::string& name : {o.backend, o.fallback}) {
    if (name == "none" || name == "rate") continue;
    header["revision_" + name] = MakeSolver(name)->AnswerRevision();
  }
  return header;
}

constexpr const char* kOtherRun = "remove it or choose another --output directory";

// Every file a run writes in its output directory (the rank files of an mpirun aside).
const std::vector<std::string> kOutputFiles = {
    "records.jsonl", "perturbations.csv", "profile.csv",  "fcrit_histogram.csv",
    "field.csv",     "stress.csv",        "summary.json", "displacement.csv",
    "response.vtk",  "response.xyz",      ".lock"};

// One run per directory (docs/cli.md, "One run per output"): rank 0, or a run without MPI,
// locks DIR/.lock for the whole run; rank r > 0 of an mpirun locks DIR/.lock.rank<r>, beside
// the records file it alone writes, so that the ranks of one mpirun do not refuse each other.
std::filesystem::path LockPath(const std::filesystem::path& dir, int rank) {
  return RankPath(dir / ".lock", rank);
}

std::string TargetName(const PerturbationTarget& t) {
  if (t.kind == PerturbationTarget::Kind::kParticleShift) return Format("particle %d", t.i);
  return Format("contact %d-%d", t.i, t.j);
}

std::string PerturbationsCsv(const std::map<int, ReducedResponse>& records) {
  std::ostringstream os;
  os << "index,kind,i,j,image_x,image_y,x,y,axis_x,axis_y,f_reference,f_crit,penetration_depth,"
        "cell_strain,pressure_change,inertia_ratio,inertial_force,fcrit_10xi,linearity_misfit,"
        "equilibrium_residual,iterations,residual,status,rattler,seconds,backend\n";
  for (const auto& [k, r] : records) {
    const bool shift = r.target.kind == PerturbationTarget::Kind::kParticleShift;
    os << Format(
        "%d,%s,%d,%d,%d,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.6e,%.6e,%.17g,%."
        "6e,%.6e,%d,%.6e,%s,%d,%.4f,%s\n",
        k, shift ? "shift" : "opening", r.target.i, r.target.j, r.target.image[0],
        r.target.image[1], r.origin.x(), r.origin.y(), r.axis.x(), r.axis.y(), r.f_reference,
        r.f_crit, r.penetration_depth, r.cell_strain, r.pressure_change, r.inertia_ratio,
        r.inertial_force, r.fcrit_10xi, r.linearity_misfit, r.equilibrium_residual, r.iterations,
        r.residual, ToString(r.status), r.rattler ? 1 : 0, r.seconds, r.backend.c_str());
  }
  return os.str();
}

std::string ProfileCsv(const EnsembleSummary& s) {
  std::ostringstream os;
  os << "r_low,r_high,r,displacement_over_gap,displacement_error,displacement_samples,abs_force_"
        "change,force_change_error,force_samples,averaged_field_over_gap,averaged_field_error,"
        "averaged_field_boxes\n";
  for (std::size_t b = 0; b < s.displacement_profile.size(); ++b) {
    const LogBin& d = s.displacement_profile[b];
    const LogBin& f = s.force_profile[b];
    const LogBin& a = s.averaged_field_profile[b];
    os << Format("%.6g,%.6g,%.6g,%.10g,%.4g,%d,%.10g,%.4g,%d,%.10g,%.4g,%d\n", d.r_low, d.r_high,
                 d.r_mean, d.mean, d.error, d.count, f.mean, f.error, f.count, a.mean, a.error,
                 a.count);
  }
  return os.str();
}

std::string HistogramCsv(const EnsembleSummary& s) {
  std::ostringstream os;
  os << "scale,bin_low,bin_high,count,density\n";
  auto emit = [&](const char* name, const Histogram& h) {
    const int n = static_cast<int>(h.counts.size());
    for (int b = 0; b < n; ++b) {
      const double w = (h.high - h.low) / n;
      os << Format("%s,%.8g,%.8g,%d,%.8g\n", name, h.low + b * w, h.low + (b + 1) * w, h.counts[b],
                   h.density[b]);
    }
  };
  emit("raw", s.fcrit_raw);
  emit("over_f0", s.fcrit_over_f0);
  emit("over_mean", s.fcrit_over_mean);
  return os.str();
}

std::string FieldCsv(const EnsembleSummary& s) {
  std::ostringstream os;
  os << "x,y,dx_over_gap,dy_over_gap,samples\n";
  for (const FieldBox& b : s.field) {
    os << Format("%.6g,%.6g,%.10g,%.10g,%d\n", b.center.x(), b.center.y(), b.mean.x(), b.mean.y(),
                 b.count);
  }
  return os.str();
}

std::string StressCsv(const EnsembleSummary& s) {
  std::ostringstream os;
  os << "x,y,dsigma_xx,dsigma_xy,dsigma_yy,pressure_change,max_shear,shear_angle,sigma_xx_after,"
        "sigma_xy_after,sigma_yy_after,pressure_after,shear_angle_after\n";
  for (const StressBox& b : s.stress) {
    os << Format("%.6g,%.6g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n",
                 b.center.x(), b.center.y(), b.mean(0, 0), b.mean(0, 1), b.mean(1, 1),
                 b.pressure_change, b.max_shear, b.shear_angle, b.after(0, 0), b.after(0, 1),
                 b.after(1, 1), b.pressure_after, b.shear_angle_after);
  }
  return os.str();
}

std::string DisplacementCsv(const PerturbationBase& base, const PerturbationResult& r) {
  std::ostringstream os;
  os << "particle,x,y,radius,dx,dy,rotation\n";
  for (std::size_t i = 0; i < r.displacement.size(); ++i) {
    const Particle& p = base.scene.particles[i];
    os << Format("%zu,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", i, p.position.x(), p.position.y(),
                 p.radius, r.displacement[i].x(), r.displacement[i].y(), r.rotation[i]);
  }
  return os.str();
}

}  // namespace

void WriteFullField(const std::filesystem::path& dir, const PerturbationBase& base,
                    const PerturbationResult& r) {
  WriteFileAtomically(dir / "displacement.csv", DisplacementCsv(base, r));
  ParticleField field;
  field.displacement = r.displacement;
  for (const ContactForceChange& c : r.force_changes) {
    if (c.normal_after != 0.0 || c.tangential_after != 0.0)
      field.forces.push_back({c.i, c.j, c.image, c.normal_after, c.tangential_after});
    field.force_change.push_back({c.i, c.j, c.image, c.normal_after - c.normal_before,
                                  c.tangential_after - c.tangential_before});
  }
  WriteVtk(base.scene, field, dir / "response.vtk");
  WriteExtendedXyz(base.scene, field, dir / "response.xyz");
}

namespace {

// A mean over no sample is no number.
nlohmann::json MeanOrNull(const MeanAndError& m) {
  return m.count > 0 ? NumberOrNull(m.mean) : nlohmann::json(nullptr);
}
nlohmann::json ErrorOrNull(const MeanAndError& m) {
  return m.count > 1 ? NumberOrNull(m.error) : nlohmann::json(nullptr);
}
// A mean (and its error) over a fixed positive denominator.
nlohmann::json RatioOrNull(const MeanAndError& m, double denominator) {
  return m.count > 0 && denominator > 0.0 ? NumberOrNull(m.mean / denominator)
                                          : nlohmann::json(nullptr);
}
nlohmann::json RatioErrorOrNull(const MeanAndError& m, double denominator) {
  return m.count > 1 && denominator > 0.0 ? NumberOrNull(m.error / denominator)
                                          : nlohmann::json(nullptr);
}

nlohmann::json SummaryJson(const PerturbFlags& f, const Selection& sel,
                           const PerturbationOptions& o, const PerturbationBase& base,
                           const EnsembleSummary& s, double seconds) {
  const bool shift = sel.Shifts();
  nlohmann::json j = {
      {"file", f.file},
      {"selection", sel.description},
      {"mode", shift                              ? "shift"
               : base.scene.effects.pressure_bath ? ToString(o.cell)
                                                  : "fixed-cell"},
      {"gap", o.gap},
      {"dt", o.dt},
      {"tolerance", SolverToleranceFor(o, base)},
      {"backend", o.backend},
      {"fallback", o.fallback},
      {"check_linearity", o.check_linearity},
      {"check_by_continuation", o.check_linearity && o.check_by_continuation},
      {"member", o.nearest_member ? "nearest" : "path"},
      {"perturbations", s.perturbations},
      {"used", s.used},
      {"not_converged", s.not_converged},
      {"dynamic", s.dynamic},
      {"nonlinear", s.nonlinear},
      {"blocked", s.blocked},
      {"rattlers", s.rattlers},
      {"mean_fcrit", MeanOrNull(s.f_crit)},
      {"mean_fcrit_error", ErrorOrNull(s.f_crit)},
      {"mean_fcont", shift ? nlohmann::json(base.mean_contact_force) : MeanOrNull(s.f_reference)},
      {"reference", shift ? "F_y (effective weight)" : "F_cont"},
      {"mean_freference", MeanOrNull(s.f_reference)},
      {"ratio_fcrit_freference", NumberOrNull(s.ratio)},
      {"ratio_error", NumberOrNull(s.ratio_error)},
      // The paper's ratio for openings: ⟨F_crit⟩ of the used openings over ⟨F_cont⟩ of
      // every force-carrying contact of the packing, not only of the opened ones.
      {"mean_fcont_all", base.mean_contact_force},
      {"ratio_fcrit_fcont_all", shift ? nullptr : RatioOrNull(s.f_crit, base.mean_contact_force)},
      {"ratio_fcrit_fcont_all_error",
       shift ? nullptr : RatioErrorOrNull(s.f_crit, base.mean_contact_force)},
      {"f0", s.f0},
      {"mean_delta", MeanOrNull(s.penetration_depth)},
      {"mean_delta_error", ErrorOrNull(s.penetration_depth)},
      {"alpha", NumberOrNull(s.decay.alpha)},
      {"alpha_error", NumberOrNull(s.decay.alpha_error)},
      {"alpha_fit_range", {s.decay.fit_min, s.decay.fit_max}},
      {"alpha_fit_points", s.decay.points},
      {"alpha_mean_magnitude", NumberOrNull(s.magnitude_decay.alpha)},
      {"alpha_mean_magnitude_error", NumberOrNull(s.magnitude_decay.alpha_error)},
      {"fcrit_tail_scale", s.fcrit_tail.count > 0 ? NumberOrNull(s.fcrit_tail.scale) : nullptr},
      {"fcrit_tail_scale_error",
       s.fcrit_tail.count > 0 ? NumberOrNull(s.fcrit_tail.scale_error) : nullptr},
      {"fcrit_tail_samples", s.fcrit_tail.count},
      {"corr_fcrit_delta", s.corr_fcrit_delta},
      {"corr_fcont_delta", s.corr_freference_delta},
      {"corr_fcrit_fcont", s.corr_fcrit_freference},
      {"seconds", seconds}};
  if (!f.output_dir.empty()) j["output"] = f.output_dir;
  return j;
}

void PrintSummary(const nlohmann::json& j) {
  auto num = [&](const char* key) {
    return j[key].is_null() ? std::string("n/a") : Format("%.6g", j[key].get<double>());
  };
  std::printf(
      "perturbations      %d (used %d, not converged %d, dynamic %d, nonlinear %d, blocked %d, "
      "rattlers %d)\n",
      j["perturbations"].get<int>(), j["used"].get<int>(), j["not_converged"].get<int>(),
      j["dynamic"].get<int>(), j["nonlinear"].get<int>(), j["blocked"].get<int>(),
      j["rattlers"].get<int>());
  if (!j["complete"].get<bool>())
    std::printf("incomplete         %d of %d targets done\n", j["perturbations"].get<int>(),
                j["targets"].get<int>());
  std::printf("mode               %s, gap %.3g, dt %.3g, tolerance %.3g (%s)\n",
              j["mode"].get<std::string>().c_str(), j["gap"].get<double>(), j["dt"].get<double>(),
              j["tolerance"].get<double>(), j["backend"].get<std::string>().c_str());
  std::printf("<F_crit>           %s +- %s\n", num("mean_fcrit").c_str(),
              num("mean_fcrit_error").c_str());
  std::printf("<reference>        %s  (%s)\n", num("mean_freference").c_str(),
              j["reference"].get<std::string>().c_str());
  std::printf("<F_crit>/<ref>     %s +- %s\n", num("ratio_fcrit_freference").c_str(),
              num("ratio_error").c_str());
  if (!j["ratio_fcrit_fcont_all"].is_null()) {
    std::printf("  over all F_cont  %s +- %s (<F_cont> of every contact, %d openings used)\n",
                num("ratio_fcrit_fcont_all").c_str(), num("ratio_fcrit_fcont_all_error").c_str(),
                j["used"].get<int>());
  }
  std::printf("<delta>            %s +- %s\n", num("mean_delta").c_str(),
              num("mean_delta_error").c_str());
  std::printf("decay alpha        %s +- %s (|<d>|(r) ~ r^-alpha, the averaged field; %d bins)\n",
              num("alpha").c_str(), num("alpha_error").c_str(), j["alpha_fit_points"].get<int>());
  std::printf("  of mean |d|      %s +- %s\n", num("alpha_mean_magnitude").c_str(),
              num("alpha_mean_magnitude_error").c_str());
  std::printf("seconds            %.3f\n", j["seconds"].get<double>());
}

// The full fields of perturbation 0 (WriteFullField), written before its record: a record
// without them (a run stopped or failed in between, before they came first; or files
// removed since) leaves them to the next run.
const std::vector<std::string> kFullFieldFiles = {"displacement.csv", "response.vtk",
                                                  "response.xyz"};

bool FullFieldMissing(const std::filesystem::path& dir) {
  for (const std::string& name : kFullFieldFiles) {
    if (!std::filesystem::exists(dir / name)) return true;
  }
  return false;
}

// The targets not yet recorded, with their indices in the selection, and perturbation 0
// again where only its fields are missing (`refill_first`). Under mpirun rank r owns the
// targets k = r mod ranks, by the selection alone, so that the ranks need not agree on what
// is recorded (each reads the others' files while they are written).
struct PendingTargets {
  std::vector<PerturbationTarget> targets;
  std::vector<int> index;
};

PendingTargets Pending(const Selection& selection, const std::map<int, ReducedResponse>& records,
                       bool refill_first, int rank, int ranks) {
  PendingTargets pending;
  for (int k = 0; k < static_cast<int>(selection.targets.size()); ++k) {
    const bool done = records.count(k) > 0 && !(k == 0 && refill_first);
    if (done || k % ranks != rank) continue;
    pending.targets.push_back(selection.targets[k]);
    pending.index.push_back(k);
  }
  return pending;
}

void PrintProgress(const PerturbationResult& r, int done, int total, int rank, int ranks) {
  const std::string who = ranks > 1 ? Format("perturb rank %d [%d/%d]", rank, done, total)
                                    : Format("perturb [%d/%d]", done, total);
  std::fprintf(
      stderr, "%s %s: F_crit %.6g (ref %.6g) delta %.4g %s, %d it, residual %.2e, %.2f s\n",
      who.c_str(), TargetName(r.target).c_str(), r.f_crit, r.f_reference, r.penetration_depth,
      ToString(r.status), r.solve.iterations, r.solve.residual, r.seconds);
  if (!r.resolved)
    std::fprintf(stderr, "  %s: %s\n", r.solve.backend.c_str(), r.solve.message.c_str());
}

void WriteEnsembleFiles(const std::filesystem::path& dir,
                        const std::map<int, ReducedResponse>& records,
                        const EnsembleSummary& summary, const nlohmann::json& out) {
  WriteFileAtomically(dir / "perturbations.csv", PerturbationsCsv(records));
  WriteFileAtomically(dir / "profile.csv", ProfileCsv(summary));
  WriteFileAtomically(dir / "fcrit_histogram.csv", HistogramCsv(summary));
  WriteFileAtomically(dir / "field.csv", FieldCsv(summary));
  WriteFileAtomically(dir / "stress.csv", StressCsv(summary));
  WriteFileAtomically(dir / "summary.json", out.dump(2) + "\n");
}

// Says on stderr which perturbations have no usable response, and where `auto` left lemke
// out for the packing's size only, how to resolve them; the exit code.
int ReportUnusable(const EnsembleSummary& summary, bool lemke_left_for_size,
                   bool require_converged) {
  const int failed = summary.not_converged + summary.dynamic + summary.nonlinear + summary.blocked;
  if (failed == 0) return kOk;
  std::fprintf(stderr,
               "unjam perturb: %d of %d perturbations have no usable response (not converged: %d, "
               "dynamic: %d, nonlinear: %d, blocked: %d)\n",
               failed, summary.perturbations, summary.not_converged, summary.dynamic,
               summary.nonlinear, summary.blocked);
  if (summary.not_converged > 0 && lemke_left_for_size) {
    std::fprintf(
        stderr,
        "  (auto gave this packing of more than %zu contacts to newton, which stalls on "
        "quasi-static frictional "
        "responses; lemke resolves them exactly, at minutes to an hour each: --backend lemke "
        "--max-iter 3000000; docs/perturbations.md, \"Which backend `auto` picks\")\n",
        kLemkeAutoContacts);
  }
  return require_converged ? kNotConverged : kOk;
}

}  // namespace

int RunPerturb(const PerturbFlags& f) {
  const auto start = Clock::now();
  RefuseOutputDirectoryOverInput("-o", f.output_dir, kOutputFiles, {f.file});
  if (f.time_limit && !(std::isfinite(*f.time_limit) && *f.time_limit >= 0.0)) {
    throw std::invalid_argument("--time-limit must be a finite number of seconds >= 0, got " +
                                Format("%g", *f.time_limit));
  }
  PerturbationOptions options = OptionsFrom(f);
  const Scene scene = ReadPacking(f.file);
  const bool lemke_left_for_size =
      AutoLeavesLemkeForSize(options, scene);  // before "auto" is resolved
  ResolveBackends(options, scene);
  if (scene.forces.empty()) {
    throw InputError(f.file, 0,
                     "stores no static forces: run `unjam solve " + f.file + " -o FILE` first");
  }
  const PerturbationBase base = PreparePerturbations(scene, options);
  const Selection selection = SelectTargets(f, base);
  const EnsembleOptions ensemble;
  const ResponseLayout layout = MakeLayout(base, ensemble, options.gap);

  MpiSession* mpi = CurrentMpiSession();
  const int rank = mpi != nullptr ? mpi->rank() : 0, ranks = mpi != nullptr ? mpi->size() : 1;
  if (ranks > 1 && f.output_dir.empty()) {
    throw std::invalid_argument(
        "under mpirun, -o DIR is needed: the ranks share their records there");
  }
  const std::filesystem::path dir = f.output_dir;
  const nlohmann::json header = Header(f, selection, options, base);
  std::map<int, ReducedResponse> records;
  std::optional<RunRecords> run;   // -o DIR: the records, this rank's appended as they come
  std::optional<OutputLock> lock;  // held until every output is written
  if (!f.output_dir.empty()) {
    std::filesystem::create_directories(dir);
    lock.emplace(LockPath(dir, rank), dir.string());
    run.emplace(dir / "records.jsonl", header, rank, kOtherRun);
    records = RecordsByIndex(run->Entries());
  }
  const bool refill_first = run.has_value() && records.count(0) > 0 && FullFieldMissing(dir);
  const PendingTargets pending = Pending(selection, records, refill_first, rank, ranks);
  if (!f.quiet && !records.empty())
    std::fprintf(stderr, "perturb: resuming, %zu of %zu done\n", records.size(),
                 selection.targets.size());
  if (!f.quiet && refill_first && rank == 0) {
    std::fprintf(stderr,
                 "perturb: perturbation 0 is recorded without its fields (displacement.csv, "
                 "response.vtk, response.xyz): solving it again for them\n");
  }
  PerturbSchedule schedule;
  schedule.threads = ThreadsFromOption(f.threads);
  schedule.as_finished = true;  // each record written as soon as it exists
  if (f.time_limit)
    schedule.start_before = start + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(*f.time_limit));
  const int total = static_cast<int>(selection.targets.size());
  PerturbAll(base, pending.targets, options, schedule, [&](int t, const PerturbationResult& r) {
    const int k = pending.index[t];
    // The fields first, each file atomically: once perturbation 0 is recorded, a rerun
    // solves it again only if they are missing.
    if (run && k == 0) WriteFullField(dir, base, r);
    if (records.count(k) > 0) return;  // solved again for its fields alone
    ReducedResponse record = Reduce(base, r, layout, ensemble);
    if (run) {
      nlohmann::json line = ToJson(record);
      line["index"] = k;
      run->Append(line);
    }
    if (!f.quiet) PrintProgress(r, static_cast<int>(records.size()) + 1, total, rank, ranks);
    records.emplace(k, std::move(record));
  });
  if (run) run->Close();
  if (ranks > 1) {
    // Every rank's share is recorded (or a rank failed: then all end with its code).
    const int worst = mpi->WorstStatus(kOk);
    if (worst != kOk || rank != 0) return worst;
  }
  if (run && run->HasRankFiles()) {
    run->Merge();
    records = RecordsByIndex(run->Entries());
  }
  std::vector<ReducedResponse> ordered;
  for (const auto& [k, r] : records) ordered.push_back(r);
  const EnsembleSummary summary = Summarize(ordered, layout, ensemble, &base);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  nlohmann::json out = SummaryJson(f, selection, options, base, summary, seconds);
  out["targets"] = total;
  out["complete"] = static_cast<int>(records.size()) == total;
  if (!f.output_dir.empty()) WriteEnsembleFiles(dir, records, summary, out);
  if (f.summary && f.json) std::printf("%s\n", out.dump().c_str());
  else if (f.summary) PrintSummary(out);
  if (!out["complete"].get<bool>() && !f.quiet) {
    std::fprintf(stderr,
                 "perturb: stopped at the time limit with %zu of %d done; the same command "
                 "continues from %s\n",
                 records.size(), total, (dir / "records.jsonl").string().c_str());
  }
  return ReportUnusable(summary, lemke_left_for_size, f.solver.require_converged);
}

}  // namespace unjam::cli
