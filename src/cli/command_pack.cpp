// `unjam pack`: make a static packing and save it with its contact forces.
#include "command_pack.hpp"

#include <chrono>
#include <cstdio>

#include "unjam/analysis/equilibrium.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/protocols/gravity_pile.hpp"

namespace unjam::cli {

void PackFlags::Register(CLI::App& app) {
  app.add_option("--protocol", protocol, "how to pack: gravity (pile on a rough bed, periodic in x)")
      ->check(CLI::IsMember({"gravity"}))->capture_default_str();
  app.add_option("--n", n, "number of free disks")->check(CLI::Range(1, 100000000))->capture_default_str();
  app.add_option("--mu", mu, "Coulomb friction coefficient")->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--width", width, "cell width (periodic in x)")->capture_default_str();
  app.add_option("--initial-fraction", initial_fraction, "packing fraction of the initial dilute medium")->capture_default_str();
  app.add_option("--seed", seed, "random seed")->capture_default_str();
  app.add_option("--dt", dt, "time step")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--step-tol", step_tol, "residual tolerance of each time step's contact solve")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--rest-speed", rest_speed, "static when every speed stays below this × sqrt(g R_max) for 50 steps")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--max-steps", max_steps, "give up after this many steps")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("-o,--output", output, "the packing file to write")->required();
  app.add_flag("--json", json, "one JSON object on stdout");
  app.add_flag("--quiet", quiet, "no progress on stderr");
}

int RunPack(const PackFlags& f, const std::string& command_line) {
  const auto start = std::chrono::steady_clock::now();
  PileOptions pile;
  pile.particles = f.n;
  pile.width = f.width;
  pile.friction = f.mu;
  pile.initial_packing_fraction = f.initial_fraction;
  pile.seed = f.seed;
  Scene scene = MakeLoosePile(pile);
  scene.provenance = command_line;

  SettleOptions settle;
  settle.step.dt = f.dt;
  settle.step.solver.tolerance = f.step_tol;
  settle.step.solver.max_iterations = 5000;
  settle.max_steps = f.max_steps;
  settle.speed_threshold = f.rest_speed;
  settle.progress_interval = f.quiet ? 0 : 1000;
  settle.progress = [](int step, double kinetic) {
    std::fprintf(stderr, "step %8d  kinetic energy %.3e\n", step, kinetic);
  };
  Simulation sim(scene, settle.step);
  const SettleReport settled = Settle(sim, settle);

  // The last step's forces start the static solve: the pile's own, path-dependent forces.
  Scene result = sim.scene();
  result.forces = LastStepForces(sim);
  StaticSolveOptions solve;
  solve.solver.tolerance = 1e-10;
  const StaticSolution s = SolveStatic(result, solve);
  result.forces = ToContactForces(s);
  WritePacking(result, f.output);

  const Coordination z = ComputeCoordination(result, s.contacts, s.forces);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json out = {{"particles", result.particles.size()}, {"contacts", z.force_carrying_contacts},
                        {"packing_fraction", PackingFraction(result)}, {"coordination", z.z},
                        {"rattlers", z.rattlers}, {"steps", settled.steps}, {"settled", settled.settled},
                        {"unconverged_steps", settled.unconverged_steps},
                        {"max_overlap", MaxOverlap(result)}, {"static_solve", ToJson(s.report)},
                        {"equilibrium_residual", s.equilibrium.residual}, {"seconds", seconds},
                        {"output", f.output}};
  if (f.json) {
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::printf("%s\n", out.dump(2).c_str());
  }
  if (!settled.settled) {
    std::fprintf(stderr, "unjam pack: not static after %d steps (largest speed %.3e); saved anyway\n",
                 settled.steps, settled.max_speed);
    return kNotConverged;
  }
  return kOk;
}

}  // namespace unjam::cli
