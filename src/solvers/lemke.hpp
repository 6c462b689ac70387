// Lemke's complementary pivoting on the exact 2D Signorini–Coulomb LCP ("lemke"): the
// exact backend. See lemke.cpp.
#pragma once

#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

class LemkeSolver final : public ContactSolver {
 public:
  std::string Name() const override { return "lemke"; }
  // 2: the rate form's runs come first, before the plain runs.
  // 3: the rate form's runs may take 200 pivots per row, not 100.
  int AnswerRevision() const override { return 3; }

 private:
  SolveResult DoSolve(const ContactProblem& problem, const SolverOptions& options,
                      const SolverGuess& guess) override;
  SolveResult DoSolveDelassus(const DelassusProblem& problem, const SolverOptions& options,
                              const SolverGuess& guess) override;
};

}  // namespace unjam
