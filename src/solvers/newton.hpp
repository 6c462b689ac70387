// Semismooth Newton on the Alart–Curnier function of the exact Signorini–Coulomb law
// ("newton"): the high-accuracy backend. See newton.cpp.
#pragma once

#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

class NewtonSolver final : public ContactSolver {
 public:
  std::string Name() const override { return "newton"; }
  // 2: from a warm start, Newton alone first (the probe).
  int AnswerRevision() const override { return 2; }

 private:
  SolveResult DoSolve(const ContactProblem& problem, const SolverOptions& options,
                      const SolverGuess& guess) override;
  SolveResult DoSolveDelassus(const DelassusProblem& problem, const SolverOptions& options,
                              const SolverGuess& guess) override;
};

}  // namespace unjam
