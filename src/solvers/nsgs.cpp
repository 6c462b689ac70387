// Nonlinear Gauss–Seidel on the contact impulses, velocity-based (as in Box2D and the
// Brendel–Unger–Wolf CD code): the generalised velocity v = v_free + M⁻¹ Hᵀ r is kept up to
// date, so one contact update reads and writes only its two bodies (and λ).
//
// Local problem of contact k with all other impulses frozen: ũ = ũ⁰ + W_kk r_k with W_kk
// diagonal for disks (the normal impulse exerts no torque and λ couples to the normal
// only), so the exact 2D Signorini–Coulomb solution is closed-form:
//   ũ⁰_n ≥ 0                   → r = 0                       (the contact opens)
//   else r_n = −ũ⁰_n / W_nn,  r_t = −u⁰_t / W_tt             (sticking)
//        |r_t| > μ r_n         → r_t = −μ r_n sign(u⁰_t)     (sliding)
// A bilateral (held) contact takes r_n = −ũ⁰_n / W_nn of either sign and r_t = 0.
// Over-relaxation blends the old and new impulse and projects back onto the cone.
#include "nsgs.hpp"
#include "nsgs_domains.hpp"
#include "sweeps.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <numeric>
#include <vector>

#include "unjam/problem/kinematics.hpp"
#include "unjam/solvers/residual.hpp"

