// The convex step as a bound-constrained QP on cone edges, solved matrix-free by NLopt,
// inside the De Saxcé fixed point ("nlopt"). See nlopt_solver.cpp.
#pragma once

#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

class NloptSolver final : public ContactSolver {
 public:
  std::string Name() const override { return "nlopt"; }

 private:
  SolveResult DoSolve(const ContactProblem& problem, const SolverOptions& options,
                      const SolverGuess& guess) override;
  // Refuses (kUnsupported) a W that is not symmetric: the convex step needs one.
  SolveResult DoSolveDelassus(const DelassusProblem& problem, const SolverOptions& options,
                              const SolverGuess& guess) override;
};

}  // namespace unjam
