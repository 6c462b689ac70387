// The process's place in an MPI launch. `mpirun -np N unjam perturb ...` divides the
// ensemble among N processes (docs/perturbations.md, "Beyond one machine: MPI"). Outside an
// MPI launch nothing of MPI is called, and the process is rank 0 of 1.
#pragma once

namespace unjam::cli {

class MpiSession {
 public:
  // Initialises MPI only when a launcher started this process (its environment says so).
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  // Every rank's `status` (0: fine); each gets the largest. A barrier: all ranks wait here.
  // The one collective of a run: `unjam perturb` calls it once its share is done, and main
  // calls it for a rank that ended before (an error), so that every rank calls it once.
  int WorstStatus(int status);
  bool Synchronised() const { return synchronised_; }

 private:
  bool active_ = false;
  bool synchronised_ = false;
  int rank_ = 0;
  int size_ = 1;
};

// The session of this process (set by main), or null: rank 0 of 1.
MpiSession* CurrentMpiSession();
void SetCurrentMpiSession(MpiSession* session);

}  // namespace unjam::cli
