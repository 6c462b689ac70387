// Writing the Siconos numerics `.dat` format (docs/format.md, "Siconos problem format"),
// laid out as Siconos' own writer (frictionContact_printInFile) but with shortest
// round-trip doubles instead of %32.24e: both read back to the same bits.
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "text_fields.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/io/siconos_problem.hpp"

namespace unjam {

namespace {

using io_internal::AppendDouble;

void AppendLine(std::string& out, long long value) { out += std::to_string(value) + '\n'; }

void AppendValues(std::string& out, const Eigen::Ref<const Eigen::VectorXd>& values) {
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    if (i > 0) out += ' ';
    AppendDouble(out, values[i]);
  }
  out += '\n';
}

// Storage 0: the size again, then the values column by column, one column per line.
void AppendDense(std::string& out, const Eigen::SparseMatrix<double>& w) {
  const Eigen::MatrixXd dense(w);
  out += std::to_string(dense.rows()) + '\t' + std::to_string(dense.cols()) + '\n';
  for (Eigen::Index col = 0; col < dense.cols(); ++col) AppendValues(out, dense.col(col));
}

// The 2×2 blocks of W by (block row, block column), in row-major order: every diagonal
// block (Siconos' 2D NSGS reads them) and every block holding a stored entry.
std::map<std::pair<int, int>, Eigen::Matrix2d> Blocks(const Eigen::SparseMatrix<double>& w) {
  std::map<std::pair<int, int>, Eigen::Matrix2d> blocks;
  for (int k = 0; k < w.rows() / 2; ++k) blocks[{k, k}] = Eigen::Matrix2d::Zero();
  for (int col = 0; col < w.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(w, col); it; ++it) {
      const int row = static_cast<int>(it.row());
      auto [entry, inserted] = blocks.try_emplace({row / 2, col / 2}, Eigen::Matrix2d::Zero());
      entry->second(row % 2, col % 2) = it.value();
    }
  }
  return blocks;
}

// Storage 1: the SparseBlockStructuredMatrix layout of SBM_write_in_file.
void AppendSparseBlock(std::string& out, const Eigen::SparseMatrix<double>& w) {
  const int nc = static_cast<int>(w.rows() / 2);
  const auto blocks = Blocks(w);
  AppendLine(out, static_cast<long long>(blocks.size()));
  AppendLine(out, nc);
  AppendLine(out, nc);
  std::string ends;
  for (int k = 1; k <= nc; ++k) ends += std::to_string(2 * k) + (k < nc ? " " : "\n");
  out += ends + ends;  // cumulative row ends, then column ends
  AppendLine(out, nc + 1);
  AppendLine(out, static_cast<long long>(blocks.size()));
  std::vector<long long> row_start(nc + 1, 0);
  for (const auto& [key, block] : blocks) ++row_start[key.first + 1];
  for (int i = 0; i < nc; ++i) row_start[i + 1] += row_start[i];
  for (int i = 0; i <= nc; ++i) out += std::to_string(row_start[i]) + (i < nc ? " " : "\n");
  const char* separator = "";
  for (const auto& [key, block] : blocks) {
    out += separator;
    out += std::to_string(key.second);
    separator = " ";
  }
  out += '\n';
  long long number = 0;
  for (const auto& [key, block] : blocks) {
    AppendLine(out, number++);
    AppendValues(out, Eigen::Map<const Eigen::VectorXd>(block.data(), 4));  // column-major
  }
}

}  // namespace

std::string FormatSiconosProblem(const DelassusProblem& p, SiconosStorage storage) {
  Validate(p);
  if (p.NumContacts() == 0)
    throw std::invalid_argument(
        "the problem has no contacts: a Siconos problem needs at least one");
  for (int k = 0; k < p.NumContacts(); ++k) {
    if (p.laws[k].kind == ConstraintKind::kBilateral) {
      throw std::invalid_argument("contact " + std::to_string(k) +
                                  " is held at a prescribed gap (bilateral): Siconos' "
                                  "friction-contact problem has unilateral contacts only");
    }
  }
  std::string out;
  AppendLine(out, 2);
  AppendLine(out, p.NumContacts());
  AppendLine(out, static_cast<int>(storage));
  AppendLine(out, p.NumUnknowns());
  AppendLine(out, p.NumUnknowns());
  if (storage == SiconosStorage::kDense) AppendDense(out, p.w);
  else AppendSparseBlock(out, p.w);
  AppendValues(out, p.q);
  Eigen::VectorXd mu(p.NumContacts());
  for (int k = 0; k < p.NumContacts(); ++k) mu[k] = p.laws[k].mu;
  AppendValues(out, mu);
  return out;
}

void WriteSiconosProblem(const DelassusProblem& p, const std::filesystem::path& path,
                         SiconosStorage storage) {
  std::string text;
  try {
    text = FormatSiconosProblem(p, storage);
  } catch (const std::invalid_argument& e) {
    throw OutputError("cannot write '" + path.string() + "': " + e.what());
  }
  WriteFileAtomically(path, text);
}

void WriteImpulses(const Eigen::VectorXd& impulses, const std::filesystem::path& path) {
  if (impulses.size() % 2 != 0) {
    throw OutputError("cannot write '" + path.string() + "': " + std::to_string(impulses.size()) +
                      " impulses, expected two per contact");
  }
  std::string text;
  for (Eigen::Index k = 0; k < impulses.size() / 2; ++k)
    AppendValues(text, impulses.segment<2>(2 * k));
  WriteFileAtomically(path, text);
}

}  // namespace unjam
