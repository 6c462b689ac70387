#include "unjam/problem/inertia_bound.hpp"

#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include <ClpSimplex.hpp>

#include "unjam/lp/lp_triplets.hpp"

namespace unjam {

namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The impulses of each contact as columns, x = r / (Δt s_ref), their law's cone built in:
// a frictional unilateral contact's cone is spanned by its two edges, r = α (1, μ) + β (1, −μ)
// with α, β ≥ 0, so it needs no rows. `columns` gets, per unknown of the problem, the
// (column, coefficient) pairs that make it up.
struct ImpulseColumns {
  std::vector<std::vector<std::pair<int, double>>> of_unknown;
};
ImpulseColumns AddImpulseColumns(const ContactProblem& p, lp::LpTriplets& lp) {
  const int per = p.UnknownsPerContact();
  ImpulseColumns out;
  out.of_unknown.resize(p.NumUnknowns());
  for (int k = 0; k < p.NumContacts(); ++k) {
    const ProblemContact& c = p.contacts[k];
    const int n = k * per;
    if (c.kind == ConstraintKind::kBilateral) {
      out.of_unknown[n] = {{lp.AddColumns(1, -kInfinity, kInfinity), 1.0}};
    } else if (per == 1 || c.mu <= 0.0) {
      out.of_unknown[n] = {{lp.AddColumns(1, 0.0, kInfinity), 1.0}};
    } else {
      const int edges = lp.AddColumns(2, 0.0, kInfinity);
      out.of_unknown[n] = {{edges, 1.0}, {edges + 1, 1.0}};
      out.of_unknown[n + 1] = {{edges, c.mu}, {edges + 1, -c.mu}};
    }
  }
  return out;
}

// Per degree of freedom d, −t ≤ c_d + a_d·x ≤ t: two rows, in units of s_d.
void AddInertiaRows(const ContactProblem& p, const Eigen::VectorXd& scale, double reference,
                    int t_column, const ImpulseColumns& columns, lp::LpTriplets& lp) {
  const Eigen::SparseMatrix<double> h = AssembleJacobian(p);  // column d: H's entries of dof d
  const Eigen::VectorXd inv_mass = InverseMassDiagonal(p);
  const Eigen::VectorXd free = FreeVelocityVector(p);
  for (int d = 0; d < p.NumDofs(); ++d) {
    const double c = free[d] / inv_mass[d] / (p.dt * scale[d]);
    const int below = lp.AddRow(-kInfinity, -c);  // a·x − t ≤ −c
    const int above = lp.AddRow(-c, kInfinity);   // a·x + t ≥ −c
    for (Eigen::SparseMatrix<double>::InnerIterator it(h, d); it; ++it) {
      const double a = it.value() * reference / scale[d];
      for (const auto& [column, coefficient] : columns.of_unknown[it.row()]) {
        lp.Add(below, column, a * coefficient);
        lp.Add(above, column, a * coefficient);
      }
    }
    lp.Add(below, t_column, -1.0);
    lp.Add(above, t_column, 1.0);
  }
}

void CheckScales(const ContactProblem& p, const Eigen::VectorXd& scale) {
  if (scale.size() != p.NumDofs() || (scale.array() <= 0.0).any()) {
    throw std::invalid_argument("SmallestInertia: one positive force scale per degree of freedom");
  }
}

// Runs the dual simplex on `model` (from whatever basis it holds) and reads t.
InertiaBound Solve(ClpSimplex& model, int t_column) {
  InertiaBound out;
  model.dual();
  out.iterations = model.numberIterations();
  if (model.status() != 0) {
    out.decided = false;
    out.message = "the inertia LP stopped with CLP status " + std::to_string(model.status());
    return out;
  }
  out.ratio = model.getColSolution()[t_column];
  return out;
}
}  // namespace

// Without a load zero impulses leave every degree of freedom at rest.
bool IsUnloaded(const ContactProblem& p) { return FreeVelocityVector(p).isZero(0.0); }

InertiaBound SmallestInertia(const ContactProblem& p, const Eigen::VectorXd& scale) {
  CheckScales(p, scale);
  if (p.NumDofs() == 0 || IsUnloaded(p)) return {};
  lp::LpTriplets lp;
  const ImpulseColumns columns = AddImpulseColumns(p, lp);
  const int t_column = lp.AddColumns(1, 0.0, kInfinity, 1.0);
  AddInertiaRows(p, scale, scale.minCoeff(), t_column, columns, lp);
  ClpSimplex model;
  lp::LoadIntoClp(lp, 1e-9, model);
  return Solve(model, t_column);
}

struct HeldContactInertia::Model {
  ClpSimplex solved;
  bool ready = false;
  bool unloaded = false;  // t* = 0 for every held contact, no LP
  int t_column = -1;
  std::vector<std::vector<int>> law_columns;  // per contact: its cone's columns
  std::vector<int> held_column;               // per contact: its spare free normal column
};

HeldContactInertia::HeldContactInertia(const ContactProblem& p, const Eigen::VectorXd& scale)
    : model_(std::make_unique<Model>()) {
  CheckScales(p, scale);
  if (p.NumDofs() == 0) return;
  if (IsUnloaded(p)) {
    model_->unloaded = true;
    return;
  }
  lp::LpTriplets lp;
  ImpulseColumns columns = AddImpulseColumns(p, lp);
  Model& m = *model_;
  const int per = p.UnknownsPerContact();
  m.law_columns.resize(p.NumContacts());
  m.held_column.resize(p.NumContacts());
  for (int k = 0; k < p.NumContacts(); ++k) {
    for (const auto& entry : columns.of_unknown[k * per]) m.law_columns[k].push_back(entry.first);
    m.held_column[k] = lp.AddColumns(1, 0.0, 0.0);  // the normal direction only, released when held
    columns.of_unknown[k * per].push_back({m.held_column[k], 1.0});
  }
  m.t_column = lp.AddColumns(1, 0.0, kInfinity, 1.0);
  AddInertiaRows(p, scale, scale.minCoeff(), m.t_column, columns, lp);
  lp::LoadIntoClp(lp, 1e-9, m.solved);
  m.ready = Solve(m.solved, m.t_column).decided;
}

HeldContactInertia::~HeldContactInertia() = default;

bool HeldContactInertia::ready() const { return model_->ready || model_->unloaded; }

InertiaBound HeldContactInertia::WithHeld(int contact) const {
  const Model& m = *model_;
  if (m.unloaded) return {};
  if (!m.ready) return {0.0, false, "the unperturbed inertia LP was not solved", 0};
  if (contact < 0 || contact >= static_cast<int>(m.held_column.size()))
    throw std::out_of_range("HeldContactInertia: no such contact");
  ClpSimplex model(m.solved);  // its basis and solution: the dual simplex continues from them
  for (int column : m.law_columns[contact]) model.setColumnBounds(column, 0.0, 0.0);
  model.setColumnBounds(m.held_column[contact], -kInfinity, kInfinity);
  return Solve(model, m.t_column);
}

}  // namespace unjam
