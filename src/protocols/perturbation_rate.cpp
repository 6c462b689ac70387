#include "perturbation_rate.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include <Eigen/UmfPackSupport>

#include "unjam/problem/contact_problem.hpp"
#include "unjam/solvers/pattern_polish.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {

namespace {

using Key = std::tuple<int, int, int, int>;
Key KeyOf(const Contact& c) { return {c.i, c.j, c.image[0], c.image[1]}; }

// Closed-contact index of every contact of a posed step, by key (−1: not closed).
std::vector<int> ClosedIndexOf(const RateBase& rb, const StaticProblem& posed) {
  std::map<Key, int> closed;
  for (std::size_t c = 0; c < rb.closed.size(); ++c) {
    const int k = rb.closed[c];
    closed[KeyOf(rb.posed.contacts[static_cast<std::size_t>(
        rb.posed.assembled.source_contact[static_cast<std::size_t>(k)])])] = static_cast<int>(c);
  }
  const ContactProblem& p = posed.assembled.problem;
  std::vector<int> out(static_cast<std::size_t>(p.NumContacts()), -1);
  for (int k = 0; k < p.NumContacts(); ++k) {
    const auto it = closed.find(KeyOf(posed.contacts[static_cast<std::size_t>(
        posed.assembled.source_contact[static_cast<std::size_t>(k)])]));
    if (it != closed.end()) out[static_cast<std::size_t>(k)] = it->second;
  }
  return out;
}

Eigen::SparseMatrix<double> RowsOf(const Eigen::SparseMatrix<double>& h,
                                   const std::vector<int>& rows) {
  using Triplet = Eigen::Triplet<double>;
  std::vector<Triplet> t;
  const Eigen::SparseMatrix<double, Eigen::RowMajor> by_row = h;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(by_row, rows[r]); it;
         ++it) {
      t.emplace_back(static_cast<int>(r), static_cast<int>(it.col()), it.value());
    }
  }
  Eigen::SparseMatrix<double> out(static_cast<Eigen::Index>(rows.size()), h.cols());
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

RateProblem ProblemOver(const RateBase& rb, Eigen::MatrixXd basis) {
  const ContactProblem& p = rb.posed.assembled.problem;
  const int stride = rb.UnknownsPerContact();
  RateProblem out;
  out.basis = std::move(basis);
  for (std::size_t c = 0; c < rb.closed.size(); ++c) {
    RateContact rc;
    rc.row_n = static_cast<int>(c) * stride;
    rc.row_t = stride == 2 ? rc.row_n + 1 : -1;
    rc.mu = p.contacts[static_cast<std::size_t>(rb.closed[c])].mu;
    rc.r0_n = rb.impulses[rc.row_n];
    rc.r0_t = stride == 2 ? rb.impulses[rc.row_t] : 0.0;
    out.contacts.push_back(rc);
  }
  return out;
}

int BodyColumn(const ContactProblem& p, int body, int component) {
  return body * p.DofsPerBody() + component;
}

}  // namespace

RateBase PrepareRateBase(const PerturbationBase& base, const StaticSolveOptions& step) {
  RateBase rb;
  rb.posed = PoseStaticProblem(base.scene, step);
  const ContactProblem& p = rb.posed.assembled.problem;
  const Eigen::VectorXd& stored = rb.posed.guess.impulses;  // the static forces' impulses
  const int stride = p.UnknownsPerContact();
  rb.closed_index.assign(static_cast<std::size_t>(p.NumContacts()), -1);
  std::vector<int> rows;
  for (int k = 0; k < p.NumContacts(); ++k) {
    const Contact& c = rb.posed.contacts[static_cast<std::size_t>(
        rb.posed.assembled.source_contact[static_cast<std::size_t>(k)])];
    const bool loaded = stored.size() > 0 && stored[k * stride] != 0.0;
    if (!(std::abs(c.gap) <= step.closed_gap_tolerance) && !loaded) continue;
    rb.closed_index[static_cast<std::size_t>(k)] = static_cast<int>(rb.closed.size());
    rb.closed.push_back(k);
    for (int d = 0; d < stride; ++d) rows.push_back(k * stride + d);
  }
  rb.jacobian = RowsOf(AssembleJacobian(p), rows);
  rb.impulses.resize(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    rb.impulses[static_cast<Eigen::Index>(r)] = stored.size() > 0 ? stored[rows[r]] : 0.0;
  }
  rb.stresses = ComputeSelfStresses(rb.jacobian);
  return rb;
}

