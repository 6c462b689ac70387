#include "unjam/solvers/rate_path.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_set>

#include <Eigen/Dense>

#include "reach_heap.hpp"
#include "unjam/solvers/givens_qr.hpp"
#include "unjam/solvers/resizable_matrix.hpp"

namespace unjam {

const char* ToString(RatePathEnd end) {
  switch (end) {
    case RatePathEnd::kCollapse: return "collapse";
    case RatePathEnd::kUnbounded: return "unbounded";
    case RatePathEnd::kReleaseFails: return "release-fails";
    case RatePathEnd::kFixedCollapse: return "fixed-collapse";
    case RatePathEnd::kBack: return "back";
    case RatePathEnd::kCycle: return "cycle";
    case RatePathEnd::kStalled: return "stalled";
    case RatePathEnd::kSingular: return "singular";
  }
  return "?";
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// On a piece whose direction is a unit vector, a rate below −kRateTolerance approaches its
// bound; steps within kTie of each other are equal at order zero, and the perturbation
// (below) decides between them.
constexpr double kRateTolerance = 1e-13;
constexpr double kTie = 1e-11;
// |t| below this at order zero: the path has not left its start (t of a collapse is O(1)+).
constexpr double kZeroLoad = 1e-9;
// A piece whose forces move less than this per unit t is a mechanism at constant forces (a
// collapse piece): measured, such pieces move them by 1e-12 per unit t or less (round-off),
// every other piece by 1e-5 or more. Its forces are held exactly: paths that go on past
// one (a slip of the mechanism that runs backwards stops) reach t ~ 1e15, where round-off
// in the forces would be of their own size.
constexpr double kCollapseRate = 1e-9;
// A direction whose α moves by `dalpha_norm` while t moves by dt is such a piece.
bool MovesNoForce(double dalpha_norm, double dt) {
  return dalpha_norm <= kCollapseRate * std::abs(dt);
}
// The piece's kernel comes from a QR factorisation updated event by event (O(m²) instead of
// O(m³)), factorised anew after this many updates; where its diagonal is this close to
// rank loss, or its kernel misses, the pivoted factorisation decides.
constexpr int kRefactorAfter = 200;
constexpr double kDoubtfulDiagonal = 1e-8;
constexpr double kKernelResidual = 1e-11;
// A kernel direction that moves α and t by less than this (per unit length) is a free
// mechanism: round-off gives 1e-13 and less, a loading direction 1e-6 and more.
constexpr double kFreeMechanism = 1e-10;

// A number of the perturbed problem, v₀ + ε v₁ for an infinitesimal ε > 0: every bound of
// the contact law is moved outward by ε times a weight (distinct for every bound), which
// makes the path non-degenerate, as the lexicographic rule does for Lemke's method, without
// changing any order-zero value. Several bounds reached at one point of the path (a static
// state with contacts on the edge of their cone, a contact reaching the apex) are then
// reached one after the other, in the order of their ε parts.
struct Lex {
  double v0 = 0.0, v1 = 0.0;
};
bool LexLess(const Lex& a, const Lex& b) {
  if (a.v0 < b.v0 - kTie * (1.0 + std::abs(b.v0))) return true;
  if (b.v0 < a.v0 - kTie * (1.0 + std::abs(a.v0))) return false;
  return a.v1 < b.v1;
}

enum class UnknownKind { kSlip, kOpenNormal, kOpenTangential, kApexPlus, kApexMinus };
struct Unknown {
  int contact;
  UnknownKind kind;
  bool operator==(const Unknown& o) const { return contact == o.contact && kind == o.kind; }
};

enum class EventKind {
  kNone,
  kSlipStops,
  kCloses,
  kLeavesApex,
  kStartsSliding,
  kOpens,
  kParameterLimit
};
struct Event {
  EventKind kind = EventKind::kNone;
  int contact = -1;
  double sign = 0.0;  // kStartsSliding: the slip direction; kLeavesApex: the flow that stops
  Lex step{kInf, kInf};
};

// The quantity whose growth orients the next piece.
enum class Orientation { kParameter, kUnknown, kNormalForce, kFrictionRow };

// A contact's bounds: y⁺ = μ r_n − r_t ≥ 0, y⁻ = μ r_n + r_t ≥ 0, r_n ≥ 0; their ε weights.
struct Weights {
  double plus = 1.0, minus = 1.0, normal = 1.0;
};
Weights WeightsOf(int contact) {
  // Fractional parts of multiples of the golden ratio: distinct, in [1, 2).
  auto w = [](long long k) {
    const double x = 0.6180339887498949 * static_cast<double>(k);
    return 1.0 + (x - std::floor(x));
  };
  return {w(3LL * contact + 1), w(3LL * contact + 2), w(3LL * contact + 3)};
}

class PathFollower {
 public:
  PathFollower(const RateProblem& p, const RatePathOptions& o)
      : p_(p), options_(o), dims_(p.basis.cols()), st_(p.basis.transpose()) {
    const std::size_t n = p.contacts.size();
    MeasureGradients();
    state_.assign(n, ContactState::kStick);
    for (auto* v : {&slip_, &open_n_, &open_t_, &apex_plus_, &apex_minus_}) v->assign(n, Lex{});
    weights_.resize(n);
    for (std::size_t c = 0; c < n; ++c) weights_[c] = WeightsOf(static_cast<int>(c));
    BuildRelease();
  }

  RatePathResult Run() {
    RatePathResult out;
    if (!release_possible_)
      return Finish(RatePathEnd::kReleaseFails, "no self-stress carries the released force", out);
    SetForces(Eigen::VectorXd::Zero(dims_), Eigen::VectorXd::Zero(dims_));
    if (release_.norm() > 0.0) {
      // Phase 1, with the associated (dilatant) law: its holonomic path ends on the
      // admissible network nearest the elastic release (a projection onto a convex set),
      // which exists exactly when the static LP is feasible.
      associated_ = true;
      direction_ = release_;
      const RatePathEnd end = Follow(1.0, out);
      if (end != RatePathEnd::kCollapse)
        return Finish(RatePathEnd::kReleaseFails, std::string("releasing: ") + ToString(end), out);
      const Eigen::VectorXd alpha0 = alpha0_, alpha1 = alpha1_;
      Reset();
      SetForces(alpha0, alpha1);
    }
    // Phase 2: the perturbation, with Coulomb's law, from the released network. The contacts
    // phase 1 left on a bound of its perturbed problem sit on it exactly; phase 2 moves every
    // bound out by as much again, so that its start too is strictly inside them all.
    associated_ = false;
    weight_scale_ = 2.0;
    direction_ = Project(p_.driver);
    seen_.clear();
    const RatePathEnd end = Follow(kInf, out);
    // A state that recurs while t has not moved but at first order in ε: the path is a
    // loop through the degenerate static state (contacts exactly on their cone's edge),
    // which no event cap or tie-break changes (docs/performance.md, "The rate solve").
    const bool at_zero_load = end == RatePathEnd::kCycle && std::abs(t_.v0) <= kZeroLoad;
    return Finish(end, at_zero_load ? "at zero load" : "", out);
  }

 private:
  // Every contact sticking again with no plastic displacement, t = 0: the released network
  // is the prestress the perturbation starts from.
  void Reset() {
    std::fill(state_.begin(), state_.end(), ContactState::kStick);
    for (auto* v : {&slip_, &open_n_, &open_t_, &apex_plus_, &apex_minus_})
      std::fill(v->begin(), v->end(), Lex{});
    t_ = Lex{};
    unknowns_.clear();
    qr_.Reset(1);
    qr_updates_ = 0;
    pg_.Resize(dims_, 0);
    epg_.Resize(0, 0);
    ed_.resize(0);
    e_.Resize(0, dims_);
  }

  // P = I − Q Qᵀ, the released forces' directions Q (one or two columns) projected out:
  // applied as such, O(D) per vector instead of O(D²) with P formed.
  Eigen::VectorXd Project(const Eigen::VectorXd& x) const {
    if (released_.cols() == 0) return x;
    return x - released_ * (released_.transpose() * x);
  }

  // Q and the least-norm α that zeroes the released forces.
  void BuildRelease() {
    released_.resize(dims_, 0);
    release_ = Eigen::VectorXd::Zero(dims_);
    pg_.Resize(dims_, 0);
    e_.Resize(0, dims_);
    if (p_.released_rows.empty()) return;
    Eigen::MatrixXd rows(static_cast<Eigen::Index>(p_.released_rows.size()), dims_);
    Eigen::VectorXd target(rows.rows());
    for (Eigen::Index k = 0; k < rows.rows(); ++k) {
      const int r = p_.released_rows[static_cast<std::size_t>(k)];
      rows.row(k) = p_.basis.row(r);
      target[k] = -p_.StaticImpulse(r);
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(rows.transpose());
    qr.setThreshold(1e-10);
    released_ = qr.householderQ() * Eigen::MatrixXd::Identity(dims_, qr.rank());
    release_ = rows.completeOrthogonalDecomposition().solve(target);
    release_possible_ = (rows * release_ - target).norm() <= 1e-9 * std::max(1.0, target.norm());
  }

  bool Frictional(const RateContact& c) const { return c.row_t >= 0; }
  const RateContact& ContactOf(int c) const { return p_.contacts[static_cast<std::size_t>(c)]; }
  Eigen::MatrixXd::ConstColXpr RowN(const RateContact& c) const { return st_.col(c.row_n); }
  Eigen::MatrixXd::ConstColXpr RowT(const RateContact& c) const { return st_.col(c.row_t); }
  // The gradient of the cone's edge μ r_n + σ r_t ≥ 0, in the basis' coordinates.
  Eigen::VectorXd EdgeNormal(const RateContact& c, double sigma) const {
    return c.mu * RowN(c) + sigma * RowT(c);
  }
  double SlipSign(int c) const {
    return state_[static_cast<std::size_t>(c)] == ContactState::kSlidePositive ? 1.0 : -1.0;
  }
  // The weight of the edge μ r_n + σ r_t ≥ 0 (σ = −1: y⁺, σ = +1: y⁻).
  double EdgeWeight(int c, double sigma) const {
    const Weights& w = weights_[static_cast<std::size_t>(c)];
    return weight_scale_ * (sigma < 0.0 ? w.plus : w.minus);
  }
  double NormalWeight(int c) const {
    return weight_scale_ * weights_[static_cast<std::size_t>(c)].normal;
  }

  // G_c: how an unknown displaces its contact, in the basis' coordinates.
  Eigen::VectorXd Column(const Unknown& u) const {
    const RateContact& c = ContactOf(u.contact);
    switch (u.kind) {
      case UnknownKind::kSlip:
        // Coulomb: along the tangent; associated: along the normal of the edge the force is
        // on, μ n + σ t for a slip σ (it opens the contact too).
        return associated_ ? EdgeNormal(c, SlipSign(u.contact))
                           : Eigen::VectorXd(SlipSign(u.contact) * RowT(c));
      case UnknownKind::kOpenNormal: return RowN(c);
      case UnknownKind::kOpenTangential: return RowT(c);
      case UnknownKind::kApexPlus: return EdgeNormal(c, -1.0);
      case UnknownKind::kApexMinus: return EdgeNormal(c, +1.0);
    }
    return {};
  }

  // The row e of an unknown's force equation e·α + b = 0 (b fixed: the path moves along
  // the kernel of these rows, and the event that adds an unknown puts it on its equation).
  Eigen::VectorXd EquationRow(const Unknown& u) const {
    const RateContact& c = ContactOf(u.contact);
    switch (u.kind) {
      case UnknownKind::kSlip:
        return EdgeNormal(c, SlipSign(u.contact));  // on the edge opposing the slip
      case UnknownKind::kApexPlus: return EdgeNormal(c, -1.0);
      case UnknownKind::kApexMinus: return EdgeNormal(c, +1.0);
      case UnknownKind::kOpenNormal: return RowN(c);      // r_n stays at its bound
      case UnknownKind::kOpenTangential: return RowT(c);  // r_t stays as it was
    }
    return {};
  }

  Lex& Value(const Unknown& u) {
    const auto c = static_cast<std::size_t>(u.contact);
    switch (u.kind) {
      case UnknownKind::kSlip: return slip_[c];
      case UnknownKind::kOpenNormal: return open_n_[c];
      case UnknownKind::kOpenTangential: return open_t_[c];
      case UnknownKind::kApexPlus: return apex_plus_[c];
      case UnknownKind::kApexMinus: return apex_minus_[c];
    }
    return slip_[c];
  }

  // The unknowns of every moving contact, in contact order.
  std::vector<Unknown> WantedUnknowns() const {
    std::vector<Unknown> u;
    for (std::size_t c = 0; c < state_.size(); ++c) {
      const int k = static_cast<int>(c);
      switch (state_[c]) {
        case ContactState::kStick: break;
        case ContactState::kSlidePositive:
        case ContactState::kSlideNegative: u.push_back({k, UnknownKind::kSlip}); break;
        case ContactState::kOpen:
          if (associated_ &&
              Frictional(p_.contacts[c])) {  // at the apex: a flow along each edge's normal
            u.push_back({k, UnknownKind::kApexPlus});
            u.push_back({k, UnknownKind::kApexMinus});
          } else {
            u.push_back({k, UnknownKind::kOpenNormal});
            if (Frictional(p_.contacts[c])) u.push_back({k, UnknownKind::kOpenTangential});
          }
          break;
      }
    }
    return u;
  }

  // Brings P G, E P G and E d up to date with the contacts' states: only the unknowns that
  // came or went change a row and a column (O(m D) each, not O(m² D)).
  void UpdateSystem() {
    const std::vector<Unknown> wanted = WantedUnknowns();
    // Drop the unknowns no longer wanted (and those whose column changed: a slip whose
    // sign flipped).
    for (std::size_t k = unknowns_.size(); k-- > 0;) {
      const bool keep = std::find(wanted.begin(), wanted.end(), unknowns_[k]) != wanted.end() &&
                        (unknowns_[k].kind != UnknownKind::kSlip ||
                         slip_sign_[k] == SlipSign(unknowns_[k].contact));
      if (keep) continue;
      RemoveAt(static_cast<Eigen::Index>(k));
    }
    for (const Unknown& u : wanted) {
      if (std::find(unknowns_.begin(), unknowns_.end(), u) == unknowns_.end()) Append(u);
    }
  }

  void RemoveAt(Eigen::Index k) {
    const Eigen::Index m = static_cast<Eigen::Index>(unknowns_.size());
    pg_.DropColumn(k);
    e_.DropRow(k);
    epg_.DropRow(k);
    epg_.DropColumn(k);
    if (k < m - 1) ed_.segment(k, m - k - 1) = ed_.tail(m - k - 1).eval();
    ed_.conservativeResize(m - 1);
    unknowns_.erase(unknowns_.begin() + k);
    slip_sign_.erase(slip_sign_.begin() + k);
    qr_.RemoveColumn(k);
    qr_.RemoveRow(k + 1);
    ++qr_updates_;
  }

  void Append(const Unknown& u) {
    const Eigen::Index m = static_cast<Eigen::Index>(unknowns_.size());
    const Eigen::VectorXd e = EquationRow(u);
    const Eigen::VectorXd pg = Project(Column(u));
    pg_.Resize(dims_, m + 1);
    pg_.view().col(m) = pg;
    e_.Resize(m + 1, dims_);
    e_.view().row(m) = e.transpose();
    epg_.Resize(m + 1, m + 1);
    epg_.view().row(m) = e.transpose() * pg_.view();
    epg_.view().col(m) = e_.view() * pg;
    ed_.conservativeResize(m + 1);
    ed_[m] = e.dot(direction_);
    unknowns_.push_back(u);
    slip_sign_.push_back(u.kind == UnknownKind::kSlip ? SlipSign(u.contact) : 0.0);
    // Kᵀ gains the new unknown's row (its column of K on the old equations) and the new
    // equation's column (over t, then the unknowns).
    qr_.AppendRow(epg_.view().col(m).head(m));
    Eigen::VectorXd equation(m + 2);
    equation << ed_[m], epg_.view().row(m).transpose();
    qr_.AppendColumn(equation);
    ++qr_updates_;
  }

  // α and the forces it adds, S α, both orders; from here on they move by whole pieces.
  void SetForces(const Eigen::VectorXd& alpha0, const Eigen::VectorXd& alpha1) {
    alpha0_ = alpha0;
    alpha1_ = alpha1;
    reach_stale_ = true;
  }

  // Per contact, the products of its rows of S, from which the norm of any of its margins'
  // gradients follows without reading the rows again.
  void MeasureGradients() {
    gradients_.assign(p_.contacts.size(), Gradients{});
    for (std::size_t ci = 0; ci < p_.contacts.size(); ++ci) {
      const RateContact& c = p_.contacts[ci];
      Gradients& g = gradients_[ci];
      g.nn = RowN(c).squaredNorm();
      if (!Frictional(c)) continue;
      g.tt = RowT(c).squaredNorm();
      g.nt = RowN(c).dot(RowT(c));
    }
  }
  // The norm of the gradient of a·r_n + b·r_t in α.
  double GradientNorm(std::size_t ci, double a, double b) const {
    const Gradients& g = gradients_[ci];
    return std::sqrt(std::max(0.0, a * a * g.nn + 2.0 * a * b * g.nt + b * b * g.tt));
  }

  // A bound of a contact's law that it can reach in its state: the margin a·r_n + b·r_t
  // falls to −ε·weight, and the event that happens there. Both the ratio test and the reach
  // of the contact in the heap read these, so they watch the same bounds.
  struct Bound {
    double a = 0.0, b = 0.0, weight = 0.0;
    EventKind kind = EventKind::kNone;
    double sign = 0.0;  // kStartsSliding: the slip direction
  };
  int BoundsOf(std::size_t ci, std::array<Bound, 2>& bounds) const {
    const RateContact& c = p_.contacts[ci];
    const int k = static_cast<int>(ci);
    if (!Frictional(c) || (state_[ci] != ContactState::kStick && !associated_)) {
      // A frictionless contact, or one sliding under Coulomb's law (it reaches the apex),
      // opens at r_n = −ε w.
      bounds[0] = {1.0, 0.0, NormalWeight(k), EventKind::kOpens, 0.0};
      return 1;
    }
    if (state_[ci] != ContactState::kStick) {
      // Sliding under the associated law: the force meets the other edge, μ r_n − σ r_t.
      const double other = -SlipSign(k);
      bounds[0] = {c.mu, other, EdgeWeight(k, other), EventKind::kOpens, 0.0};
      return 1;
    }
    // y⁺ = μ r_n − r_t reaches −ε w: the friction force points along +t, the slip along −t.
    bounds[0] = {c.mu, -1.0, EdgeWeight(k, -1.0), EventKind::kStartsSliding, -1.0};
    bounds[1] = {c.mu, 1.0, EdgeWeight(k, 1.0), EventKind::kStartsSliding, 1.0};
    return 2;
  }

  // A contact's force S α (normal, tangential; the tangential 0 without friction).
  struct Pair {
    double n = 0.0, t = 0.0;
  };
  Pair Moved(const RateContact& c, const Eigen::VectorXd& alpha) const {
    return {RowN(c).dot(alpha), Frictional(c) ? RowT(c).dot(alpha) : 0.0};
  }
  Pair ForcesAt(const RateContact& c, const Eigen::VectorXd& alpha) const {
    const Pair moved = Moved(c, alpha);
    return {c.r0_n + moved.n, Frictional(c) ? c.r0_t + moved.t : 0.0};
  }

  // Puts a contact in the ratio test's heap with its reach at the forces r (order zero at
  // the path's point): its least margin to a bound, lowered by round-off, over the largest
  // rate at which that margin can fall per unit length of α's motion. Absent if open or held.
  void Track(std::size_t ci, const Pair& r) {
    const int k = static_cast<int>(ci);
    std::array<Bound, 2> bounds;
    const int n = BoundsOf(ci, bounds);
    double margin = kInf, rate = 0.0;
    for (int i = 0; i < n; ++i) {
      margin = std::min(margin, bounds[i].a * r.n + bounds[i].b * r.t);
      rate = std::max(rate, GradientNorm(ci, bounds[i].a, bounds[i].b));
    }
    margin -= kTie * (1.0 + std::abs(r.n) + std::abs(r.t));
    reach_.Set(k, rate > 0.0 ? arc_ + std::max(margin, 0.0) / rate : kInf);
  }
  void Track(std::size_t ci) {
    const RateContact& c = p_.contacts[ci];
    if (c.held || state_[ci] == ContactState::kOpen) {
      reach_.Remove(static_cast<int>(ci));
      return;
    }
    Track(ci, ForcesAt(c, alpha0_));
  }
  void TrackEveryContact() {
    arc_ = 0.0;
    reach_.Reset(static_cast<int>(p_.contacts.size()));
    for (std::size_t ci = 0; ci < p_.contacts.size(); ++ci) Track(ci);
    reach_stale_ = false;
  }

  // One piece: the unit direction (du, dt) in the kernel of K = [E P G | E d], from the
  // updated factorisation of Kᵀ (variables t, u₁ … u_m) where it is clearly of full rank.
  bool Direction(Eigen::VectorXd& dir) {
    const Eigen::Index m = epg_.rows();
    const auto epg = epg_.view();
    if (m == 0) {
      dir = Eigen::VectorXd::Ones(1);
      return true;
    }
    if (qr_updates_ >= kRefactorAfter) {
      Eigen::MatrixXd kt(m + 1, m);
      kt << ed_.transpose(), epg.transpose();
      qr_.Factorize(kt);
      qr_updates_ = 0;
    }
    if (qr_.DiagonalRatio() > kDoubtfulDiagonal) {
      // Q's last column, with the part of its residual in K's row space taken out once
      // (K = Rᵀ Q₁ᵀ): the updates' round-off would otherwise steer long paths elsewhere
      // than the pivoted factorisation (measured: 4 more of 100 paths at μ = 0.1 fail).
      Eigen::VectorXd z = qr_.q().col(m);
      const Eigen::VectorXd residual = epg * z.tail(m) + ed_ * z[0];
      z -= qr_.q().leftCols(m) *
           qr_.r().topRows(m).transpose().triangularView<Eigen::Lower>().solve(residual);
      z.normalize();
      dir.resize(m + 1);
      dir << z.tail(m), z[0];
      if ((epg * dir.head(m) + ed_ * dir[m]).norm() <= kKernelResidual) return true;
    }
    return PivotedDirection(dir);
  }

  // The same by a pivoted factorisation of K, with its rank decided. Where it is lost, the
  // kernel has more than one direction: false unless one of them is a collapse piece.
  bool PivotedDirection(Eigen::VectorXd& dir) {
    const Eigen::Index m = epg_.rows();
    Eigen::MatrixXd k(m, m + 1);
    k << epg_.view(), ed_;
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(k.transpose());
    qr.setThreshold(1e-11);
    // The last columns of Kᵀ's Q span K's kernel (only those are formed: O(m²) each).
    const Eigen::Index nullity = m + 1 - qr.rank();
    const Eigen::MatrixXd kernel =
        qr.householderQ() * Eigen::MatrixXd::Identity(m + 1, m + 1).rightCols(nullity);
    if (nullity <= 1) {
      dir = kernel.col(0);
      return true;
    }
    const Eigen::MatrixXd moves = ForceMoves(kernel);
    return CollapseInKernel(kernel, moves, dir) || BesideFreeMechanisms(kernel, moves, dir);
  }

  // dα per kernel column (variables u₁ … u_m, t).
  Eigen::MatrixXd ForceMoves(const Eigen::MatrixXd& kernel) const {
    const Eigen::Index m = kernel.rows() - 1;
    return pg_.view() * kernel.topRows(m) + direction_ * kernel.row(m);
  }

  // A kernel whose other directions are free mechanisms (neither the forces nor t move: a
  // grain spinning with every contact sliding): the one direction orthogonal to them. Any
  // amount of such a motion leaves the forces as they are, so the path may fix it (a gauge);
  // the step solved on the final pattern sets the grains' actual velocities.
  bool BesideFreeMechanisms(const Eigen::MatrixXd& kernel, const Eigen::MatrixXd& moves,
                            Eigen::VectorXd& dir) {
    Eigen::MatrixXd motion(dims_ + 1, kernel.cols());  // dα and dt per column
    motion << moves, kernel.row(kernel.rows() - 1);
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(motion, Eigen::ComputeFullV);
    const Eigen::VectorXd& sigma = svd.singularValues();
    Eigen::Index moving = 0;  // the columns of V whose motion moves forces or t
    while (moving < sigma.size() && sigma[moving] > kFreeMechanism) ++moving;
    if (moving != 1) return false;
    dir = (kernel * svd.matrixV().col(0)).normalized();
    ++free_mechanism_pieces_;
    return true;
  }

  // A kernel of several directions (the last columns of Kᵀ's Q, variables u₁ … u_m, t): the
  // combination that moves no force, where it moves t, is a collapse piece: a second
  // mechanism formed beside the one the path was growing, as on the 1600-disk pile, where
  // the path then ends exactly (lemke's F_crit). A combination that moves neither (a grain
  // spinning with every contact sliding) is a free mechanism (BesideFreeMechanisms).
  bool CollapseInKernel(const Eigen::MatrixXd& kernel, const Eigen::MatrixXd& moves,
                        Eigen::VectorXd& dir) const {
    const Eigen::Index m = kernel.rows() - 1;
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(moves, Eigen::ComputeFullV);
    const Eigen::Index last = kernel.cols() - 1;
    const double least = last < svd.singularValues().size() ? svd.singularValues()[last] : 0.0;
    const Eigen::VectorXd v = kernel * svd.matrixV().col(last);
    if (std::abs(v[m]) <= kRateTolerance || !MovesNoForce(least, v[m])) return false;
    dir = v.normalized();
    return true;
  }

  std::uint64_t StateHash() const {
    std::uint64_t h = 1469598103934665603ull;
    for (ContactState s : state_) h = (h ^ static_cast<std::uint64_t>(s)) * 1099511628211ull;
    return h;
  }

  // Follows the path until t reaches t_max (kCollapse returned for that), or it ends.
  RatePathEnd Follow(double t_max, RatePathResult& out) {
    Orientation orient = Orientation::kParameter;
    int oriented_contact = -1;
    double last_dt = 1.0;
    if (reach_stale_) TrackEveryContact();
    for (;;) {
      if (out.events >= options_.max_events || out.work >= options_.max_work)
        return RatePathEnd::kStalled;
      if (!seen_.insert(StateHash()).second && out.events > 0) return RatePathEnd::kCycle;
      UpdateSystem();
      Eigen::VectorXd dir;
      if (!Direction(dir)) return RatePathEnd::kSingular;
      const Eigen::Index m = static_cast<Eigen::Index>(unknowns_.size());
      Eigen::VectorXd dalpha = pg_.view() * dir.head(m) + dir[m] * direction_;
      if (MovesNoForce(dalpha.norm(), dir[m])) dalpha.setZero();
      double sign = Orient(orient, oriented_contact, dir, dalpha);
      // Where the quantity the event released does not move on the piece (e.g. beside a
      // free mechanism, which moved it), the piece goes on as t grows.
      if (sign == 0.0 && std::abs(dir[m]) > kRateTolerance) {
        sign = dir[m] > 0.0 ? 1.0 : -1.0;
        ++pieces_oriented_by_t_;
      }
      if (sign == 0.0) return RatePathEnd::kSingular;
      dir *= sign;
      dalpha *= sign;
      const double dt = dir[m];
      if (dt * last_dt < 0.0) ++out.turns;
      if (std::abs(dt) > kRateTolerance) last_dt = dt;
      last_dir_ = dir;
      last_dalpha_ = dalpha;
      last_dt_ = dt;
      last_unknowns_ = unknowns_;

      const Event next = NextEvent(dir, dalpha, t_max);
      if (next.kind == EventKind::kNone) {
        if (std::abs(dt) <= kRateTolerance) return RatePathEnd::kFixedCollapse;
        if (dt < 0.0) return RatePathEnd::kBack;
        return dalpha.isZero(0.0) ? RatePathEnd::kCollapse : RatePathEnd::kUnbounded;
      }
      for (Eigen::Index k = 0; k < m; ++k) {
        Lex& v = Value(unknowns_[static_cast<std::size_t>(k)]);
        v.v0 += next.step.v0 * dir[k];
        v.v1 += next.step.v1 * dir[k];
      }
      t_.v0 += next.step.v0 * dt;
      t_.v1 += next.step.v1 * dt;
      alpha0_ += next.step.v0 * dalpha;
      alpha1_ += next.step.v1 * dalpha;
      arc_ += next.step.v0 * dalpha.norm();
      if (next.kind == EventKind::kParameterLimit) return RatePathEnd::kCollapse;
      ++out.events;
      out.work += static_cast<double>(p_.basis.rows()) * static_cast<double>(dims_) +
                  static_cast<double>(m) * static_cast<double>(m);
      Apply(next, orient, oriented_contact);
      Track(static_cast<std::size_t>(next.contact));
    }
  }

  // +1 or −1: the orientation of the new piece along which the quantity that the last event
  // released grows (0: it does not move, a degenerate piece).
  double Orient(Orientation orient, int contact, const Eigen::VectorXd& dir,
                const Eigen::VectorXd& dalpha) const {
    const Eigen::Index m = static_cast<Eigen::Index>(unknowns_.size());
    double rate = 0.0;
    switch (orient) {
      case Orientation::kParameter: rate = dir[m]; break;
      case Orientation::kUnknown:
        for (Eigen::Index k = 0; k < m; ++k) {
          const Unknown& u = unknowns_[static_cast<std::size_t>(k)];
          if (u.contact == contact && u.kind == oriented_kind_) rate = dir[k];
        }
        break;
      case Orientation::kNormalForce: rate = RowN(ContactOf(contact)).dot(dalpha); break;
      case Orientation::kFrictionRow:
        rate = EdgeNormal(ContactOf(contact), friction_row_sign_).dot(dalpha);
        break;
    }
    if (std::abs(rate) > kRateTolerance) return rate > 0.0 ? 1.0 : -1.0;
    // A collapse piece (the forces held, t moving) after a contact sticks or closes: no force
    // can move along it, and it is followed as t grows.
    const bool oriented_by_force =
        orient == Orientation::kNormalForce || orient == Orientation::kFrictionRow;
    if (oriented_by_force && dalpha.isZero(0.0) && std::abs(dir[m]) > kRateTolerance)
      return dir[m] > 0.0 ? 1.0 : -1.0;
    return 0.0;
  }

  static void Consider(const Event& candidate, Event& best) {
    if (LexLess(candidate.step, best.step)) best = candidate;
  }
  // The step at which a value v₀ + ε v₁, changing at `rate` < 0 per unit step, reaches 0.
  static Lex StepTo(double v0, double v1, double rate) {
    return {std::max(0.0, v0) / -rate, v1 / -rate};
  }

  // The events of contact k along the piece: r its forces at the path's point (order
  // zero), their ε parts S α₁ and their rates S dα.
  void ConsiderContact(int k, const Pair& r, const Eigen::VectorXd& dalpha, Event& best) const {
    const auto ci = static_cast<std::size_t>(k);
    const RateContact& c = p_.contacts[ci];
    const Pair r1 = Moved(c, alpha1_), dr = Moved(c, dalpha);
    std::array<Bound, 2> bounds;
    const int n = BoundsOf(ci, bounds);
    for (int i = 0; i < n; ++i) {
      const Bound& b = bounds[i];
      const double rate = b.a * dr.n + b.b * dr.t;
      if (rate >= -kRateTolerance) continue;
      const double y = b.a * r.n + b.b * r.t, y1 = b.a * r1.n + b.b * r1.t + b.weight;
      Consider({b.kind, k, b.sign, StepTo(y, y1, rate)}, best);
    }
  }

  // The first event along the piece `dir`, on which α moves by dα per unit step.
  Event NextEvent(const Eigen::VectorXd& dir, const Eigen::VectorXd& dalpha, double t_max) {
    Event best;
    const Eigen::Index m = static_cast<Eigen::Index>(unknowns_.size());
    for (Eigen::Index k = 0; k < m; ++k) {
      const Unknown& u = unknowns_[static_cast<std::size_t>(k)];
      if (u.kind == UnknownKind::kOpenTangential || dir[k] >= -kRateTolerance) continue;
      const Lex v = Value(u);
      EventKind kind = EventKind::kCloses;
      double sign = 0.0;
      if (u.kind == UnknownKind::kSlip) kind = EventKind::kSlipStops;
      if (u.kind == UnknownKind::kApexPlus || u.kind == UnknownKind::kApexMinus) {
        kind = EventKind::kLeavesApex;
        sign = u.kind == UnknownKind::kApexPlus ? -1.0 : 1.0;
      }
      Consider({kind, u.contact, sign, StepTo(v.v0, v.v1, dir[k])}, best);
    }
    // A collapse piece moves no force: no contact reaches a bound on it.
    const double speed = dalpha.norm();
    if (speed > 0.0) {
      // Only the contacts whose reach the step can attain are read; the tie band keeps
      // those whose step differs from the best one at order zero by round-off only.
      const auto limit = [&] {
        const double step = best.step.v0;
        return step == kInf || options_.read_every_contact
                   ? kInf
                   : arc_ + speed * (step + 2.0 * kTie * (1.0 + std::abs(step)));
      };
      // The forces read for the test also give each taken contact its new reach.
      taken_.clear();
      taken_forces_.clear();
      const auto visit = [&](int k) {
        taken_forces_.push_back(ForcesAt(ContactOf(k), alpha0_));
        ConsiderContact(k, taken_forces_.back(), dalpha, best);
      };
      reach_.TakeWithin(limit, visit, taken_);
      for (std::size_t i = 0; i < taken_.size(); ++i)
        Track(static_cast<std::size_t>(taken_[i]), taken_forces_[i]);
    }
    const double dt = dir[m];
    if (dt > kRateTolerance && t_max < kInf) {
      const Lex step{(t_max - t_.v0) / dt, -t_.v1 / dt};
      if (!LexLess(best.step, step)) best = {EventKind::kParameterLimit, -1, 0.0, step};
    }
    return best;
  }

  void Apply(const Event& ev, Orientation& orient, int& contact) {
    const auto c = static_cast<std::size_t>(ev.contact);
    contact = ev.contact;
    switch (ev.kind) {
      case EventKind::kStartsSliding:
        state_[c] = ev.sign > 0.0 ? ContactState::kSlidePositive : ContactState::kSlideNegative;
        slip_[c] = Lex{};
        oriented_kind_ = UnknownKind::kSlip;
        orient = Orientation::kUnknown;
        break;
      case EventKind::kSlipStops:
        // Back inside the cone: the edge it slid on (μ r_n + σ r_t) must open up.
        friction_row_sign_ = SlipSign(ev.contact);
        state_[c] = ContactState::kStick;
        slip_[c] = Lex{};
        orient = Orientation::kFrictionRow;
        break;
      case EventKind::kOpens: {
        if (associated_ &&
            Frictional(ContactOf(ev.contact))) {  // the force reaches the apex: both edges' flows
          const bool on_minus_edge = state_[c] == ContactState::kSlidePositive;  // y⁻ active
          apex_minus_[c] = on_minus_edge ? slip_[c] : Lex{};
          apex_plus_[c] = on_minus_edge ? Lex{} : slip_[c];
          slip_[c] = Lex{};
          state_[c] = ContactState::kOpen;
          oriented_kind_ = on_minus_edge ? UnknownKind::kApexPlus : UnknownKind::kApexMinus;
          orient = Orientation::kUnknown;
          break;
        }
        const double s = state_[c] == ContactState::kStick ? 0.0 : SlipSign(ev.contact);
        open_t_[c] = {s * slip_[c].v0, s * slip_[c].v1};  // its tangential displacement goes on
        open_n_[c] = Lex{};
        slip_[c] = Lex{};
        state_[c] = ContactState::kOpen;
        oriented_kind_ = UnknownKind::kOpenNormal;
        orient = Orientation::kUnknown;
        break;
      }
      case EventKind::kLeavesApex: {
        // One edge's flow stops: the force leaves the apex along the other edge.
        const bool keeps_minus = ev.sign < 0.0;  // the y⁺ flow stopped
        slip_[c] = keeps_minus ? apex_minus_[c] : apex_plus_[c];
        apex_plus_[c] = apex_minus_[c] = Lex{};
        state_[c] = keeps_minus ? ContactState::kSlidePositive : ContactState::kSlideNegative;
        friction_row_sign_ = keeps_minus ? -1.0 : 1.0;  // the released edge must open up
        orient = Orientation::kFrictionRow;
        break;
      }
      case EventKind::kCloses: {
        const Lex tangential = open_t_[c];
        open_n_[c] = open_t_[c] = Lex{};
        // Closed again: it slides on with its tangential displacement (holonomic), or sticks.
        const bool slides =
            Frictional(ContactOf(ev.contact)) && (tangential.v0 != 0.0 || tangential.v1 != 0.0);
        if (slides) {
          const bool positive =
              tangential.v0 > 0.0 || (tangential.v0 == 0.0 && tangential.v1 > 0.0);
          state_[c] = positive ? ContactState::kSlidePositive : ContactState::kSlideNegative;
          slip_[c] = positive ? tangential : Lex{-tangential.v0, -tangential.v1};
        } else {
          state_[c] = ContactState::kStick;
        }
        orient = Orientation::kNormalForce;
        break;
      }
      default: break;
    }
  }

  // The value of an unknown's force equation at α (zero on the path): the force r₀ + S α
  // on the edge, the apex or at zero, as the unknown's kind asks.
  double EquationValue(const Unknown& u, const Eigen::VectorXd& alpha) const {
    const RateContact& c = ContactOf(u.contact);
    const double rn = c.r0_n + RowN(c).dot(alpha);
    const double rt = Frictional(c) ? c.r0_t + RowT(c).dot(alpha) : 0.0;
    switch (u.kind) {
      case UnknownKind::kSlip: return c.mu * rn + SlipSign(u.contact) * rt;
      case UnknownKind::kApexPlus: return c.mu * rn - rt;
      case UnknownKind::kApexMinus: return c.mu * rn + rt;
      case UnknownKind::kOpenNormal: return rn;
      case UnknownKind::kOpenTangential: return rt;
    }
    return 0.0;
  }

  // α with the drift of its equations removed: over many events the incremental updates
  // leave the forces of sliding and open contacts off their edges by round-off that grows
  // with the path; the least-norm change of the unknowns puts them back.
  Eigen::VectorXd PolishedAlpha() {
    Eigen::VectorXd alpha = alpha0_;
    if (unknowns_.empty()) return alpha;
    Eigen::VectorXd g(static_cast<Eigen::Index>(unknowns_.size()));
    for (std::size_t k = 0; k < unknowns_.size(); ++k)
      g[static_cast<Eigen::Index>(k)] = EquationValue(unknowns_[k], alpha);
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(epg_.view());
    const Eigen::VectorXd du = cod.solve(g);
    return alpha - pg_.view() * du;
  }

  RatePathResult& Finish(RatePathEnd end, const std::string& message, RatePathResult& out) {
    out.end = end;
    out.message = message;
    out.alpha = end == RatePathEnd::kCollapse ? PolishedAlpha() : alpha0_;
    out.t = t_.v0;
    out.free_mechanism_pieces = free_mechanism_pieces_;
    out.pieces_oriented_by_t = pieces_oriented_by_t_;
    out.states = state_;
    out.rates.assign(state_.size(), Eigen::Vector2d::Zero());
    out.alpha_rate = Eigen::VectorXd::Zero(dims_);
    if (last_dir_.size() > 0 && std::abs(last_dt_) > kRateTolerance) {
      const double per_t = 1.0 / last_dt_;
      out.alpha_rate = last_dalpha_ * per_t;
      for (std::size_t k = 0; k < last_unknowns_.size(); ++k) {
        const Unknown& u = last_unknowns_[k];
        const double rate = last_dir_[static_cast<Eigen::Index>(k)] * per_t;
        Eigen::Vector2d& r = out.rates[static_cast<std::size_t>(u.contact)];
        if (u.kind == UnknownKind::kSlip) r[1] = SlipSign(u.contact) * rate;
        else if (u.kind == UnknownKind::kOpenNormal) r[0] = rate;
        else r[1] = rate;
      }
    }
    return out;
  }

  const RateProblem& p_;
  RatePathOptions options_;
  Eigen::Index dims_;
  std::vector<ContactState> state_;
  std::vector<Lex> slip_, open_n_, open_t_;
  std::vector<Lex> apex_plus_, apex_minus_;  // associated law at the apex: the two edges' flows
  std::vector<Weights> weights_;
  bool associated_ = false;
  int free_mechanism_pieces_ = 0;  // RatePathResult's counts, over every phase
  int pieces_oriented_by_t_ = 0;
  double weight_scale_ = 1.0;
  UnknownKind oriented_kind_ = UnknownKind::kSlip;
  // The linear system of the current piece, kept up to date unknown by unknown.
  std::vector<Unknown> unknowns_;
  std::vector<double> slip_sign_;
  GivensQr qr_;  // of Kᵀ, rows t, u₁ … u_m
  int qr_updates_ = 0;
  ResizableMatrix pg_, e_, epg_;
  Eigen::VectorXd ed_;
  Eigen::MatrixXd released_;  // Q of P = I − Q Qᵀ
  Eigen::VectorXd release_, direction_;
  // α at the path's point (order zero and ε), moved piece by piece: recomputing α from t
  // and the unknowns cancels terms of size t, which reaches 1e15 past collapse pieces.
  Eigen::VectorXd alpha0_, alpha1_;
  // Sᵀ: a contact's rows of S are read one contact at a time (the ratio test), contiguous here.
  Eigen::MatrixXd st_;
  struct Gradients {
    double nn = 0.0, tt = 0.0, nt = 0.0;
  };
  std::vector<Gradients> gradients_;
  // The ratio test's contacts by reach (reach_heap.hpp), the length of α's path so far.
  ReachHeap reach_;
  std::vector<int> taken_;
  std::vector<Pair> taken_forces_;
  double arc_ = 0.0;
  bool reach_stale_ = true;
  bool release_possible_ = true;
  Lex t_;
  double friction_row_sign_ = 1.0;
  std::unordered_set<std::uint64_t> seen_;
  Eigen::VectorXd last_dalpha_, last_dir_;
  double last_dt_ = 0.0;
  std::vector<Unknown> last_unknowns_;
};

}  // namespace

double RateProblem::StaticImpulse(int row) const {
  for (const RateContact& c : contacts) {
    if (c.row_n == row) return c.r0_n;
    if (c.row_t == row) return c.r0_t;
  }
  return 0.0;
}

RatePathResult FollowRatePath(const RateProblem& problem, const RatePathOptions& options) {
  PathFollower follower(problem, options);
  return follower.Run();
}

}  // namespace unjam
