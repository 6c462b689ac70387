#include "unjam/indeterminacy/force_bounds.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

#include <ClpSimplex.hpp>
#include <SuiteSparseQR.hpp>

#include "ensemble_lp.hpp"
#include "ipopt_lp.hpp"
#include "unjam/parallel/for_each_index.hpp"

namespace unjam {

const char* ToString(BoundStatus status) {
  switch (status) {
    case BoundStatus::kOptimal: return "optimal";
    case BoundStatus::kUnbounded: return "unbounded";
    case BoundStatus::kInfeasible: return "infeasible";
    case BoundStatus::kFailed: return "failed";
  }
  return "?";
}

std::optional<BoundStatus> BoundStatusFromString(const std::string& name) {
  for (BoundStatus status : {BoundStatus::kOptimal, BoundStatus::kUnbounded,
                             BoundStatus::kInfeasible, BoundStatus::kFailed}) {
    if (name == ToString(status)) return status;
  }
  return std::nullopt;
}

const char* ToString(BoundKind kind) {
  switch (kind) {
    case BoundKind::kMax: return "max";
    case BoundKind::kMaxWithoutFriction: return "max_without_friction";
    case BoundKind::kMin: return "min";
  }
  return "?";
}

std::optional<BoundKind> BoundKindFromString(const std::string& name) {
  for (BoundKind kind : {BoundKind::kMax, BoundKind::kMaxWithoutFriction, BoundKind::kMin}) {
    if (name == ToString(kind)) return kind;
  }
  return std::nullopt;
}

const char* ToString(LpBackend backend) { return backend == LpBackend::kClp ? "clp" : "ipopt"; }

LpBackend LpBackendFromString(const std::string& name) {
  if (name == "clp") return LpBackend::kClp;
  if (name == "ipopt") return LpBackend::kIpopt;
  throw std::invalid_argument("unknown LP backend '" + name + "' (available: clp, ipopt)");
}

using indeterminacy_internal::Outcome;
using indeterminacy_internal::Simplex;

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// One LP: optimise sign·f_n,k with the current bounds; primal simplex from the current basis
// (warm), or from the slack basis (cold).
// CLP's start/finish options 1|2|4: keep the factorisation and work areas between solves
// and reuse them; only the objective (or one bound) changes from one LP to the next.
constexpr int kKeepFactorisation = 7;
constexpr int kFactorizationFrequency = 100;

Bound Optimise(ClpSimplex& model, int column, double sign, bool warm, bool bounds_changed,
               double scale, long long& iterations) {
  model.setObjectiveCoefficient(column, sign);
  if (!warm) model.allSlackBasis(true);
  // A tightened bound leaves the basis dual feasible, not primal: dual simplex then.
  Simplex(model, bounds_changed && warm, warm ? kKeepFactorisation : 0, !bounds_changed,
          iterations);
  Bound b = Outcome(model, sign, scale);
  model.setObjectiveCoefficient(column, 0.0);
  return b;
}

// The bound of one kind for contact k.
Bound BoundOf(ClpSimplex& model, const EquilibriumSystem& s, int k, BoundKind kind,
              const BoundsOptions& o, long long& iterations) {
  const int normal = s.UnknownsPerContact() * k;
  if (o.lp == LpBackend::kIpopt) {
    const int fixed = kind == BoundKind::kMaxWithoutFriction ? normal + 1 : -1;
    return indeterminacy_internal::IpoptBound(s, normal, kind == BoundKind::kMin ? 1.0 : -1.0,
                                              fixed, o.lp_tolerance, iterations);
  }
  if (kind == BoundKind::kMin)
    return Optimise(model, normal, 1.0, o.warm_start, false, s.force_scale, iterations);
  if (kind == BoundKind::kMax)
    return Optimise(model, normal, -1.0, o.warm_start, false, s.force_scale, iterations);
  const int tangential = normal + 1;
  model.setColumnBounds(tangential, 0.0, 0.0);
  const Bound b = Optimise(model, normal, -1.0, o.warm_start, true, s.force_scale, iterations);
  model.setColumnBounds(tangential, -kInfinity, kInfinity);
  return b;
}

// Neighbouring contacts have nearby optimal vertices, so each warm start is short when the
// contacts come in a spatial order: serpentine bands one diameter (2 R_max = 2) high.
std::vector<int> SpatialOrder(const EquilibriumSystem& s, const std::vector<int>& contacts) {
  std::vector<int> order(contacts.size());
  for (std::size_t a = 0; a < order.size(); ++a) order[a] = static_cast<int>(a);
  auto key = [&](int a) {
    const Vec2& p = s.contact_points[contacts[a]];
    const long band = static_cast<long>(std::floor(p.y() / 2.0));
    return std::pair<long, double>(band, band % 2 == 0 ? p.x() : -p.x());
  };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  return order;
}

using KnownBounds = std::map<std::pair<int, BoundKind>, Bound>;

KnownBounds ByContactAndKind(const std::vector<BoundRecord>& records) {
  KnownBounds known;
  for (const BoundRecord& r : records) known[{r.contact, r.kind}] = r.bound;
  return known;
}

// BoundsOptions::known by contact and kind, and the serialised BoundsOptions::on_bound.
class BoundLog {
 public:
  explicit BoundLog(const BoundsOptions& o)
      : known_(ByContactAndKind(o.known)), on_bound_(o.on_bound) {}
  const Bound* Known(int contact, BoundKind kind) const {
    const auto it = known_.find({contact, kind});
    return it == known_.end() ? nullptr : &it->second;
  }
  void Add(const BoundRecord& r) {
    if (!on_bound_) return;
    const std::lock_guard<std::mutex> lock(mutex_);
    on_bound_(r);
  }

