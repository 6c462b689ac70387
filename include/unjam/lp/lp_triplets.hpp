// A linear program built up row by row and column by column, and loaded into COIN-OR CLP:
// the one builder of the project's LPs (the kinematic admissibility of a step, the pattern
// LP of solvers/pattern_lp.hpp, the force ensemble of src/indeterminacy). Internal to the
// library: included only from src/ (it includes CLP, which unjam_core links privately).
#pragma once

#include <vector>

#include <ClpSimplex.hpp>
#include <Eigen/Core>

namespace unjam::lp {

struct LpTriplets {
  std::vector<int> rows, cols;
  std::vector<double> values;
  std::vector<double> col_lower, col_upper, row_lower, row_upper;  // ±infinity where free
  std::vector<double> objective;                                   // per column

  // n new columns with these bounds and cost; returns the first one's index.
  int AddColumns(int n, double lower, double upper, double cost = 0.0);
  int AddRow(double lower, double upper);
  void Add(int row, int col, double value) {
    rows.push_back(row);
    cols.push_back(col);
    values.push_back(value);
  }
  void FixColumn(int col) { col_lower[col] = col_upper[col] = 0.0; }
  int NumRows() const { return static_cast<int>(row_lower.size()); }
  int NumColumns() const { return static_cast<int>(col_lower.size()); }
};

// Columns e⁺, e⁻ ≥ 0 of cost 1 and rows x_c − e⁺_c + e⁻_c = target_c for the columns
// [first, first + target.size()): with no other costs the LP minimises Σ |x − target|.
void AddL1Distance(LpTriplets& lp, int first, const Eigen::VectorXd& target);

// Loads `lp` (its objective included) into a CLP model, silent, with CLP's default
// tolerances. Rows and columns without entries are kept: the triplets alone would not
// imply trailing ones.
void LoadIntoClp(const LpTriplets& lp, ClpSimplex& model);
// The same with primal and dual tolerances `tolerance`.
void LoadIntoClp(const LpTriplets& lp, double tolerance, ClpSimplex& model);

}  // namespace unjam::lp
