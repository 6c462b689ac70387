#include "region_projection.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/SparseCore>

#include "unjam/indeterminacy/admissible_forces.hpp"
#include "unjam/indeterminacy/least_norm.hpp"

namespace unjam::indeterminacy_internal {

std::vector<Region> ClassifyRegions(const EquilibriumSystem& s, const Eigen::VectorXd& f,
                                    double edge_tolerance) {
  const int stride = s.UnknownsPerContact();
  std::vector<Region> regions(s.contacts.size(), Region::kOff);
  for (std::size_t k = 0; k < regions.size(); ++k) {
    const double fn = f[stride * k];
    const double ft = s.frictional ? f[stride * k + 1] : 0.0;
    if (s.frictional && fn > 0.0 && std::abs(ft) >= s.mu * fn * (1.0 - edge_tolerance)) {
      regions[k] = ft >= 0.0 ? Region::kEdgePositive : Region::kEdgeNegative;
    } else {
      regions[k] = Region::kInside;
    }
  }
  return regions;
}

namespace {

// The free directions of every contact (columns of D) and the base point of the correction:
// unchanged inside, moved onto the edge exactly on an edge, zero when off.
struct Directions {
  Eigen::SparseMatrix<double> matrix;  // unknowns × free directions
  Eigen::VectorXd base;
};

Directions FreeDirections(const EquilibriumSystem& s, const Eigen::VectorXd& f,
                          const std::vector<Region>& regions) {
  const int stride = s.UnknownsPerContact();
  Directions d;
  d.base = Eigen::VectorXd::Zero(s.NumUnknowns());
  std::vector<Eigen::Triplet<double>> t;
  int column = 0;
  for (std::size_t k = 0; k < regions.size(); ++k) {
    const int n = stride * static_cast<int>(k);
    switch (regions[k]) {
      case Region::kOff: break;
      case Region::kInside:
        d.base[n] = std::max(f[n], 0.0);
        if (stride == 2) d.base[n + 1] = std::clamp(f[n + 1], -s.mu * d.base[n], s.mu * d.base[n]);
        for (int a = 0; a < stride; ++a) t.emplace_back(n + a, column++, 1.0);
        break;
      case Region::kEdgePositive:
      case Region::kEdgeNegative: {
        const double sign = regions[k] == Region::kEdgePositive ? 1.0 : -1.0;
        const double norm = std::sqrt(1.0 + s.mu * s.mu);
        d.base[n] = std::max(f[n], 0.0);
        d.base[n + 1] = sign * s.mu * d.base[n];
        t.emplace_back(n, column, 1.0 / norm);
        t.emplace_back(n + 1, column++, sign * s.mu / norm);
        break;
      }
    }
  }
  d.matrix.resize(s.NumUnknowns(), column);
  d.matrix.setFromTriplets(t.begin(), t.end());
  return d;
}

// Moves contacts that left their region (negative normal force: off; outside the cone:
// onto the edge it crossed). Returns the number of contacts moved.
int UpdateRegions(const EquilibriumSystem& s, const Eigen::VectorXd& f,
                  std::vector<Region>& regions) {
  const int stride = s.UnknownsPerContact();
  int moved = 0;
  for (std::size_t k = 0; k < regions.size(); ++k) {
    if (regions[k] == Region::kOff) continue;
    const int n = stride * static_cast<int>(k);
    if (f[n] < 0.0) {
      regions[k] = Region::kOff;
      ++moved;
    } else if (regions[k] == Region::kInside && s.frictional && std::abs(f[n + 1]) > s.mu * f[n]) {
      regions[k] = f[n + 1] >= 0.0 ? Region::kEdgePositive : Region::kEdgeNegative;
      ++moved;
    }
  }
  return moved;
}

// The least-squares correction of smallest norm within fixed regions.
std::optional<Eigen::VectorXd> CorrectWithinRegions(const EquilibriumSystem& s,
                                                    const Eigen::VectorXd& reference,
                                                    const std::vector<Region>& regions) {
  const Directions d = FreeDirections(s, reference, regions);
  // A particle whose rows are dependent (too few contacts) makes B Bᵀ singular: the
  // solver's ridge gives the least-squares correction, and the balance check then fails
  // honestly.
  const LeastNormSolver least_norm(s.matrix * d.matrix, 1e-12);
  if (!least_norm.ok()) return std::nullopt;
  Eigen::VectorXd f = d.base;
  for (int refinement = 0; refinement < 3; ++refinement) {
    const Eigen::VectorXd step = least_norm.Solve(s.load - s.matrix * f);
    if (!step.allFinite()) return std::nullopt;
    f += d.matrix * step;
  }
  return f;
}

}  // namespace

std::optional<Eigen::VectorXd> ProjectOntoAdmissible(const EquilibriumSystem& s,
                                                     const Eigen::VectorXd& reference,
                                                     std::vector<Region> regions, double tolerance,
                                                     int max_rounds) {
  for (int round = 0; round < max_rounds; ++round) {
    std::optional<Eigen::VectorXd> f = CorrectWithinRegions(s, reference, regions);
    if (!f) return std::nullopt;
    if (UpdateRegions(s, *f, regions) > 0) continue;
    // Round-off on the cone boundary is clamped onto it (well below the tolerance).
    const int stride = s.UnknownsPerContact();
    if (s.frictional) {
      for (std::size_t k = 0; k < regions.size(); ++k) {
        const double bound = s.mu * (*f)[stride * k];
        (*f)[stride * k + 1] = std::clamp((*f)[stride * k + 1], -bound, bound);
      }
    }
    if (BalanceResidual(s, *f) > tolerance) return std::nullopt;
    return f;
  }
  return std::nullopt;
}

}  // namespace unjam::indeterminacy_internal
