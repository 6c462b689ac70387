// `unjam solve FILE`: the static contact forces of a saved packing; a Siconos .dat problem
// goes to command_solve_stored.cpp.
#include "command_solve.hpp"

#include <cstdio>
#include <stdexcept>

#include "output_paths.hpp"
#include "unjam/analysis/equilibrium.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/io/siconos_problem.hpp"

namespace unjam::cli {

namespace {

// Before any work: neither output may be the input, nor the two outputs one file (the
// second written would replace the first).
void RefuseOverwrites(const SolveFlags& flags) {
  RefuseOutputOverInput("-o", flags.output, {flags.file});
  RefuseOutputOverInput("--export-problem", flags.export_problem, {flags.file});
  if (!flags.output.empty() && !flags.export_problem.empty() &&
      SameFile(flags.output, flags.export_problem)) {
    throw std::invalid_argument("-o and --export-problem name one file, " + flags.output +
                                ": choose two");
  }
}

void PrintTable(const Scene& scene, const StaticSolution& s, const Coordination& z) {
  const SolveReport& r = s.report;
  std::printf("backend           %s\n", r.backend.c_str());
  std::printf("particles         %zu\n", scene.particles.size());
  std::printf("contacts          %zu (%d force-carrying)\n", s.contacts.size(),
              z.force_carrying_contacts);
  std::printf("coordination z    %.4f (rattlers: %d)\n", z.z, z.rattlers);
  std::printf("iterations        %d\n", r.iterations);
  std::printf("residual          %.3e\n", r.residual);
  std::printf("converged         %s%s%s\n", r.converged() ? "yes" : "NO",
              r.message.empty() ? "" : ": ", r.message.c_str());
  std::printf("equilibrium       %.3e (max net force or torque / mean contact force)\n",
              s.equilibrium.residual);
  std::printf("mean contact f_n  %.6g\n", s.equilibrium.mean_contact_force);
  if (PeriodicY(scene.cell.periodicity))
    std::printf("pressure (virial) %.6g\n", s.equilibrium.pressure);
  std::printf("seconds           %.3f\n", r.seconds);
}

void PrintForces(const StaticSolution& s) {
  std::printf("\n%8s %8s %4s %4s %22s %22s\n", "i", "j", "ix", "iy", "f_n", "f_t");
  for (std::size_t k = 0; k < s.contacts.size(); ++k) {
    const Contact& c = s.contacts[k];
    std::printf("%8d %8d %4d %4d %22.15e %22.15e\n", c.i, c.j, c.image[0], c.image[1],
                s.forces[k][0], s.forces[k][1]);
  }
}

}  // namespace

void SolveFlags::Register(CLI::App& app) {
  app.add_option("FILE", file,
                 "packing file (.unjam) or Siconos 2D friction-contact problem (.dat)")
      ->required();
  solver.Register(app);
  app.add_flag("--json", json, "one JSON object on stdout");
  app.add_flag("--forces", forces, "list every contact force (.dat: every impulse)");
  app.add_option(
      "-o,--output", output,
      "write the packing with the solved forces (.dat: the impulses, one contact per line)");
  app.add_option("--export-problem", export_problem,
                 "write the contact problem as a Siconos .dat file (sparse-block storage)");
  app.add_option("--threads", threads,
                 "NSGS threads on a packing (0: all cores): each sweeps one domain of the contact "
                 "graph, from 1000 contacts up; deterministic for a given count (docs/backends.md)")
      ->check(cli::NonNegative())
      ->capture_default_str();
}

int RunSolve(const SolveFlags& flags) {
  RefuseOverwrites(flags);
  if (IsSiconosFile(flags.file)) return RunSolveStored(flags);
  const std::string& path = flags.file;
  const bool json = flags.json;
  const std::string& output = flags.output;
  Scene scene = ReadPacking(path);
  StaticSolveOptions options;
  options.backend = flags.solver.backend;
  options.solver = flags.solver.Resolve();
  options.solver.nsgs.threads = ThreadsFromOption(flags.threads);
  // Written before solving: the problem does not depend on the solution, and a problem
  // that cannot be exported (a held contact) stops the command before the work.
  if (!flags.export_problem.empty()) {
    WriteSiconosProblem(ToDelassusProblem(PoseStaticProblem(scene, options).assembled.problem),
                        flags.export_problem);
  }
  const StaticSolution s = SolveStatic(scene, options);
  const Coordination z = ComputeCoordination(scene, s.contacts, s.forces);
  if (!output.empty()) {
    scene.forces = ToContactForces(s);
    WritePacking(scene, output);
  }
  if (json) {
    nlohmann::json out = ToJson(s.report);
    out["file"] = path;
    out["particles"] = scene.particles.size();
    out["contacts"] = s.contacts.size();
    out["force_carrying_contacts"] = z.force_carrying_contacts;
    out["coordination"] = z.z;
    out["rattlers"] = z.rattlers;
    out["equilibrium_residual"] = s.equilibrium.residual;
    out["mean_contact_force"] = s.equilibrium.mean_contact_force;
    out["max_end_speed"] = s.max_speed;
    if (PeriodicY(scene.cell.periodicity)) out["pressure"] = s.equilibrium.pressure;
    if (!output.empty()) out["output"] = output;
    if (!flags.export_problem.empty()) out["exported_problem"] = flags.export_problem;
    if (flags.forces) {  // one object per contact, in the order of the table
      nlohmann::json forces = nlohmann::json::array();
      for (std::size_t k = 0; k < s.contacts.size(); ++k) {
        const Contact& c = s.contacts[k];
        forces.push_back({{"i", c.i},
                          {"j", c.j},
                          {"image", {c.image[0], c.image[1]}},
                          {"f_n", s.forces[k][0]},
                          {"f_t", s.forces[k][1]}});
      }
      out["forces"] = forces;
    }
    std::printf("%s\n", out.dump().c_str());
  } else {
    PrintTable(scene, s, z);
    if (!flags.export_problem.empty())
      std::printf("exported problem  %s\n", flags.export_problem.c_str());
    if (flags.forces) PrintForces(s);
  }
  if (s.report.converged() && s.equilibrium.residual > kStaticEquilibriumTolerance &&
      scene.effects.prescribed_motion.empty()) {
    std::fprintf(stderr,
                 "unjam solve: warning: converged to the residual, but the forces miss equilibrium "
                 "by %.3e of the mean contact "
                 "force: the state is not static, or the problem is ill-conditioned and needs a "
                 "smaller --tol (docs/residual.md)\n",
                 s.equilibrium.residual);
  }
  if (!s.report.converged()) {
    std::fprintf(
        stderr,
        "unjam solve: the solver did not converge (%s, residual %.3e, tolerance %.3e): %s\n",
        ToString(s.report.status), s.report.residual, options.solver.tolerance,
        s.report.message.c_str());
    if (flags.solver.require_converged) return kNotConverged;
  }
  return kOk;
}

}  // namespace unjam::cli