namespace unjam {

namespace {

// Everything one contact update needs, contiguous. Bodies without degrees of freedom point
// at a dummy slot whose inverse masses are zero, so the hot loop has no branches on them.
struct Row {
  int bi, bj;
  double nx, ny;
  double arm_i, arm_j;
  double cell_arm;
  double rhs_n;  // ũ_n = n·(v_j − v_i) + c λ + rhs_n
  double bias_t;
  double inv_wnn, inv_wtt;  // 1 / W_nn, 1 / W_tt
  double mass_i, mass_j;    // inverse masses
  double rot_i, rot_j;      // inverse inertia × arm
  double mu;                // < 0 marks a bilateral contact
};

struct Body {
  double vx, vy, w;
};

// Where the solver keeps each contact and each body: row `pos` is contact
// contact_at[pos], body b lives in slot body_slot[b]. The identity except for
// SweepOrder::kLocal, which lays both out along the contact graph.
struct Layout {
  std::vector<int> contact_at;
  std::vector<int> body_slot;
};

// The bodies' contact graph in compressed rows, each body's neighbours by increasing
// degree (Cuthill–McKee's rule). Contacts with a side without degrees of freedom add no edge.
struct BodyGraph {
  std::vector<int> start, adjacent;
  int Degree(int b) const { return start[b + 1] - start[b]; }
};

BodyGraph MakeBodyGraph(const ContactProblem& p) {
  const int nb = p.NumBodies();
  BodyGraph g;
  g.start.assign(nb + 1, 0);
  for (const ProblemContact& c : p.contacts) {
    if (c.body_i >= 0 && c.body_j >= 0) {
      ++g.start[c.body_i + 1];
      ++g.start[c.body_j + 1];
    }
  }
  for (int b = 0; b < nb; ++b) g.start[b + 1] += g.start[b];
  g.adjacent.resize(g.start[nb]);
  std::vector<int> fill(g.start.begin(), g.start.end() - 1);
  for (const ProblemContact& c : p.contacts) {
    if (c.body_i < 0 || c.body_j < 0) continue;
    g.adjacent[fill[c.body_i]++] = c.body_j;
    g.adjacent[fill[c.body_j]++] = c.body_i;
  }
  for (int b = 0; b < nb; ++b) {
    std::stable_sort(g.adjacent.begin() + g.start[b], g.adjacent.begin() + g.start[b + 1],
                     [&](int x, int y) { return g.Degree(x) < g.Degree(y); });
  }
  return g;
}

// Bodies in Cuthill–McKee order: breadth first through each connected component, from the
// last body reached by a first breadth-first pass (a pseudo-peripheral body). Bodies of
// neighbouring contacts end up close in memory.
std::vector<int> CuthillMcKee(const BodyGraph& g, int nb) {
  std::vector<int> order;
  std::vector<bool> seen(nb, false);
  order.reserve(nb);
  auto breadth_first = [&](int root) {  // appends root's component to `order`
    seen[root] = true;
    order.push_back(root);
    for (std::size_t q = order.size() - 1; q < order.size(); ++q) {
      for (int e = g.start[order[q]]; e < g.start[order[q] + 1]; ++e) {
        if (seen[g.adjacent[e]]) continue;
        seen[g.adjacent[e]] = true;
        order.push_back(g.adjacent[e]);
      }
    }
  };
  for (int b = 0; b < nb; ++b) {
    if (seen[b]) continue;
    const std::size_t first = order.size();
    breadth_first(b);
    const int far = order.back();
    for (std::size_t q = first; q < order.size(); ++q) seen[order[q]] = false;
    order.resize(first);
    breadth_first(far);
  }
  return order;
}

// kLocal's layout: bodies in Cuthill–McKee order, contacts sorted by their first body's slot.
Layout LocalLayout(const ContactProblem& p) {
  const int nb = p.NumBodies();
  const std::vector<int> order = CuthillMcKee(MakeBodyGraph(p), nb);
  Layout layout;
  layout.body_slot.resize(nb);
  for (int slot = 0; slot < nb; ++slot) layout.body_slot[order[slot]] = slot;
  auto key = [&](int k) {
    const ProblemContact& c = p.contacts[k];
    return std::min(c.body_i >= 0 ? layout.body_slot[c.body_i] : nb,
                    c.body_j >= 0 ? layout.body_slot[c.body_j] : nb);
  };
  layout.contact_at.resize(p.NumContacts());
  std::iota(layout.contact_at.begin(), layout.contact_at.end(), 0);
  std::stable_sort(layout.contact_at.begin(), layout.contact_at.end(),
                   [&](int a, int b) { return key(a) < key(b); });
  return layout;
}

Layout MakeLayout(const ContactProblem& p, SweepOrder order) {
  if (order == SweepOrder::kLocal) return LocalLayout(p);
  Layout layout;
  layout.contact_at.resize(p.NumContacts());
  std::iota(layout.contact_at.begin(), layout.contact_at.end(), 0);
  if (order == SweepOrder::kHeight) {
    std::stable_sort(layout.contact_at.begin(), layout.contact_at.end(),
                     [&](int a, int b) { return p.contacts[a].height < p.contacts[b].height; });
  }
  layout.body_slot.resize(p.NumBodies());
  std::iota(layout.body_slot.begin(), layout.body_slot.end(), 0);
  return layout;
}

std::vector<Row> MakeRows(const ContactProblem& p, const Layout& layout) {
  const int dummy = p.NumBodies();
  std::vector<Row> rows(p.NumContacts());
  for (int pos = 0; pos < p.NumContacts(); ++pos) {
    const ProblemContact& c = p.contacts[layout.contact_at[pos]];
    Row& r = rows[pos];
    r.bi = c.body_i >= 0 ? layout.body_slot[c.body_i] : dummy;
    r.bj = c.body_j >= 0 ? layout.body_slot[c.body_j] : dummy;
    r.nx = c.normal.x();
    r.ny = c.normal.y();
    r.arm_i = c.arm_i;
    r.arm_j = c.arm_j;
    r.cell_arm = p.cell ? c.cell_arm : 0.0;
    r.rhs_n = c.bias.x() - c.target_velocity;
    r.bias_t = c.bias.y();
    r.mass_i = c.body_i >= 0 ? p.inv_mass[c.body_i] : 0.0;
    r.mass_j = c.body_j >= 0 ? p.inv_mass[c.body_j] : 0.0;
    const double ii = c.body_i >= 0 && p.frictional ? p.inv_inertia[c.body_i] : 0.0;
    const double ij = c.body_j >= 0 && p.frictional ? p.inv_inertia[c.body_j] : 0.0;
    r.rot_i = ii * c.arm_i;
    r.rot_j = ij * c.arm_j;
    const double wnn =
        r.mass_i + r.mass_j + (p.cell ? r.cell_arm * r.cell_arm * p.cell->inv_mass : 0.0);
    const double wtt = r.mass_i + r.mass_j + r.rot_i * c.arm_i + r.rot_j * c.arm_j;
    r.inv_wnn = wnn > 0.0 ? 1.0 / wnn : 0.0;
    r.inv_wtt = wtt > 0.0 ? 1.0 / wtt : 0.0;
    r.mu = c.kind == ConstraintKind::kBilateral ? -1.0 : c.mu;
  }
  return rows;
}

// The solver state: impulses, body velocities (with the dummy slot last), and λ.
struct State {
  std::vector<double> rn, rt;
  std::vector<Body> body;
  double cell_rate = 0.0;
  double cell_inv_mass = 0.0;
};

Eigen::VectorXd Impulses(const ContactProblem& p, const Layout& layout, const State& s) {
  Eigen::VectorXd r(p.NumUnknowns());
  for (int pos = 0; pos < p.NumContacts(); ++pos) {
    const int k = layout.contact_at[pos];
    r[k * p.UnknownsPerContact()] = s.rn[pos];
    if (p.frictional) r[2 * k + 1] = s.rt[pos];
  }
  return r;
}

// From `start` (the guess's impulses, or empty: zero). `dummies` slots without degrees of
// freedom follow the bodies (one per thread).
State InitialState(const ContactProblem& p, const Layout& layout, const Eigen::VectorXd& start,
                   int dummies = 1) {
  State s;
  const int nc = p.NumContacts();
  s.rn.assign(nc, 0.0);
  s.rt.assign(nc, 0.0);
  if (start.size() == p.NumUnknowns()) {
    for (int pos = 0; pos < nc; ++pos) {
      const int k = layout.contact_at[pos];
      s.rn[pos] = start[k * p.UnknownsPerContact()];
      if (p.frictional) s.rt[pos] = start[k * 2 + 1];
    }
  }
  const VelocityState v = EndVelocityState(p, Impulses(p, layout, s));
  s.body.resize(p.NumBodies() + dummies, Body{0.0, 0.0, 0.0});
  for (int b = 0; b < p.NumBodies(); ++b)
    s.body[layout.body_slot[b]] = {v.body[b][0], v.body[b][1], v.body[b][2]};
  s.cell_rate = v.cell_rate;
  s.cell_inv_mass = p.cell ? p.cell->inv_mass : 0.0;
  return s;
}

// One exact local solve of contact k, with over-relaxation `omega`, against the cell rate
// `cell_rate` (s.cell_rate, or a thread's copy of it). Returns |Δr|.
template <bool kFrictional>
inline double UpdateContact(const Row& r, int k, double omega, State& s, double& cell_rate) {
  Body& bi = s.body[r.bi];
  Body& bj = s.body[r.bj];
  const double dvx = bj.vx - bi.vx;
  const double dvy = bj.vy - bi.vy;
  const double un = r.nx * dvx + r.ny * dvy + r.cell_arm * cell_rate + r.rhs_n;
  const double rn_old = s.rn[k];
  const double rt_old = kFrictional ? s.rt[k] : 0.0;
  const double un0 = un - rn_old / r.inv_wnn;
  double rn = -un0 * r.inv_wnn;
  double rt = 0.0;
  if (r.mu >= 0.0) {  // unilateral: Signorini, then Coulomb
    if (un0 >= 0.0) rn = 0.0;
    if (kFrictional && rn > 0.0) {
      const double ut = -r.ny * dvx + r.nx * dvy - r.arm_i * bi.w - r.arm_j * bj.w + r.bias_t;
      const double ut0 = ut - rt_old / r.inv_wtt;
      rt = -ut0 * r.inv_wtt;
    }
  }
  if (omega != 1.0) {
    rn = (1.0 - omega) * rn_old + omega * rn;
    rt = (1.0 - omega) * rt_old + omega * rt;
    if (r.mu >= 0.0) rn = std::max(rn, 0.0);
  }
  if (kFrictional) {
    const double bound = r.mu >= 0.0 ? r.mu * rn : 0.0;
    rt = std::clamp(rt, -bound, bound);
  }
  const double dn = rn - rn_old;
  const double dt = rt - rt_old;
  const double px = dn * r.nx - dt * r.ny;
  const double py = dn * r.ny + dt * r.nx;
  bi.vx -= r.mass_i * px;
  bi.vy -= r.mass_i * py;
  bj.vx += r.mass_j * px;
  bj.vy += r.mass_j * py;
  if (kFrictional) {
    bi.w -= r.rot_i * dt;
    bj.w -= r.rot_j * dt;
    s.rt[k] = rt;
  }
  cell_rate += s.cell_inv_mass * r.cell_arm * dn;
  s.rn[k] = rn;
  return std::abs(dn) + std::abs(dt);
}

template <bool kFrictional>
void Sweep(const std::vector<Row>& rows, const std::vector<std::uint32_t>& order, double omega,
           State& s) {
  for (std::uint32_t k : order)
    UpdateContact<kFrictional>(rows[k], static_cast<int>(k), omega, s, s.cell_rate);
}

// Domains for threads (nsgs_domains.hpp): the contacts inside each (by layout position),
// and those between two.
struct Domains {
  std::vector<std::vector<std::uint32_t>> inside;
  std::vector<std::uint32_t> between;
};

// Bodies in Cuthill–McKee order cut into `parts` runs carrying about as many contacts each.
// The order is breadth first, so each run is a connected band of the contact graph and the
// contacts between runs lie along a few of its level sets.
std::vector<int> BodyDomains(const ContactProblem& p, const std::vector<int>& order, int parts) {
  std::vector<int> degree(p.NumBodies(), 0);
  for (const ProblemContact& c : p.contacts) {
    if (c.body_i >= 0) ++degree[c.body_i];
    if (c.body_j >= 0) ++degree[c.body_j];
  }
  const double total = std::accumulate(degree.begin(), degree.end(), 0.0);
  std::vector<int> domain(p.NumBodies(), 0);
  double seen = 0.0;
  int part = 0;
  for (int b : order) {
    domain[b] = part;
    seen += degree[b];
    while (part + 1 < parts && seen >= total * (part + 1) / parts) ++part;
  }
  return domain;
}

// The layout of a solve on `parts` threads, from that of one thread (`base`): bodies in
// Cuthill–McKee order and the contacts of each domain together, in their order in `base`
// (by height, for SweepOrder::kHeight), the contacts between domains last. Each thread
// then writes its own stretch of memory: interleaved, the threads' writes to shared cache
// lines had cost as much as the work they split (measured: no gain on two threads).
Layout DomainLayout(const ContactProblem& p, const Layout& base, int parts, Domains& domains) {
  const int nb = p.NumBodies();
  const std::vector<int> order = CuthillMcKee(MakeBodyGraph(p), nb);
  const std::vector<int> domain = BodyDomains(p, order, parts);
  Layout layout;
  layout.body_slot.resize(nb);
  for (int slot = 0; slot < nb; ++slot) layout.body_slot[order[slot]] = slot;
  std::vector<std::vector<int>> groups(parts + 1);  // each domain's, then those between
  for (int k : base.contact_at) {
    const ProblemContact& c = p.contacts[k];
    const int di = c.body_i >= 0 ? domain[c.body_i] : -1;
    const int dj = c.body_j >= 0 ? domain[c.body_j] : -1;
    groups[di >= 0 && dj >= 0 && di != dj ? parts : std::max({di, dj, 0})].push_back(k);
  }
  domains.inside.assign(parts, {});
  for (int g = 0; g <= parts; ++g) {
    std::vector<std::uint32_t>& list = g < parts ? domains.inside[g] : domains.between;
    for (int k : groups[g]) {
      list.push_back(static_cast<std::uint32_t>(layout.contact_at.size()));
      layout.contact_at.push_back(k);
    }
  }
  return layout;
}

// One list of contact positions and its sweep order, drawn from a generator of its own.
struct ListOrder {
  std::vector<std::uint32_t> positions;
  std::vector<std::uint32_t> order;  // indices into positions
  solvers_internal::SplitMix64 rng;
};

ListOrder MakeListOrder(std::vector<std::uint32_t> positions, std::uint64_t seed, int list) {
  ListOrder l{std::move(positions),
              {},
              {seed ^ solvers_internal::SplitMix64Hash(static_cast<std::uint64_t>(list) + 1)}};
  l.order.resize(l.positions.size());
  std::iota(l.order.begin(), l.order.end(), 0u);
  return l;
}

template <bool kFrictional>
void SweepList(const std::vector<Row>& rows, ListOrder& list, SweepOrder kind, int index,
               double omega, State& s, double& cell_rate) {
  solvers_internal::NextOrder(kind, index, list.rng, list.order);
  for (std::uint32_t i : list.order) {
    const std::uint32_t k = list.positions[i];
    UpdateContact<kFrictional>(rows[k], static_cast<int>(k), omega, s, cell_rate);
  }
}

// Rows of a domain layout whose bodies without degrees of freedom point at one dummy slot
// per thread (slot nb + 1 + t; the contacts between domains keep slot nb), so that no two
// threads write the same memory.
std::vector<Row> DomainRows(const ContactProblem& p, const Layout& layout, const Domains& domains) {
  const int nb = p.NumBodies();
  std::vector<Row> rows = MakeRows(p, layout);
  for (std::size_t t = 0; t < domains.inside.size(); ++t) {
    for (std::uint32_t pos : domains.inside[t]) {
      if (rows[pos].bi == nb) rows[pos].bi = nb + 1 + static_cast<int>(t);
      if (rows[pos].bj == nb) rows[pos].bj = nb + 1 + static_cast<int>(t);
    }
  }
  return rows;
}

// NSGS on o.nsgs.threads threads (nsgs_domains.hpp). A sweep: each thread sweeps its domain's
// contacts against its own copy of the cell rate (the one state all contacts share), the
// copies' changes are summed in thread order, then the caller sweeps the contacts between
// domains. A residual check splits its per-contact errors among the threads too: on one
// thread it had taken a quarter of a two-thread solve (the N = 3000 cell).
template <bool kFrictional>
class DomainSolve {
 public:
  DomainSolve(const ContactProblem& p, const SolverOptions& o, const Layout& base,
              const Eigen::VectorXd& start)
      : p_(p), o_(o), threads_(o.nsgs.threads), layout_(DomainLayout(p, base, threads_, domains_)),
        rows_(DomainRows(p, layout_, domains_)),
        state_(InitialState(p, layout_, start, threads_ + 1)), evaluate_(p),
        errors_(p.NumContacts()), cell_change_(threads_, 0.0),
        team_(threads_, [this](int t) { Work(t); }) {
    for (int t = 0; t < threads_; ++t)
      lists_.push_back(MakeListOrder(std::move(domains_.inside[t]), o.nsgs.seed, t));
    lists_.push_back(MakeListOrder(std::move(domains_.between), o.nsgs.seed, threads_));
  }