 private:
  KnownBounds known_;
  const std::function<void(const BoundRecord&)>& on_bound_;
  std::mutex mutex_;
};

}  // namespace

BoundsReport ComputeForceBounds(const EquilibriumSystem& system, const std::vector<int>& contacts,
                                const Eigen::VectorXd& reference, const BoundsOptions& options) {
  if (options.shares < 1 || options.share < 0 || options.share >= options.shares) {
    throw std::invalid_argument("ComputeForceBounds: share " + std::to_string(options.share) +
                                " of " + std::to_string(options.shares));
  }
  const auto start = std::chrono::steady_clock::now();
  BoundsReport report;
  std::unique_ptr<ClpSimplex> base =
      indeterminacy_internal::EnsembleModel(system, options.lp_tolerance);
  Simplex(*base, false, 0, true,
          report.lp_iterations);  // feasibility; the first basis of every block
  report.feasible = base->isProvenOptimal();
  report.bounds.resize(contacts.size());
  const int stride = system.UnknownsPerContact();
  if (!report.feasible) {
    report.message = base->isProvenPrimalInfeasible()
                         ? "no admissible force network: the packing is not static within the gap "
                           "tolerance (a carrying contact left out, or unbalanced particles)"
                         : "CLP stopped with status " + std::to_string(base->status());
    for (std::size_t a = 0; a < contacts.size(); ++a) {
      ContactBounds& b = report.bounds[a];
      b.contact = contacts[a];
      b.reference = reference.size() > 0 ? reference[stride * contacts[a]] : 0.0;
      b.min.status = b.max.status = b.max_without_friction.status = BoundStatus::kInfeasible;
    }
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
  }
  const int threads = options.lp == LpBackend::kIpopt ? 1 : options.threads;
  const int blocks =
      std::max(1, std::min<int>(threads * options.shares, static_cast<int>(contacts.size())));
  const int own_first = std::min(blocks, options.share * threads),
            own_last = std::min(blocks, (options.share + 1) * threads);
  std::vector<long long> iterations(blocks, 0);
  // Blocks of the spatial order; within a block all maxima, then the maxima without
  // friction, then the minima: successive LPs differ least.
  const std::vector<int> order = SpatialOrder(system, contacts);
  for (std::size_t a = 0; a < contacts.size(); ++a) {
    report.bounds[a].contact = contacts[a];
    report.bounds[a].reference = reference.size() > 0 ? reference[stride * contacts[a]] : 0.0;
  }
  std::vector<long long> skipped(blocks, 0), known(blocks, 0);
  std::vector<char> stopped(blocks, 0);
  BoundLog log(options);
  auto run_block = [&](int block) {
    ClpSimplex model(*base);
    // Refactorise every 100 pivots instead of CLP's 200: the updates of the factors grow
    // dense here, and the warm-started LPs ran 7-10 % faster for the same pivots (N=3000).
    model.setFactorizationFrequency(kFactorizationFrequency);
    const std::size_t first = order.size() * block / blocks;
    const std::size_t last = order.size() * (block + 1) / blocks;
    // What the optimal solutions of this block have shown (the shortcuts, see below).
    std::vector<char> zero_seen(system.contacts.size(), 0);
    std::vector<char> max_without_tangential(system.contacts.size(), 0);
    auto record = [&](const ClpSimplex& m) {
      const double* x = m.primalColumnSolution();
      for (std::size_t k = 0; k < system.contacts.size(); ++k) {
        if (x[stride * k] <= 0.0) zero_seen[k] = 1;
      }
    };
    const bool shortcuts = options.shortcuts && options.lp == LpBackend::kClp;
    if (shortcuts) record(model);
    // Maxima first: their solutions, like every optimal one, are admissible networks, and
    // the contacts they leave without force need no minimisation.
    for (BoundKind kind : {BoundKind::kMax, BoundKind::kMaxWithoutFriction, BoundKind::kMin}) {
      if (kind == BoundKind::kMaxWithoutFriction && !system.frictional) {  // the same LP as max
        for (std::size_t a = first; a < last; ++a)
          report.bounds[order[a]].max_without_friction = report.bounds[order[a]].max;
        continue;
      }
      for (std::size_t a = first; a < last; ++a) {
        ContactBounds& b = report.bounds[order[a]];
        const int k = b.contact;
        if (const Bound* given = log.Known(k, kind)) {
          b.Of(kind) = *given;
          ++known[block];
          continue;
        }
        // Exact shortcuts. An admissible network with f_n,k = 0 exists: min f_n,k = 0. The
        // maximising network carries no tangential force at k: it is also the maximum
        // without friction (which is never larger).
        const bool zero_min = shortcuts && kind == BoundKind::kMin && zero_seen[k];
        if (zero_min ||
            (shortcuts && kind == BoundKind::kMaxWithoutFriction && max_without_tangential[k])) {
          b.Of(kind) = zero_min ? Bound{BoundStatus::kOptimal, 0.0} : b.max;
          ++skipped[block];
          log.Add({k, kind, b.Of(kind), 0, true});
          continue;
        }
        if (options.start_before && std::chrono::steady_clock::now() >= *options.start_before) {
          stopped[block] = 1;
          return;
        }
        const long long before = iterations[block];
        const Bound bound = BoundOf(model, system, k, kind, options, iterations[block]);
        b.Of(kind) = bound;
        log.Add({k, kind, bound, iterations[block] - before, false});
        if (!shortcuts || !bound.ok()) continue;
        record(model);
        if (kind == BoundKind::kMax && system.frictional &&
            std::abs(model.primalColumnSolution()[stride * k + 1]) <= options.lp_tolerance) {
          max_without_tangential[k] = 1;
        }
      }
    }
  };
  // One thread per block: each block's LPs warm-start one another in a fixed order, so a
  // block's bounds do not depend on which thread runs it.
  const int own_blocks = own_last - own_first;
  parallel::ForEachIndex(own_blocks, parallel::OnThreads(own_blocks),
                         [&](int b) { run_block(own_first + b); });
  for (long long i : iterations) report.lp_iterations += i;
  for (long long i : skipped) report.lps_skipped += i;
  for (long long i : known) report.bounds_known += i;
  report.complete = std::count(stopped.begin(), stopped.end(), 1) == 0;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

BoundsReport BoundsFromRecords(const EquilibriumSystem& system, const std::vector<int>& contacts,
                               const Eigen::VectorXd& reference,
                               const std::vector<BoundRecord>& known) {
  const auto start = std::chrono::steady_clock::now();
  const KnownBounds by_key = ByContactAndKind(known);
  const int stride = system.UnknownsPerContact();
  BoundsReport report;
  report.feasible = true;
  report.bounds.resize(contacts.size());
  for (std::size_t a = 0; a < contacts.size(); ++a) {
    ContactBounds& b = report.bounds[a];
    b.contact = contacts[a];
    b.reference = reference.size() > 0 ? reference[stride * contacts[a]] : 0.0;
    for (BoundKind kind : {BoundKind::kMax, BoundKind::kMaxWithoutFriction, BoundKind::kMin}) {
      if (kind == BoundKind::kMaxWithoutFriction && !system.frictional) {
        b.max_without_friction = b.max;
      } else if (const auto it = by_key.find({b.contact, kind}); it != by_key.end()) {
        b.Of(kind) = it->second;
        ++report.bounds_known;
      } else {
        report.complete = false;
      }
    }
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

namespace {

double LargestColumnNorm(const Eigen::SparseMatrix<double>& a) {
  double largest = 0.0;
  for (int k = 0; k < a.outerSize(); ++k) {
    double norm2 = 0.0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, k); it; ++it)
      norm2 += it.value() * it.value();
    largest = std::max(largest, std::sqrt(norm2));
  }
  return largest;
}

// Rank estimate of a sparse matrix by SuiteSparseQR (long-index API).
int SparseRank(const Eigen::SparseMatrix<double>& a, double tolerance) {
  if (a.nonZeros() == 0) return 0;
  cholmod_common cc;
  cholmod_l_start(&cc);
  Eigen::SparseMatrix<double> compressed = a;
  compressed.makeCompressed();
  cholmod_sparse* m =
      cholmod_l_allocate_sparse(a.rows(), a.cols(), a.nonZeros(), 1, 1, 0, CHOLMOD_REAL, &cc);
  auto* p = static_cast<SuiteSparse_long*>(m->p);
  auto* i = static_cast<SuiteSparse_long*>(m->i);
  auto* x = static_cast<double*>(m->x);
  for (int k = 0; k <= compressed.cols(); ++k) p[k] = compressed.outerIndexPtr()[k];
  for (int k = 0; k < compressed.nonZeros(); ++k) {
    i[k] = compressed.innerIndexPtr()[k];
    x[k] = compressed.valuePtr()[k];
  }
  cholmod_sparse* r = nullptr;
  SuiteSparse_long* e = nullptr;
  const SuiteSparse_long rank =
      SuiteSparseQR<double>(SPQR_ORDERING_DEFAULT, tolerance, 0, m, &r, &e, &cc);
  cholmod_l_free_sparse(&r, &cc);
  if (e != nullptr) cholmod_l_free(a.cols(), sizeof(SuiteSparse_long), e, &cc);
  cholmod_l_free_sparse(&m, &cc);
  cholmod_l_finish(&cc);
  return static_cast<int>(rank);
}

// Exact dependencies among the rows: when every contact joins two particles that balance,
// the x rows (and the y rows) of all particles sum to zero identically (each contact adds f
// to one and −f to the other). Each such identity caps the rank by one.
int TranslationIdentities(const EquilibriumSystem& s) {
  // Every balancing particle owns one block of rows (x, y[, torque]) and the cell row comes
  // last, so the x rows are those with r % block = 0 and the y rows r % block = 1.
  const int block = s.frictional ? 3 : 2;
  int identities = 0;
  for (int axis = 0; axis < 2; ++axis) {
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(s.matrix.cols());
    double scale = 0.0;
    for (int k = 0; k < s.matrix.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(s.matrix, k); it; ++it) {
        const int r = static_cast<int>(it.row());
        if (s.row_particle[r] < 0 || r % block != axis) continue;
        sum[it.col()] += it.value();
        scale = std::max(scale, std::abs(it.value()));
      }
    }
    if (scale > 0.0 && sum.lpNorm<Eigen::Infinity>() <= 1e-12 * scale) ++identities;
  }
  return identities;
}

}  // namespace

Indeterminacy ForceIndeterminacy(const EquilibriumSystem& system) {
  Indeterminacy out;
  const Eigen::SparseMatrix<double>& a = system.matrix;
  out.unknowns = static_cast<int>(a.cols());
  out.equations = static_cast<int>(a.rows());
  out.tolerance = 1e-10 * LargestColumnNorm(a);
  // SuiteSparseQR's rank is an estimate (Heath's method): it can miss a dependency and
  // overestimate. Two estimates (QR of A and of Aᵀ) and the exact identities among the rows
  // are upper bounds; the rank is their minimum. Checked against a dense SVD on the bundled
  // N=500 packings, where the singular values jump from 1e-2 to 1e-15: the QR of A alone
  // said 1374 for 1373 (μ = 0.1) and 1411 for 1409 (μ = 0.01).
  out.rank_of_a = SparseRank(a, out.tolerance);
  out.rank_transposed = SparseRank(a.transpose(), out.tolerance);
  out.rank =
      std::min({out.rank_of_a, out.rank_transposed, out.equations - TranslationIdentities(system)});
  out.dimension = out.unknowns - out.rank;
  return out;
}

}  // namespace unjam
