// unjam: the command-line front end. Parses options, calls the library, maps errors to
// exit codes (docs/cli.md). No physics here.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"
#include "command_bounds.hpp"
#include "command_check.hpp"
#include "command_compare.hpp"
#include "command_pack.hpp"
#include "command_perturb.hpp"
#include "command_solve.hpp"
#include "command_study.hpp"
#include "main_job.hpp"
#include "mpi_session.hpp"
#include "unjam/io/packing_file.hpp"

namespace {

int Run(int argc, char** argv) {
  using namespace unjam::cli;
  CLI::App app{
      "unjam: how jammed packings of rigid frictional disks respond to local disturbances.\n"
      "Without a command, runs the main job on the bundled default packing."};
  app.require_subcommand(0, 1);
  app.set_version_flag("--version", std::string("unjam ") + UNJAM_VERSION);
  MainJobFlags main_job;
  main_job.Register(app);

  std::string info_file;
  bool info_json = false;
  CLI::App* info = app.add_subcommand("info", "what a saved packing holds");
  info->add_option("FILE", info_file, "packing file (.unjam)")->required();
  info->add_flag("--json", info_json, "one JSON object on stdout");

  SolveFlags solve_flags;
  CLI::App* solve = app.add_subcommand("solve",
                                       "static contact forces of a saved packing, or a stored "
                                       "Siconos 2D friction-contact problem (.dat)");
  solve_flags.Register(*solve);

  PackFlags pack_flags;
  CLI::App* pack = app.add_subcommand("pack", "make a static packing and save it with its forces");
  pack_flags.Register(*pack);

  PerturbFlags perturb_flags;
  CLI::App* perturb = app.add_subcommand(
      "perturb",
      "open contacts or shift particles of a static packing, one by one, and measure the response");
  perturb_flags.Register(*perturb);

  BoundsFlags bounds_flags;
  CLI::App* bounds = app.add_subcommand(
      "bounds", "admissible-force bounds per contact and the degree of force indeterminacy");
  bounds_flags.Register(*bounds);

  CompareFlags compare_flags;
  CLI::App* compare = app.add_subcommand(
      "compare", "every backend on every problem at every tolerance: what accuracy costs in time");
  compare_flags.Register(*compare);

  CheckFlags check_flags;
  CLI::App* check = app.add_subcommand("check",
                                       "the hard cases on every backend: status, residual, Siconos "
                                       "error, overlap and energy at rest");
  check_flags.Register(*check);

  StudyFlags study_flags;
  CLI::App* study = app.add_subcommand(
      "study",
      "the friction study from one configuration: packings, perturbations, bounds, "
      "tables, figures and a report (resumable)");
  study_flags.Register(*study);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kUsageError;
  }
  try {
    const MpiSession* mpi = CurrentMpiSession();
    if (mpi != nullptr && mpi->size() > 1 && !*perturb && !*study &&
        !(*bounds && !bounds_flags.Shifts())) {
      throw std::invalid_argument(
          "only `unjam perturb`, `unjam study` and `unjam bounds` on contacts divide their work "
          "among MPI ranks; run other commands without mpirun");
    }
    const bool main_job_options =
        app.count("--sample") + app.count("--seed") + app.count("--out") + app.count("--threads") >
        0;
    if (main_job_options && !app.get_subcommands().empty()) {
      throw std::invalid_argument(
          "--sample, --seed, --out and --threads before a command belong to the main job (unjam "
          "without a command)");
    }
    if (*info) return RunInfo(info_file, info_json);
    if (*solve) return RunSolve(solve_flags);
    if (*pack) return RunPack(pack_flags);
    if (*perturb) return RunPerturb(perturb_flags);
    if (*bounds) return RunBounds(bounds_flags);
    if (*compare) return RunCompare(compare_flags);
    if (*check) return RunCheck(check_flags);
    if (*study) return RunStudy(study_flags);
    return RunMainJob(main_job);
  } catch (const unjam::InputError& e) {
    std::fprintf(stderr, "unjam: error: %s\n", e.what());
    return kInputError;
  } catch (const unjam::OutputError& e) {
    std::fprintf(stderr, "unjam: error: %s\n", e.what());
    return kInputError;
  } catch (const std::filesystem::filesystem_error& e) {
    // A folder or file the run reads or writes that the file system refuses: an I/O error.
    std::fprintf(stderr, "unjam: error: %s: %s\n", e.path1().string().c_str(),
                 e.code().message().c_str());
    return kInputError;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "unjam: error: %s\n", e.what());
    return kUsageError;
  }
}

int RunOrFail(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "unjam: error: %s\n", e.what());
    return unjam::cli::kInternalError;
  }
}

}  // namespace

int main(int argc, char** argv) {
  unjam::cli::MpiSession mpi(argc, argv);
  unjam::cli::SetCurrentMpiSession(&mpi);
  const int code = RunOrFail(argc, argv);
  // Under mpirun every rank meets the others once (docs/perturbations.md, "Beyond one
  // machine: MPI"); a rank that ended early, on an error, meets them here.
  if (mpi.size() > 1 && !mpi.Synchronised()) return mpi.WorstStatus(code);
  return code;
}
