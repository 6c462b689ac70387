// `unjam pack`: make a static packing and save it with its contact forces.
#include "command_pack.hpp"
#include "output_paths.hpp"
#include "pack_checkpoint.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "unjam/analysis/equilibrium.hpp"
#include "unjam/io/output_lock.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/gravity_pile.hpp"
#include "unjam/protocols/pressure_packing.hpp"
#include "unjam/protocols/relax.hpp"

namespace unjam::cli {

void PackFlags::Register(CLI::App& app) {
  app.add_option("--protocol", protocol,
                 "pressure: homogeneous, fully periodic cell at constant external pressure; "
                 "gravity: pile on a rough bed, periodic in x")
      ->check(CLI::IsMember({"pressure", "gravity"}))
      ->required();
  app.add_option("--n", n, "number of free disks (default 500 pressure, 1600 gravity)")
      ->check(CLI::Range(2, 100000000));
  app.add_option("--mu", mu, "Coulomb friction coefficient")
      ->check(cli::NonNegative())
      ->capture_default_str();
  app.add_option("--pressure", pressure, "external pressure P_ext (pressure protocol)")
      ->check(cli::Positive())
      ->capture_default_str();
  app.add_option("--cell-mass", cell_mass, "barostat cell mass M_lambda (pressure protocol)")
      ->check(cli::Positive())
      ->capture_default_str();
  app.add_option("--width", width, "cell width, periodic in x (gravity protocol)")
      ->capture_default_str();
  app.add_option("--initial-fraction", initial_fraction,
                 "packing fraction of the dilute start (default 0.3 pressure, 0.35 gravity)");
  app.add_option("--seed", seed, "random seed")->capture_default_str();
  app.add_option("--dt", dt,
                 "time step (default 0.02 T0; T0 = R_max sqrt(rho/P_ext) = 1 at the default "
                 "pressure, sqrt(R_max/g) = 1 for piles)")
      ->check(cli::Positive());
  app.add_option("--step-tol", step_tol,
                 "residual tolerance of each dynamics step (default 1e-8 with newton; with the "
                 "others 1e-4, tightened as (0.02 T0/dt)^2 for a larger --dt)")
      ->check(cli::Positive());
  app.add_option("--backend", backend,
                 "contact solver of the dynamics steps and of the static check (nsgs, newton, "
                 "ipopt, nlopt; auto: newton if mu <= 1e-4, else nsgs)")
      ->capture_default_str();
  app.add_option("--order", order,
                 "NSGS sweep order of the steps and of the certificate's static solves: random, "
                 "local (random blocks of neighbouring contacts: the same convergence, faster once "
                 "the contacts outgrow the cache, N >= 4000), or height (contacts by height, swept "
                 "up and down in turn: cheaper sweeps on piles; docs/performance.md). Default: "
                 "random for a cell, height for a pile")
      ->check(CLI::IsMember({"random", "local", "height"}));
  app.add_option("--step-iter", step_iter,
                 "NSGS sweeps allowed per dynamics step (default 500 pressure, 1000 gravity)")
      ->check(cli::Positive());
  app.add_option(
         "--rest-speed", rest_speed,
         "try to prove the packing static when the mean speed stays below this x V0 for 20 steps")
      ->check(cli::Positive())
      ->capture_default_str();
  app.add_option("--check-iter", check_iter,
                 "NSGS sweeps allowed to the static solve that checks a certified packing")
      ->check(cli::Positive())
      ->capture_default_str();
  app.add_option("--refine-iter", refine_iter,
                 "when a certificate finds no admissible forces near the last step's, refine them "
                 "by a static solve from rest of at most this many NSGS sweeps and try again (0: "
                 "never; docs/method.md, \"Until static\")")
      ->check(cli::NonNegative())
      ->capture_default_str();
  app.add_option("--closure-gap", closure_gap,
                 "a certificate lets contacts with gaps up to this carry force, and closes those "
                 "that do by moving the particles (docs/method.md, \"Until static\")")
      ->check(CLI::Range(1e-9, 1e-3))
      ->capture_default_str();
  app.add_flag("--certificate-lp", certificate_lp,
               "when a certificate's projections find no admissible forces, let the linear program "
               "decide (exact: it finds a network that the projection, a local method, misses, or "
               "proves that none exists; at N = 4000 about 20 s to find none, 100 s to find one)");
  app.add_option("--threads", threads,
                 "NSGS threads of the steps and the certificate's static solves (0: all cores). "
                 "Each sweeps one domain of the contact graph; the packing is deterministic for a "
                 "given thread count, and differs between counts (docs/cli.md)")
      ->check(cli::NonNegative())
      ->capture_default_str();
  app.add_option("--max-steps", max_steps, "give up after this many steps")
      ->check(cli::Positive())
      ->capture_default_str();
  app.add_option("-o,--output", output, "the packing file to write")->required();
  app.add_option("--checkpoint", checkpoint,
                 "checkpoint file (default: OUTPUT.checkpoint); an existing one is resumed");
  app.add_option("--checkpoint-every", checkpoint_every, "steps between checkpoints (0: none)")
      ->check(cli::NonNegative())
      ->capture_default_str();
  app.add_flag("--json", json, "one JSON object on stdout");
  app.add_flag("--quiet", quiet, "no progress on stderr");
}

namespace {

int Particles(const PackFlags& f) {
  return f.n > 0 ? f.n : (f.protocol == "pressure" ? 500 : 1600);
}
double InitialFraction(const PackFlags& f) {
  return f.initial_fraction.value_or(f.protocol == "pressure" ? 0.3 : 0.35);
}
// What the two protocols' options share (their fields have the same names).
template <class Options>
Options CommonOptions(const PackFlags& f) {
  Options o;
  o.particles = Particles(f);
  o.friction = f.mu;
  o.initial_packing_fraction = InitialFraction(f);
  o.seed = f.seed;
  return o;
}

GasOptions GasOptionsOf(const PackFlags& f) {
  GasOptions gas = CommonOptions<GasOptions>(f);
  gas.pressure = f.pressure;
  gas.cell_mass = f.cell_mass;
  return gas;
}

PileOptions PileOptionsOf(const PackFlags& f) {
  PileOptions pile = CommonOptions<PileOptions>(f);
  pile.width = f.width;
  return pile;
}

double TimeUnit(const PackFlags& f) {
  return f.protocol == "pressure" ? TimeUnit(GasOptionsOf(f)) : TimeUnit(PileOptionsOf(f));
}

double TimeStep(const PackFlags& f) { return f.dt.value_or(kPackingTimeStep * TimeUnit(f)); }

Scene InitialScene(const PackFlags& f) {
  return f.protocol == "pressure" ? MakeGranularGas(GasOptionsOf(f))
                                  : MakeLoosePile(PileOptionsOf(f));
}

// The shortest decimal that reads back to the same double.
std::string Number(double x) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

// The command line that remakes the packing, every parameter spelled out.
std::string ProvenanceOf(const nlohmann::json& p) {
  std::string line = "unjam pack";
  for (const auto& [key, value] : p.items()) {
    if (key == "unjam") continue;
    std::string flag = key;
    std::replace(flag.begin(), flag.end(), '_', '-');
    line += " --" + flag;
    if (value.is_boolean()) continue;  // a flag, written only when set
    line += " " + (value.is_number_float() ? Number(value.get<double>())
                   : value.is_string()     ? value.get<std::string>()
                                           : value.dump());
  }
  return line + " (unjam " + p["unjam"].get<std::string>() + ")";
}

void PrintProgress(const Simulation& sim, int step, const StepReport& r) {
  const Scene& s = sim.scene();
  std::fprintf(stderr, "step %8d  phi %.5f", step, PackingFraction(s));
  if (s.effects.pressure_bath) {
    // P_in over P_ext from this step's impulses (virial) — the barostat's own measure.
    std::vector<Eigen::Vector2d> forces(sim.impulses().size());
    for (std::size_t k = 0; k < forces.size(); ++k)
      forces[k] = sim.impulses()[k] / sim.options().dt;
    const EquilibriumReport e = CheckEquilibrium(s, sim.contacts(), forces);
    std::fprintf(stderr, "  P_in/P_ext %.5f", e.pressure / s.effects.pressure_bath->pressure);
  }
  std::fprintf(stderr, "  kinetic %.3e  contacts %d  sweeps %d\n", r.kinetic_energy, r.contacts,
               r.solve.iterations);
}

// After this many failed certificates a run prints how a creeping packing can be certified.
// Runs that were certified needed up to 26 attempts (N = 500, mu = 10 at dt = 0.01; up to
// 16 at today's step); the creeping N = 4000, mu = 1 cell had failed 20 by step 9 000.
constexpr int kChecksBeforeHint = 20;

void PrintCheck(const RelaxReport& r) {
  std::fprintf(stderr, "static check %d after step %d: ", r.static_checks, r.steps);
  if (r.jammed) {
    const StaticSolution& s = r.final_check;
    std::fprintf(
        stderr,
        "static (contacts closed by moving particles at most %.1e; residual %.2e, equilibrium %.2e",
        r.closure_displacement, s.report.residual, s.equilibrium.residual);
    if (s.equilibrium.pressure != 0.0)
      std::fprintf(stderr, ", |P_in/P_ext - 1| %.2e", r.pressure_mismatch);
    std::fprintf(stderr, ")\n");
  } else {
    std::fprintf(stderr, "not yet (%s)\n", r.check_message.c_str());
  }
}

nlohmann::json Summary(const PackFlags& f, const Scene& result, const RelaxReport& r,
                       double seconds) {
  const StaticSolution& s = r.final_check;
  const Coordination z = ComputeCoordination(result, s.contacts, s.forces);
  nlohmann::json out = {{"protocol", f.protocol},
                        {"particles", result.particles.size()},
                        {"contacts", z.force_carrying_contacts},
                        {"packing_fraction", PackingFraction(result)},
                        {"coordination", z.z},
                        {"rattlers", z.rattlers},
                        {"steps", r.steps},
                        {"jammed", r.jammed},
                        {"static_checks", r.static_checks},
                        {"refined_checks", r.refined_checks},
                        {"unconverged_steps", r.unconverged_steps},
                        {"max_overlap", MaxOverlap(result)},
                        {"closure_displacement", r.closure_displacement},
                        {"static_solve", ToJson(s.report)},
                        {"equilibrium_residual", s.equilibrium.residual},
                        {"seconds", seconds},
                        {"output", f.output},
                        {"parameters", f.Parameters()}};
  out["pressure"] = result.effects.pressure_bath ? nlohmann::json(s.equilibrium.pressure)
                                                 : nlohmann::json(nullptr);
  // Without a proven static state there are no static forces: zeros here would read as a
  // packing with no contacts and every particle a rattler.
  if (!r.jammed) {
    for (const char* key : {"contacts", "coordination", "rattlers", "pressure",
                            "closure_displacement", "static_solve", "equilibrium_residual"}) {
      out[key] = nullptr;
    }
  }
  return out;
}

}  // namespace

nlohmann::json PackFlags::Parameters() const {
  nlohmann::json p = {
      {"unjam", UNJAM_VERSION}, {"protocol", protocol}, {"n", Particles(*this)}, {"mu", mu}};
  if (protocol == "pressure") {
    p["pressure"] = pressure;
    p["cell_mass"] = cell_mass;
  } else {
    p["width"] = width;
  }
  p["initial_fraction"] = InitialFraction(*this);
  p["seed"] = seed;
  p["dt"] = TimeStep(*this);
  p["step_tol"] = StepTolerance();
  p["step_iter"] = StepIterations();
  if (Backend() != "nsgs") p["backend"] = Backend();  // absent from files made before the option
  if (Order() != "random") p["order"] = Order();      // likewise
  p["rest_speed"] = rest_speed;
  p["check_iter"] = check_iter;
  // Written only when it is not the default, as --backend. Files made before the option
  // lack it although they ran without refinement: the bundled ones had `--refine-iter 0`
  // added to their provenance (problems/README.md).
  if (refine_iter != PackFlags{}.refine_iter) p["refine_iter"] = refine_iter;
  if (closure_gap != PackFlags{}.closure_gap) p["closure_gap"] = closure_gap;  // likewise
  if (certificate_lp) p["certificate_lp"] = true;                              // likewise
  if (Threads() != 1) p["threads"] = Threads();                                // likewise
  return p;
}

// Frictionless packings jam isostatic, where loose steps (NSGS at 1e-4) leave the backbone
// held up by their own errors and no certificate ever passes; newton steps at 1e-8 certify
// them (docs/performance.md, "Frictionless and nearly frictionless cells"), and nearly
// frictionless ones (mu <= 1e-4) since newton starts their steps from the frictionless
// solution (N = 500 at mu = 1e-8, 1e-5, 1e-4). With more friction newton steps cost far
// more than NSGS's (15x at N = 500, mu = 1) and do not end the creep, so NSGS stays the
// default there.
std::string PackFlags::Backend() const {
  if (backend != "auto") return backend;
  return mu <= kNearlyFrictionless ? "newton" : "nsgs";
}

// Newton is for tight steps (at 1e-4 it does no better than NSGS); NSGS's steps are capped
// by sweeps, and dense packings need loose steps to stay affordable.
double PackFlags::StepTolerance() const {
  if (step_tol) return *step_tol;
  return Backend() == "newton" ? 1e-8 : LooseStepTolerance(TimeStep(*this) / TimeUnit(*this));
}

// A tall frictional pile creeps for ever with 500 sweeps per step (each capped step leaves
// it a little under-supported); 1000 certify the 1600-disk piles at mu = 0.1 and 1
// (docs/performance.md, "Time step and sweep order of the packing runs").
int PackFlags::StepIterations() const {
  return step_iter.value_or(protocol == "gravity" ? 1000 : 500);
}

// A pile's sweeps by height cost 1.4x less than random ones; whole runs took 1.3x less on
// 13 pairs of piles and made the same piles within their seed-to-seed scatter
// (docs/performance.md, "Time step and sweep order of the packing runs"). A cell has no height to
// sort by.
std::string PackFlags::Order() const {
  return order.value_or(protocol == "gravity" ? "height" : "random");
}

std::string PackFlags::Provenance() const { return ProvenanceOf(Parameters()); }

// Threads change the order of the sweeps, hence the packing: the count is a parameter of
// the packing, stored unless it is 1 (as files made before the option were).
int PackFlags::Threads() const { return ThreadsFromOption(threads); }

int RunPack(const PackFlags& f) {
  const auto start = std::chrono::steady_clock::now();
  const std::string checkpoint_path =
      f.checkpoint.empty() ? f.output + ".checkpoint" : f.checkpoint;
  // The checkpoint is removed once the packing is written: in one file, the packing would
  // go with it.
  if (SameFile(checkpoint_path, f.output)) {
    throw std::invalid_argument("--checkpoint " + checkpoint_path +
                                " is the output file (-o), which would be removed with the "
                                "checkpoint: choose another --checkpoint");
  }
  const nlohmann::json parameters = f.Parameters();
  StepOptions step;
  step.dt = TimeStep(f);
  step.backend = f.Backend();
  step.solver.nsgs.order = SweepOrderFromString(f.Order());
  step.solver.nsgs.threads = f.Threads();
  Scene scene = InitialScene(f);
  scene.provenance = ProvenanceOf(parameters);
  Simulation sim(scene, step);
  RelaxOptions relax;
  relax.step_tolerance = f.StepTolerance();
  relax.step_max_iterations = f.StepIterations();
  relax.rest_speed = f.rest_speed;
  relax.max_steps = f.max_steps;
  relax.static_max_iterations = f.check_iter;
  relax.refine_max_iterations = f.refine_iter;
  relax.closure_gap = f.closure_gap;
  relax.linear_program = f.certificate_lp;
  relax.static_backend = f.Backend();
  relax.sweep_order = step.solver.nsgs.order;
  relax.threads = step.solver.nsgs.threads;
  // A progress line every 1000 steps, or sooner once 10 s have passed since the last one (a
  // pile at today's time step takes about 1 500 steps, a minute or more).
  relax.progress_interval = f.quiet ? 0 : 10;
  relax.progress = [last = std::chrono::steady_clock::now()](const Simulation& s, int step,
                                                             const StepReport& r) mutable {
    const auto now = std::chrono::steady_clock::now();
    if (step % 1000 != 0 && now - last < std::chrono::seconds(10)) return;
    last = now;
    PrintProgress(s, step, r);
  };
  if (!f.quiet) {
    relax.on_check = [hinted = f.certificate_lp](const RelaxReport& r) mutable {
      PrintCheck(r);
      if (hinted || r.jammed || r.static_checks < kChecksBeforeHint) return;
      hinted = true;
      std::fprintf(
          stderr,
          "hint: %d certificates failed on a calm packing. A marginal one (high friction, "
          "large N) can creep for a very long time; --certificate-lp --closure-gap 1e-4 let the "
          "certificate load contacts up to 1e-4 apart and ask the linear program "
          "(docs/performance.md, \"Time to a jammed packing vs N\")\n",
          r.static_checks);
    };
  }

  // One run per checkpoint (docs/cli.md, "One run per output"): two runs resuming from one
  // would overwrite each other's state.
  const OutputLock lock(checkpoint_path + ".lock", checkpoint_path);
  PackCheckpointer checkpointer(checkpoint_path, parameters, f.checkpoint_every > 0);
  const RelaxReport resume = checkpointer.Resume(sim);
  relax.checkpoint_interval = f.checkpoint_every;
  relax.on_checkpoint = [&](Simulation& s, const RelaxReport& r) { checkpointer.Save(s, r); };
  const RelaxReport r = RelaxToStatic(sim, relax, resume);

  // A packing not proven static is no result: no output file; its state goes to the
  // checkpoint, from which a rerun with a larger --max-steps resumes.
  Scene result = sim.scene();
  result.forces = ToContactForces(r.final_check);
  if (r.jammed) {
    WritePacking(result, f.output);
  } else {
    checkpointer.Save(sim, r);
  }
  const double seconds =
      checkpointer.PreviousSeconds() +
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json out = Summary(f, result, r, seconds);
  if (!r.jammed) out["output"] = nullptr;
  if (f.summary) std::printf("%s\n", f.json ? out.dump().c_str() : out.dump(2).c_str());
  if (!r.jammed) {
    std::fprintf(
        stderr,
        "unjam pack: not static after %d steps (%d static checks failed: %s); %s not written; %s\n",
        r.steps, r.static_checks,
        r.check_message.empty() ? "none attempted" : r.check_message.c_str(), f.output.c_str(),
        f.checkpoint_every > 0
            ? ("rerun with a larger --max-steps to resume from " + checkpoint_path).c_str()
            : "no checkpoint (--checkpoint-every 0)");
    return kNotConverged;
  }
  checkpointer.Remove();
  return kOk;
}

}  // namespace unjam::cli
