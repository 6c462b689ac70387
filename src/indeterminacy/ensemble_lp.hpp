// The force ensemble (equilibrium_system.hpp) as the rows, columns and bounds of a linear
// program over f / F (F the force scale, so that solver tolerances are relative): rows
// A f = b / F, then per frictional contact ±f_t − μ f_n ≤ 0; columns f_n ≥ 0, f_t free.
// The one description that the nearest-network LP, the bounds (CLP) and Ipopt all load.
// Internal to src/indeterminacy.
#pragma once

#include <vector>

#include <ClpSimplex.hpp>

#include "unjam/indeterminacy/equilibrium_system.hpp"

namespace unjam::indeterminacy_internal {

struct LpTriplets {
  std::vector<int> rows, cols;
  std::vector<double> values;
  std::vector<double> col_lower, col_upper, row_lower, row_upper;  // ±infinity where free

  void Add(int row, int col, double value) {
    rows.push_back(row);
    cols.push_back(col);
    values.push_back(value);
  }
  int AddRow(double lower, double upper) {
    row_lower.push_back(lower);
    row_upper.push_back(upper);
    return static_cast<int>(row_lower.size()) - 1;
  }
};

LpTriplets EnsembleLp(const EquilibriumSystem& system);

// Loads `lp` with the given objective (one entry per column) into a CLP model, silent,
// with primal and dual tolerances `tolerance`.
void LoadIntoClp(const LpTriplets& lp, const std::vector<double>& objective, double tolerance, ClpSimplex& model);

}  // namespace unjam::indeterminacy_internal
