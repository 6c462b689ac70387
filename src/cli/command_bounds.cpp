// `unjam bounds FILE [--contacts all|K,K,...] [--lp clp] [--compare-perturb] ...`
#include "command_bounds.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include "bounds_records.hpp"
#include "mpi_session.hpp"
#include "output_paths.hpp"
#include "unjam/indeterminacy/force_bounds.hpp"
#include "unjam/io/json_lines.hpp"
#include "unjam/io/output_lock.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/perturbation.hpp"

namespace unjam::cli {

void BoundsFlags::Register(CLI::App& a) {
  a.add_option("FILE", file,
               "static packing (.unjam); its stored forces are shown beside the bounds")
      ->required();
  CLI::Option* contacts_option =
      a.add_option("--contacts", contacts,
                   "all, or K,K,... (the K-th force-carrying contact in the file's force order)")
          ->capture_default_str();
  CLI::Option* top_option = a.add_flag(
      "--top", shifts.top,
      "instead of contacts, bound the critical force of each top shift of a pile (the particles "
      "`unjam perturb --top` pushes down): min and max of F_crit over the admissible networks");
  CLI::Option* bottom_option =
      a.add_flag("--bottom", shifts.bottom,
                 "the same for the bottom shifts (`unjam perturb --bottom`, pushed up)");
  CLI::Option* down_option =
      a.add_option("--shift-down", shifts.down,
                   "the same for particle P alone, pushed down (`unjam perturb --shift-down P`)");
  CLI::Option* up_option =
      a.add_option("--shift-up", shifts.up,
                   "the same for particle P alone, pushed up (`unjam perturb --shift-up P`)");
  const std::vector<CLI::Option*> selections = {contacts_option, top_option, bottom_option,
                                                down_option, up_option};
  for (std::size_t i = 0; i < selections.size(); ++i) {
    for (std::size_t j = i + 1; j < selections.size(); ++j) selections[i]->excludes(selections[j]);
  }
  a.add_option("--lp", lp,
               "linear-program backend: clp (simplex, warm starts) or ipopt (interior point)")
      ->capture_default_str();
  a.add_flag("--cold", cold, "solve every LP from scratch (no warm start; for comparison)");
  a.add_flag("--compare-perturb", compare_perturb,
             "also open each contact (or make each shift) with unjam perturb and compare F_crit "
             "with the LP interval");
  a.add_option("--mode", mode,
               "cell condition of --compare-perturb: fixed-pressure or fixed-volume")
      ->capture_default_str();
  a.add_option("--gap-tol", gap_tolerance,
               "contacts with a gap up to this are contacts of the ensemble")
      ->capture_default_str();
  a.add_option("--threads", threads, "threads (0: all cores)")
      ->check(cli::NonNegative())
      ->capture_default_str();
  CLI::Option* output_option =
      a.add_option("-o,--output", output,
                   "CSV file, one row per contact; the bounds are recorded in OUTPUT.records.jsonl "
                   "as they come, and a rerun resumes from it");
  CLI::Option* limit_option =
      a.add_option("--time-limit", time_limit,
                   "start no LP after S seconds of this run; the bounds so far stay in "
                   "OUTPUT.records.jsonl and the same command continues (contacts only)")
          ->needs(output_option);
  for (CLI::Option* shifts : {top_option, bottom_option, down_option, up_option})
    limit_option->excludes(shifts);
  a.add_flag("--json", json, "one JSON object on stdout");
  a.add_flag("--quiet", quiet, "no progress on stderr");
}

EquilibriumSystemOptions BoundsFlags::SystemOptions() const {
  if (!(gap_tolerance >= 0.0)) throw std::invalid_argument("--gap-tol must be >= 0");
  EquilibriumSystemOptions so;
  so.closed_gap_tolerance = gap_tolerance;
  so.margin = std::max(so.margin, gap_tolerance);
  return so;
}

namespace {

using Clock = std::chrono::steady_clock;

// System contact indices of the selection: every contact of the ensemble, or the K-th
// force-carrying contacts of the file (the numbering of `unjam perturb --contact K`).
std::vector<int> SelectContacts(const std::string& spec, const Scene& scene,
                                const EquilibriumSystem& s) {
  std::vector<int> out;
  if (spec == "all") {
    for (int k = 0; k < static_cast<int>(s.contacts.size()); ++k) out.push_back(k);
    return out;
  }
  const std::vector<ContactForce> carrying = ForceCarryingPairs(scene);
  std::stringstream list(spec);
  std::string item;
  while (std::getline(list, item, ',')) {
    std::size_t used = 0;
    int k = -1;
    try {
      k = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || item.empty())
      throw std::invalid_argument("--contacts: '" + item +
                                  "' is not a contact number (use all, or K,K,...)");
    if (k < 0 || k >= static_cast<int>(carrying.size())) {
      throw std::invalid_argument("--contacts: " + item + " is out of range (the packing has " +
                                  std::to_string(carrying.size()) + " force-carrying contacts)");
    }
    const int index = FindContact(s.contacts, carrying[k].i, carrying[k].j, carrying[k].image);
    if (index < 0)
      throw std::invalid_argument("--contacts: contact " + item + " has a gap above --gap-tol");
    if (std::find(out.begin(), out.end(), index) != out.end()) {
      throw std::invalid_argument("--contacts: contact " + item + " is listed twice");
    }
    out.push_back(index);
  }
  return out;
}

struct Comparison {
  std::vector<double> f_crit;  // NaN where the perturbation has no usable response
  std::vector<PerturbationStatus> status;
  // Per contact: 1 if the quasi-static F_crit lies in [LP min, LP max without friction],
  // 0 if not, −1 where that does not apply (no quasi-static F_crit, or no such interval).
  std::vector<int> inside;
  int used = 0;
  double mean_rel_diff = std::nan(""), max_rel_diff = std::nan("");
  int WithStatus(PerturbationStatus s) const {
    return static_cast<int>(std::count(status.begin(), status.end(), s));
  }
  int WithInside(int value) const {
    return static_cast<int>(std::count(inside.begin(), inside.end(), value));
  }
};

// A static opening is held by a network in which the opened contact carries no tangential
// force, so its F_crit must lie in [min, max without friction] (docs/indeterminacy.md,
// "Comparison with simulation"). −1: no quasi-static F_crit, or the pure-opening LP has no
// optimum (then a quasi-static F_crit is outside by definition: 0).
int InsideInterval(const ContactBounds& b, const PerturbationResult& r) {
  if (!r.ok()) return -1;
  if (!b.min.ok() || !b.max_without_friction.ok()) return 0;
  // Both sides carry the LP's and the perturbation's tolerances, about 1e-6 relative, and
  // F_crit its inertial part (a frictionless opening's F_crit is F_cont plus exactly that).
  const double tol =
      1e-6 * (std::abs(b.max_without_friction.value) + b.reference) + r.inertial_force;
  return r.f_crit >= b.min.value - tol && r.f_crit <= b.max_without_friction.value + tol ? 1 : 0;
}

Comparison ComparePerturbations(const Scene& scene, const EquilibriumSystem& s,
                                const BoundsReport& report, const BoundsFlags& f, int threads) {
  PerturbationOptions o;
  o.cell = CellConditionFromString(f.mode);
  const PerturbationBase base = PreparePerturbations(scene, o);
  std::vector<PerturbationTarget> targets;
  for (const ContactBounds& b : report.bounds) {
    const Contact& c = s.contacts[b.contact];
    PerturbationTarget t;
    t.i = c.i;
    t.j = c.j;
    t.image = c.image;
    targets.push_back(t);
  }
  Comparison out;
  out.f_crit.assign(targets.size(), std::nan(""));
  out.status.assign(targets.size(), PerturbationStatus::kNotConverged);
  out.inside.assign(targets.size(), -1);
  double sum = 0.0, worst = 0.0;
  PerturbAll(base, targets, o, threads, [&](int k, const PerturbationResult& r) {
    out.status[k] = r.status;
    out.inside[k] = InsideInterval(report.bounds[k], r);
    if (!r.ok()) return;
    out.f_crit[k] = r.f_crit;
    const Bound& max = report.bounds[k].max;
    if (!max.ok() || max.value == 0.0) return;
    const double rel = std::abs(r.f_crit - max.value) / std::abs(max.value);
    sum += rel;
    worst = std::max(worst, rel);
    ++out.used;
  });
  if (out.used > 0) {
    out.mean_rel_diff = sum / out.used;
    out.max_rel_diff = worst;
  }
  return out;
}

std::string Number(const Bound& b) { return b.ok() ? ExactNumber(b.value) : ""; }

std::string Csv(const EquilibriumSystem& s, const BoundsReport& r, const Comparison* cmp) {
  std::ostringstream os;
  os << "contact,i,j,image_x,image_y,f_cont,min,max,max_without_friction,status_min,status_max,"
        "status_without_friction";
  if (cmp) os << ",f_crit,perturbation_status,inside_interval";
  os << "\n";
  for (std::size_t a = 0; a < r.bounds.size(); ++a) {
    const ContactBounds& b = r.bounds[a];
    const Contact& c = s.contacts[b.contact];
    os << b.contact << ',' << c.i << ',' << c.j << ',' << c.image[0] << ',' << c.image[1] << ','
       << ExactNumber(b.reference) << ',' << Number(b.min) << ',' << Number(b.max) << ','
       << Number(b.max_without_friction) << ',' << ToString(b.min.status) << ','
       << ToString(b.max.status) << ',' << ToString(b.max_without_friction.status);
    if (cmp) {
      os << ',' << ExactNumber(cmp->f_crit[a]) << ',' << ToString(cmp->status[a]) << ','
         << (cmp->inside[a] < 0 ? "" : std::to_string(cmp->inside[a]));
    }
    os << "\n";
  }
  return os.str();
}

// The bounds a run over `selected` contacts obtains (and records): max, max without friction
// and min of each; a frictionless packing's max without friction is its max, not recorded.
long long BoundsTotal(const EquilibriumSystem& s, std::size_t selected) {
  return static_cast<long long>(selected) * (s.frictional ? 3 : 2);
}

// Progress of a long run on stderr, at most every 30 s: how many of the selection's bounds
// are obtained and, on one process, about how long the rest will take at this run's pace.
class BoundsProgress {
 public:
  BoundsProgress(long long total, long long known, int rank, int ranks, bool quiet)
      : total_(total), obtained_(known), rank_(rank), ranks_(ranks), quiet_(quiet),
        start_(Clock::now()), last_(start_) {}
  void Add() {
    ++obtained_;
    ++this_run_;
    const auto now = Clock::now();
    if (quiet_ || now - last_ < std::chrono::seconds(30)) return;
    last_ = now;
    const double seconds = std::chrono::duration<double>(now - start_).count();
    if (ranks_ > 1) {
      std::fprintf(stderr, "bounds rank %d: %lld bounds in %.0f s\n", rank_, this_run_, seconds);
      return;
    }
    std::fprintf(
        stderr, "bounds: %lld of %lld (%.1f %%) in %.0f s, about %.0f s to go\n", obtained_, total_,
        100.0 * static_cast<double>(obtained_) / static_cast<double>(total_), seconds,
        seconds / static_cast<double>(this_run_) * static_cast<double>(total_ - obtained_));
  }

