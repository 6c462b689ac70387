#include "unjam/problem/delassus_problem.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace unjam {

namespace {

// The same problem with two unknowns per contact: without friction, spins are held fixed
// (zero inverse inertia) and every μ is 0, so the tangent rows only observe.
ContactProblem WithTangentRows(const ContactProblem& p) {
  ContactProblem out = p;
  if (p.frictional) return out;
  out.frictional = true;
  out.inv_inertia.assign(p.NumBodies(), 0.0);
  out.free_spin.assign(p.NumBodies(), 0.0);
  for (ProblemContact& c : out.contacts) c.mu = 0.0;
  return out;
}

[[noreturn]] void Reject(const std::string& what) {
  throw std::invalid_argument("Delassus problem: " + what);
}

}  // namespace

DelassusProblem ToDelassusProblem(const ContactProblem& problem) {
  const ContactProblem p = WithTangentRows(problem);
  DelassusProblem out;
  out.w = AssembleDelassus(p);
  out.q = DelassusOffset(p);
  out.laws.reserve(p.NumContacts());
  for (const ProblemContact& c : p.contacts) out.laws.push_back({c.mu, c.kind});
  return out;
}

void Validate(const DelassusProblem& p) {
  const int n = p.NumUnknowns();
  const std::string size = std::to_string(n);
  if (p.w.rows() != n || p.w.cols() != n) {
    Reject("W is " + std::to_string(p.w.rows()) + " x " + std::to_string(p.w.cols()) +
           ", expected " + size + " x " + size + " (two rows per contact)");
  }
  if (p.q.size() != n) Reject("q has " + std::to_string(p.q.size()) + " entries, expected " + size);
  for (int k = 0; k < p.NumContacts(); ++k) {
    if (!(p.laws[k].mu >= 0.0) || !std::isfinite(p.laws[k].mu)) {
      Reject("contact " + std::to_string(k) + " has friction coefficient " +
             std::to_string(p.laws[k].mu) + " (must be finite and >= 0)");
    }
  }
}

}  // namespace unjam
