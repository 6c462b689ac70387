// `unjam pack`: make a static packing and save it with its contact forces.
#include "command_pack.hpp"

#include <chrono>
#include <cstdio>

#include "unjam/analysis/equilibrium.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/gravity_pile.hpp"
#include "unjam/protocols/pressure_packing.hpp"
#include "unjam/protocols/relax.hpp"

namespace unjam::cli {

void PackFlags::Register(CLI::App& app) {
  app.add_option("--protocol", protocol, "pressure: homogeneous, fully periodic cell at constant external pressure; "
                 "gravity: pile on a rough bed, periodic in x")->check(CLI::IsMember({"pressure", "gravity"}))->required();
  app.add_option("--n", n, "number of free disks (default 500 pressure, 1600 gravity)")->check(CLI::Range(2, 100000000));
  app.add_option("--mu", mu, "Coulomb friction coefficient")->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--pressure", pressure, "external pressure P_ext (pressure protocol)")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--cell-mass", cell_mass, "barostat cell mass M_lambda (pressure protocol)")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--width", width, "cell width, periodic in x (gravity protocol)")->capture_default_str();
  app.add_option("--initial-fraction", initial_fraction, "packing fraction of the dilute start (default 0.3 pressure, 0.35 gravity)");
  app.add_option("--seed", seed, "random seed")->capture_default_str();
  app.add_option("--dt", dt, "time step (default 1e-2 pressure, 5e-3 gravity)")->check(CLI::PositiveNumber);
  app.add_option("--step-tol", step_tol, "residual tolerance of each dynamics step")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--step-iter", step_iter, "NSGS sweeps allowed per dynamics step")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--rest-speed", rest_speed, "quench and check when the mean speed stays below this x V0 for 20 steps")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--check-iter", check_iter, "NSGS sweeps allowed to a static check (large packings need more)")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--max-steps", max_steps, "give up after this many steps")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("-o,--output", output, "the packing file to write")->required();
  app.add_flag("--json", json, "one JSON object on stdout");
  app.add_flag("--quiet", quiet, "no progress on stderr");
}

namespace {

Scene InitialScene(const PackFlags& f) {
  if (f.protocol == "pressure") {
    GasOptions gas;
    gas.particles = f.n > 0 ? f.n : 500;
    gas.friction = f.mu;
    gas.pressure = f.pressure;
    gas.cell_mass = f.cell_mass;
    gas.initial_packing_fraction = f.initial_fraction.value_or(0.3);
    gas.seed = f.seed;
    return MakeGranularGas(gas);
  }
  PileOptions pile;
  pile.particles = f.n > 0 ? f.n : 1600;
  pile.width = f.width;
  pile.friction = f.mu;
  pile.initial_packing_fraction = f.initial_fraction.value_or(0.35);
  pile.seed = f.seed;
  return MakeLoosePile(pile);
}

void PrintProgress(const Simulation& sim, int step, const StepReport& r) {
  const Scene& s = sim.scene();
  std::fprintf(stderr, "step %8d  phi %.5f", step, PackingFraction(s));
  if (s.effects.pressure_bath) {
    // P_in over P_ext from this step's impulses (virial) — the barostat's own measure.
    std::vector<Eigen::Vector2d> forces(sim.impulses().size());
    for (std::size_t k = 0; k < forces.size(); ++k) forces[k] = sim.impulses()[k] / sim.options().dt;
    const EquilibriumReport e = CheckEquilibrium(s, sim.contacts(), forces);
    std::fprintf(stderr, "  P_in/P_ext %.5f", e.pressure / s.effects.pressure_bath->pressure);
  }
  std::fprintf(stderr, "  kinetic %.3e  contacts %d  sweeps %d\n", r.kinetic_energy, r.contacts, r.solve.iterations);
}

void PrintCheck(const RelaxReport& r) {
  const StaticSolution& s = r.final_check;
  std::fprintf(stderr, "static check %d after step %d: %s, residual %.2e (%d sweeps), equilibrium %.2e",
               r.static_checks, r.steps, ToString(s.report.status), s.report.residual, s.report.iterations,
               s.equilibrium.residual);
  std::fprintf(stderr, ", |P_in/P_ext - 1| %.2e: %s\n", r.pressure_mismatch, r.jammed ? "static" : "not yet");
}

}  // namespace

int RunPack(const PackFlags& f, const std::string& command_line) {
  const auto start = std::chrono::steady_clock::now();
  Scene scene = InitialScene(f);
  scene.provenance = command_line;
  StepOptions step;
  step.dt = f.dt.value_or(f.protocol == "pressure" ? 1e-2 : 5e-3);
  Simulation sim(scene, step);
  RelaxOptions relax;
  relax.loose_step_tolerance = f.step_tol;
  relax.step_max_iterations = f.step_iter;
  relax.rest_speed = f.rest_speed;
  relax.max_steps = f.max_steps;
  relax.static_max_iterations = f.check_iter;
  relax.progress_interval = f.quiet ? 0 : 1000;
  relax.progress = PrintProgress;
  if (!f.quiet) relax.on_check = PrintCheck;
  const RelaxReport r = RelaxToStatic(sim, relax);

  Scene result = sim.scene();
  const StaticSolution& s = r.final_check;
  result.forces = ToContactForces(s);
  WritePacking(result, f.output);

  const Coordination z = ComputeCoordination(result, s.contacts, s.forces);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json out = {{"protocol", f.protocol}, {"particles", result.particles.size()},
                        {"contacts", z.force_carrying_contacts}, {"packing_fraction", PackingFraction(result)},
                        {"coordination", z.z}, {"rattlers", z.rattlers}, {"steps", r.steps},
                        {"jammed", r.jammed}, {"static_checks", r.static_checks},
                        {"unconverged_steps", r.unconverged_steps}, {"max_overlap", MaxOverlap(result)},
                        {"static_solve", ToJson(s.report)}, {"equilibrium_residual", s.equilibrium.residual},
                        {"seconds", seconds}, {"output", f.output}};
  out["pressure"] = result.effects.pressure_bath ? nlohmann::json(s.equilibrium.pressure) : nlohmann::json(nullptr);
  std::printf("%s\n", f.json ? out.dump().c_str() : out.dump(2).c_str());
  if (!r.jammed) {
    std::fprintf(stderr, "unjam pack: not static after %d steps (%d static checks failed); saved anyway\n",
                 r.steps, r.static_checks);
    return kNotConverged;
  }
  return kOk;
}

}  // namespace unjam::cli
