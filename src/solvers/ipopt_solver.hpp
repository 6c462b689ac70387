// The convex step as a sparse quadratic program solved by Ipopt, inside the De Saxcé fixed
// point ("ipopt"). See ipopt_solver.cpp.
#pragma once

#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

class IpoptSolver final : public ContactSolver {
 public:
  std::string Name() const override { return "ipopt"; }
  // 2: each convex solve carries a proximal term (ipopt_solver.cpp), which changes the answer
  // wherever the step's solutions are not unique.
  int AnswerRevision() const override { return 2; }

 private:
  SolveResult DoSolve(const ContactProblem& problem, const SolverOptions& options,
                      const SolverGuess& guess) override;
  // Refuses (kUnsupported) a W that is not symmetric: the convex step needs one.
  SolveResult DoSolveDelassus(const DelassusProblem& problem, const SolverOptions& options,
                              const SolverGuess& guess) override;
};

}  // namespace unjam
