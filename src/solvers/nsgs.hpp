// Nonlinear projected Gauss–Seidel over contacts (the default backend, "nsgs"): on body
// problems (nsgs.cpp) and on Delassus-form problems (nsgs_delassus.cpp).
#pragma once

#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

class NsgsSolver final : public ContactSolver {
 public:
  std::string Name() const override { return "nsgs"; }
  SolveResult Solve(const ContactProblem& problem, const SolverOptions& options) override;
  SolveResult SolveDelassus(const DelassusProblem& problem, const SolverOptions& options) override;
};

}  // namespace unjam
