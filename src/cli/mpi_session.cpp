#include "mpi_session.hpp"

#include <cstdlib>
#include <initializer_list>

#include <mpi.h>

namespace unjam::cli {
namespace {

// Open MPI's launcher sets OMPI_COMM_WORLD_SIZE; PMI and PMIx launchers (srun, mpiexec.hydra)
// set PMI_SIZE or PMIX_RANK.
bool LaunchedByMpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

MpiSession* current = nullptr;

}  // namespace

MpiSession::MpiSession(int& argc, char**& argv) {
  if (!LaunchedByMpi()) return;
  MPI_Init(&argc, &argv);
  active_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  if (active_) MPI_Finalize();
}

int MpiSession::WorstStatus(int status) {
  synchronised_ = true;
  if (!active_) return status;
  int worst = status;
  MPI_Allreduce(&status, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return worst;
}

MpiSession* CurrentMpiSession() { return current; }
void SetCurrentMpiSession(MpiSession* session) { current = session; }

}  // namespace unjam::cli
