// Nonlinear projected Gauss–Seidel over contacts (the default backend, "nsgs").
#pragma once

#include "unjam/solvers/contact_solver.hpp"

namespace unjam {

class NsgsSolver final : public ContactSolver {
 public:
  std::string Name() const override { return "nsgs"; }
  SolveResult Solve(const ContactProblem& problem, const SolverOptions& options) override;
};

}  // namespace unjam