 private:
  long long total_, obtained_, this_run_ = 0;
  int rank_, ranks_;
  bool quiet_;
  Clock::time_point start_, last_;
};

// --time-limit ended the run before every bound was obtained: no CSV; what was obtained is
// in the records, from which the same command continues.
int StoppedAtTimeLimit(const BoundsFlags& f, const EquilibriumSystem& s, std::size_t selected,
                       long long lp_iterations, double lp_seconds, const BoundsRecords& records,
                       Clock::time_point start) {
  const long long total = BoundsTotal(s, selected);
  const long long obtained = records.Obtained();
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (f.summary && f.json) {
    const nlohmann::json out = {{"file", f.file},
                                {"contacts", selected},
                                {"ensemble_contacts", s.contacts.size()},
                                {"complete", false},
                                {"bounds_obtained", obtained},
                                {"bounds_total", total},
                                {"records", records.Path().string()},
                                {"lp_iterations", lp_iterations},
                                {"lp_seconds", lp_seconds},
                                {"seconds", seconds}};
    std::printf("%s\n", out.dump().c_str());
  } else if (f.summary) {
    std::printf("contacts           %zu of %zu in the ensemble\n", selected, s.contacts.size());
    std::printf("incomplete         %lld of %lld bounds obtained\n", obtained, total);
    std::printf("seconds            %.3f (LPs %.3f, %lld simplex iterations)\n", seconds,
                lp_seconds, lp_iterations);
  }
  if (!f.quiet) {
    std::fprintf(stderr,
                 "bounds: stopped at the time limit with %lld of %lld bounds; the same command "
                 "continues from %s\n",
                 obtained, total, records.Path().string().c_str());
  }
  return kOk;
}

BoundsOptions BoundsOptionsFrom(const BoundsFlags& f, LpBackend lp, int threads,
                                Clock::time_point start) {
  BoundsOptions bo;
  bo.warm_start = !f.cold;
  bo.lp = lp;
  bo.threads = threads;
  if (f.time_limit) {
    if (!(std::isfinite(*f.time_limit) && *f.time_limit >= 0.0)) {
      throw std::invalid_argument("--time-limit must be a finite number of seconds >= 0, got " +
                                  Format("%g", *f.time_limit));
    }
    bo.start_before = start + std::chrono::duration_cast<Clock::duration>(
                                  std::chrono::duration<double>(*f.time_limit));
  }
  return bo;
}

// Rank 0 of an mpirun, once every rank is done: the ranks' records merged, and the report
// made from them alone, without an LP (a bound that no rank obtained in its time leaves
// the report incomplete).
BoundsReport GatherRanks(const EquilibriumSystem& system, const std::vector<int>& selected,
                         const Eigen::VectorXd& stored, BoundsRecords& records) {
  records.Merge();
  return BoundsFromRecords(system, selected, stored, records.Known());
}

// What the bounds of a run add up to, for its summary.
struct BoundsTally {
  double width_sum = 0.0, reference_sum = 0.0;
  int widths = 0, failed = 0, references = 0, no_pure_opening = 0;
};

BoundsTally Tally(const BoundsReport& report) {
  BoundsTally t;
  for (const ContactBounds& b : report.bounds) {
    if (b.reference > 0.0) {
      t.reference_sum += b.reference;
      ++t.references;
    }
    if (b.max_without_friction.status == BoundStatus::kInfeasible && report.feasible)
      ++t.no_pure_opening;
    if (b.min.ok() && b.max.ok()) {
      t.width_sum += b.max.value - b.min.value;
      ++t.widths;
    } else {
      ++t.failed;
    }
  }
  return t;
}

// The text summary, from the JSON one (a null number, a mean over nothing, prints as nan).
void PrintBoundsSummary(const nlohmann::json& j, double gap_tolerance, const char* lp_kind) {
  auto num = [&](const char* key) {
    return j[key].is_null() ? std::nan("") : j[key].get<double>();
  };
  auto integer = [&](const char* key) { return j[key].get<int>(); };
  const std::string message = j["message"].get<std::string>();
  std::printf("contacts           %zu of %zu in the ensemble (gap <= %.3g)\n",
              j["contacts"].get<std::size_t>(), j["ensemble_contacts"].get<std::size_t>(),
              gap_tolerance);
  std::printf("ensemble           %s%s%s\n", j["feasible"].get<bool>() ? "feasible" : "INFEASIBLE",
              message.empty() ? "" : ": ", message.c_str());
  std::printf("indeterminacy      %d (unknowns %d, rank %d, tolerance %.2e)\n",
              integer("indeterminacy_dimension"), integer("unknowns"), integer("rank"),
              num("rank_tolerance"));
  if (integer("rank_qr_transpose") != integer("rank_qr_a")) {
    std::printf("                   (QR estimates of the rank: %d from A, %d from its transpose)\n",
                integer("rank_qr_a"), integer("rank_qr_transpose"));
  }
  if (integer("bounded_contacts") > 0) {
    std::printf("mean width         %.6g (max - min of f_n, %d contacts; %d unbounded or failed)\n",
                num("mean_width"), integer("bounded_contacts"), integer("unbounded_or_failed"));
  }
  if (j.contains("compared")) {
    std::printf("F_crit vs LP max   %d compared, mean |rel diff| %.3g, max %.3g\n",
                integer("compared"), num("mean_rel_diff_fcrit"), num("max_rel_diff_fcrit"));
    std::printf(
        "openings           %d quasi-static (%d inside [LP min, LP max without friction], %d "
        "outside), %d dynamic\n",
        integer("quasi_static"), integer("inside_interval"), integer("outside_interval"),
        integer("dynamic"));
  }
  std::printf("seconds            %.3f (LPs %.3f, %lld simplex iterations, %s)\n", num("seconds"),
              num("lp_seconds"), j["lp_iterations"].get<long long>(), lp_kind);
}

}  // namespace

int RunBounds(const BoundsFlags& f) {
  RefuseOutputOverInput("-o", f.output, {f.file});
  if (f.Shifts()) return RunShiftBounds(f);
  const auto start = Clock::now();
  const LpBackend lp = LpBackendFromString(f.lp);
  const EquilibriumSystemOptions so = f.SystemOptions();
  CellConditionFromString(f.mode);
  const Scene scene = ReadPacking(f.file);
  if (f.compare_perturb && scene.forces.empty()) {
    throw InputError(
        f.file, 0,
        "stores no static forces, which --compare-perturb starts from: run `unjam solve " + f.file +
            " -o FILE` first");
  }
  const EquilibriumSystem system = BuildEquilibriumSystem(scene, so);
  const std::vector<int> selected = SelectContacts(f.contacts, scene, system);
  const int threads = ThreadsFromOption(f.threads);
  BoundsOptions bo = BoundsOptionsFrom(f, lp, threads, start);
  MpiSession* mpi = CurrentMpiSession();
  const int rank = mpi != nullptr ? mpi->rank() : 0, ranks = mpi != nullptr ? mpi->size() : 1;
  if (ranks > 1 && f.output.empty())
    throw std::invalid_argument(
        "under mpirun, -o FILE is needed: the ranks share their records beside it");
  bo.shares = ranks;
  bo.share = rank;
  // One run per output (docs/cli.md, "One run per output"): FILE.lock for rank 0, or a run
  // without MPI, held until the CSV is written; FILE.rank<r>.lock for rank r > 0 of an
  // mpirun, beside the records file it alone writes.
  std::optional<OutputLock> lock;
  std::optional<BoundsRecords> records;
  if (!f.output.empty()) {
    lock.emplace(RankPath(f.output + ".lock", rank), f.output);
    records.emplace(f, system, selected.size(), bo, rank);
    bo.known = records->Known();
    if (!bo.known.empty() && rank == 0 && !f.quiet)
      std::fprintf(stderr, "bounds: resuming, %zu bounds recorded in %s\n", bo.known.size(),
                   records->Path().string().c_str());
  }
  BoundsProgress progress(BoundsTotal(system, selected.size()),
                          static_cast<long long>(bo.known.size()), rank, ranks, f.quiet);
  bo.on_bound = [&](const BoundRecord& r) {
    if (records) records->Add(r);
    progress.Add();
  };
  const Eigen::VectorXd stored = StoredForcesOf(system, scene.forces);
  BoundsReport report = ComputeForceBounds(system, selected, stored, bo);
  long long lp_iterations = report.lp_iterations, lps_skipped = report.lps_skipped;
  const double lp_seconds = report.seconds;  // this process's
  if (ranks > 1) {
    // Every rank's share is recorded (or a rank failed: then all end with its code).
    const int worst = mpi->WorstStatus(kOk);
    if (worst != kOk || rank != 0) return worst;
    if (report.feasible) {  // (an infeasible ensemble's report is every rank's, whole)
      const long long feasibility = report.lp_iterations - records->WrittenIterations();
      report = GatherRanks(system, selected, stored, *records);
      lp_iterations = feasibility + records->ObtainedIterations() - records->ResumedIterations();
      lps_skipped = records->ShortcutsThisRun();
    }
  }
  if (!report.complete)
    return StoppedAtTimeLimit(f, system, selected.size(), lp_iterations, lp_seconds, *records,
                              start);
  const Indeterminacy nd = ForceIndeterminacy(system);
  std::optional<Comparison> cmp;
  if (f.compare_perturb && report.feasible)
    cmp = ComparePerturbations(scene, system, report, f, threads);

  const BoundsTally tally = Tally(report);
  if (records) {
    WriteFileAtomically(f.output, Csv(system, report, cmp ? &*cmp : nullptr));
    records->Remove();
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  nlohmann::json out = {
      {"file", f.file},
      {"contacts", selected.size()},
      {"ensemble_contacts", system.contacts.size()},
      {"unknowns", nd.unknowns},
      {"equations", nd.equations},
      {"rank", nd.rank},
      {"rank_qr_a", nd.rank_of_a},
      {"rank_qr_transpose", nd.rank_transposed},
      {"rank_tolerance", nd.tolerance},
      {"indeterminacy_dimension", nd.dimension},
      {"feasible", report.feasible},
      {"message", report.message},
      {"mean_width",
       tally.widths > 0 ? nlohmann::json(tally.width_sum / tally.widths) : nlohmann::json(nullptr)},
      {"bounded_contacts", tally.widths},
      {"unbounded_or_failed", tally.failed},
      {"mean_fcont", tally.references > 0 ? nlohmann::json(tally.reference_sum / tally.references)
                                          : nlohmann::json(nullptr)},
      {"no_frictionless_equilibrium", tally.no_pure_opening},
      {"lp", f.lp},
      {"warm_start", lp == LpBackend::kClp && !f.cold},
      {"lp_iterations", lp_iterations},
      {"lps_skipped", lps_skipped},
      {"bounds_resumed", records ? records->Resumed() : 0},
      {"lp_iterations_resumed", records ? records->ResumedIterations() : 0},
      {"complete", true},
      {"lp_seconds", lp_seconds},
      {"threads", lp == LpBackend::kIpopt ? 1 : threads},
      {"ranks", ranks},
      {"seconds", seconds}};
  if (cmp) {
    out["compared"] = cmp->used;
    out["mean_rel_diff_fcrit"] = NumberOrNull(cmp->mean_rel_diff);
    out["max_rel_diff_fcrit"] = NumberOrNull(cmp->max_rel_diff);
    out["quasi_static"] = cmp->WithStatus(PerturbationStatus::kOk);
    out["dynamic"] = cmp->WithStatus(PerturbationStatus::kDynamic);
    out["inside_interval"] = cmp->WithInside(1);
    out["outside_interval"] = cmp->WithInside(0);
  }
  if (!f.output.empty()) out["output"] = f.output;
  if (f.summary && f.json) std::printf("%s\n", out.dump().c_str());
  else if (f.summary)
    PrintBoundsSummary(out, f.gap_tolerance,
                       lp == LpBackend::kIpopt ? "ipopt"
                       : f.cold                ? "cold"
                                               : "warm");
  return report.feasible ? kOk : kNotConverged;
}

}  // namespace unjam::cli