  void Sweep(int index) {
    index_ = index;
    cell_start_ = state_.cell_rate;
    team_.Run();
    for (double change : cell_change_) state_.cell_rate += change;
    SweepList<kFrictional>(rows_, lists_[threads_], o_.nsgs.order, index, o_.nsgs.relaxation,
                           state_, state_.cell_rate);
  }

  double Residual() {
    impulses_ = Impulses();
    velocities_ = evaluate_.Velocities(impulses_);
    checking_ = true;
    team_.Run();
    checking_ = false;
    return evaluate_.Summarise(impulses_, errors_).residual;
  }

  Eigen::VectorXd Impulses() const { return unjam::Impulses(p_, layout_, state_); }

 private:
  // Thread t's part of the current phase (lists_ is filled before the first phase).
  void Work(int t) {
    if (checking_) {
      const int nc = p_.NumContacts();
      evaluate_.Errors(impulses_, velocities_, nc * t / threads_, nc * (t + 1) / threads_, errors_);
      return;
    }
    double cell = cell_start_;
    SweepList<kFrictional>(rows_, lists_[t], o_.nsgs.order, index_, o_.nsgs.relaxation, state_,
                           cell);
    cell_change_[t] = cell - cell_start_;
  }

  const ContactProblem& p_;
  const SolverOptions& o_;
  const int threads_;
  Domains domains_;  // moved into lists_ once laid out
  const Layout layout_;
  const std::vector<Row> rows_;
  State state_;
  std::vector<ListOrder> lists_;  // the threads' domains, then the contacts between them
  const ResidualEvaluator evaluate_;
  std::vector<double> errors_;
  std::vector<double> cell_change_;
  int index_ = 0;
  double cell_start_ = 0.0;
  bool checking_ = false;
  Eigen::VectorXd impulses_;
  VelocityState velocities_;
  solvers_internal::DomainTeam<std::function<void(int)>> team_;  // last: its threads use the rest
};

// NSGS on one thread: one order over all contacts (sweeps.hpp's RunSweeps).
void SolveOnOneThread(const ContactProblem& p, const SolverOptions& o, const Layout& layout,
                      const Eigen::VectorXd& start, SolveResult& result) {
  const std::vector<Row> rows = MakeRows(p, layout);
  State state = InitialState(p, layout, start);
  const ResidualEvaluator evaluate(p);
  auto sweep = [&](const std::vector<std::uint32_t>& order) {
    if (p.frictional) Sweep<true>(rows, order, o.nsgs.relaxation, state);
    else Sweep<false>(rows, order, o.nsgs.relaxation, state);
  };
  auto residual = [&] { return evaluate(Impulses(p, layout, state)).residual; };
  solvers_internal::RunSweeps(p.NumContacts(), o, sweep, residual, result.report);
  result.impulses = Impulses(p, layout, state);
}

template <bool kFrictional>
void SolveInDomains(const ContactProblem& p, const SolverOptions& o, const Layout& base,
                    const Eigen::VectorXd& start, SolveResult& result) {
  DomainSolve<kFrictional> solve(p, o, base, start);
  solvers_internal::RunIndexedSweeps(
      p.NumContacts(), o, [&](int i) { solve.Sweep(i); }, [&] { return solve.Residual(); },
      result.report);
  result.impulses = solve.Impulses();
}

}  // namespace

SolveResult NsgsSolver::DoSolve(const ContactProblem& p, const SolverOptions& options,
                                const SolverGuess& guess) {
  const Layout layout = MakeLayout(p, options.nsgs.order);
  SolveResult result;
  result.report.backend = Name();
  const Eigen::VectorXd& start = guess.impulses;
  if (options.nsgs.threads < 2 || p.NumContacts() < kParallelContacts)
    SolveOnOneThread(p, options, layout, start, result);
  else if (p.frictional) SolveInDomains<true>(p, options, layout, start, result);
  else SolveInDomains<false>(p, options, layout, start, result);
  return result;
}

}  // namespace unjam
