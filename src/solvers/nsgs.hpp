// Nonlinear projected Gauss–Seidel over contacts (the default backend, "nsgs"): on body
// problems (nsgs.cpp) and on Delassus-form problems (nsgs_delassus.cpp).
#pragma once

#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

class NsgsSolver final : public ContactSolver {
 public:
  std::string Name() const override { return "nsgs"; }

 private:
  SolveResult DoSolve(const ContactProblem& problem, const SolverOptions& options,
                      const SolverGuess& guess) override;
  SolveResult DoSolveDelassus(const DelassusProblem& problem, const SolverOptions& options,
                              const SolverGuess& guess) override;
};

}  // namespace unjam