RateTarget PoseRateTarget(const RateBase& rb, const PerturbationTarget& t,
                          const PerturbationOptions& o) {
  RateTarget out;
  const ContactProblem& p = rb.posed.assembled.problem;
  const int stride = rb.UnknownsPerContact();
  if (t.kind == PerturbationTarget::Kind::kParticleShift) {
    const int body = rb.posed.assembled.body_of_particle[static_cast<std::size_t>(t.i)];
    if (body < 0) {
      out.refused = "the particle has no degrees of freedom";
      return out;
    }
    std::vector<int> released;
    for (int d = 0; d < p.DofsPerBody(); ++d) released.push_back(BodyColumn(p, body, d));
    out.problem = ProblemOver(rb, ExtendSelfStresses(rb.stresses.basis, rb.jacobian, released));
    const Eigen::VectorXd motion = rb.jacobian.col(BodyColumn(p, body, 0)) * t.direction.x() +
                                   rb.jacobian.col(BodyColumn(p, body, 1)) * t.direction.y();
    // The shift opens (u_n = H v > 0) or presses the particle's contacts; the driver is
    // the compression it imposes, as the held contact's is for an opening.
    out.problem.driver = -(out.problem.basis.transpose() * motion);
    // F_crit = −ŝ·(Hᵀ r)_p: the contact impulses on p against the shift.
    const Eigen::MatrixXd hs = rb.jacobian.transpose() * out.problem.basis;
    const Eigen::VectorXd h0 = rb.jacobian.transpose() * rb.impulses;
    const int cx = BodyColumn(p, body, 0), cy = BodyColumn(p, body, 1);
    out.critical = -(t.direction.x() * hs.row(cx) + t.direction.y() * hs.row(cy)).transpose();
    out.critical_offset = -(t.direction.x() * h0[cx] + t.direction.y() * h0[cy]);
    return out;
  }
  int held = -1;
  for (std::size_t c = 0; c < rb.closed.size(); ++c) {
    const Contact& k = rb.posed.contacts[static_cast<std::size_t>(
        rb.posed.assembled.source_contact[static_cast<std::size_t>(rb.closed[c])])];
    if (k.i == t.i && k.j == t.j && k.image == t.image) held = static_cast<int>(c);
  }
  if (held < 0) {
    out.refused = "the contact is not closed in the static state";
    return out;
  }
  std::vector<int> released;  // a frozen cell no longer has to balance
  if (o.cell == CellCondition::kFixedVolume && p.cell) released.push_back(p.NumDofs() - 1);
  out.problem = ProblemOver(rb, ExtendSelfStresses(rb.stresses.basis, rb.jacobian, released));
  out.problem.contacts[static_cast<std::size_t>(held)].held = true;
  if (stride == 2) out.problem.released_rows.push_back(held * stride + 1);
  out.problem.driver = out.problem.basis.row(held * stride).transpose();
  out.critical = out.problem.basis.row(held * stride).transpose();
  out.critical_offset = rb.impulses[held * stride];
  return out;
}

SolveResult StepOnPattern(const RateBase& rb, const RateTarget& rt, const RatePathResult& path,
                          const StaticProblem& perturbed, bool open_may_close) {
  const ContactProblem& p = perturbed.assembled.problem;
  const int stride = p.UnknownsPerContact();
  const std::vector<int> closed = ClosedIndexOf(rb, perturbed);
  const Eigen::VectorXd forces = rb.impulses + rt.problem.basis * path.alpha;
  // The path's forces and states on the perturbed step's contacts; the contacts the static
  // state leaves open start open, with no force, and stay so unless `open_may_close`.
  Eigen::VectorXd impulses = Eigen::VectorXd::Zero(p.NumUnknowns());
  std::vector<ContactState> states(static_cast<std::size_t>(p.NumContacts()), ContactState::kOpen);
  std::vector<char> frozen(static_cast<std::size_t>(p.NumContacts()), open_may_close ? 0 : 1);
  for (int k = 0; k < p.NumContacts(); ++k) {
    const int c = closed[static_cast<std::size_t>(k)];
    if (c < 0) continue;
    for (int d = 0; d < stride; ++d) impulses[k * stride + d] = forces[c * stride + d];
    states[static_cast<std::size_t>(k)] = path.states[static_cast<std::size_t>(c)];
    frozen[static_cast<std::size_t>(k)] = 0;
  }
  SolveResult out = SolveOnPattern(p, impulses, std::move(states), frozen);
  out.report.backend = "rate";
  return out;
}

}  // namespace unjam
