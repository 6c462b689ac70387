// Reading the Siconos numerics `.dat` format of a 2D friction-contact problem
// (docs/format.md, "Siconos problem format"). Siconos reads it with fscanf, so values are
// whitespace-separated and line breaks carry no meaning, except in the sparse storage (2),
// which Siconos parses line by line and so do we. Every error names the file and the line.
#include <algorithm>
#include <vector>

#include "text_fields.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/io/read_text.hpp"
#include "unjam/io/siconos_problem.hpp"

namespace unjam {

namespace {

using io_internal::FieldError;
using Triplets = std::vector<Eigen::Triplet<double>>;

// The smallest number of bytes one value takes in a file (a digit and a separator): a
// count that the rest of the text could not hold is rejected before anything is allocated.
constexpr long long kMinBytesPerValue = 2;
constexpr long long kMaxIndex = 1LL << 30;

struct Token {
  std::string_view text;
  int line = 0;
};

bool IsSpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

// Whitespace-separated tokens with their line numbers, and whole lines where the format
// is line-based.
class Scanner {
 public:
  Scanner(std::string_view text, const std::string& name) : text_(text), name_(name) {}

  [[noreturn]] void Fail(int line, const std::string& message) const {
    throw InputError(name_, line, message);
  }

  // True if only whitespace is left.
  bool AtEnd() {
    SkipSpace();
    return pos_ == text_.size();
  }

  // The next token. At the end of the file: "truncated", at the last line that has text.
  Token Next(std::string_view what) {
    if (AtEnd())
      Fail(last_text_line_, "truncated: expected " + std::string(what) + " at the end of the file");
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !IsSpace(text_[pos_])) ++pos_;
    last_text_line_ = line_;
    return {text_.substr(start, pos_ - start), line_};
  }

  double Double(std::string_view what) {
    const Token t = Next(what);
    try {
      return io_internal::ParseDouble(t.text, what);
    } catch (const FieldError& e) {
      Fail(t.line, e.what());
    }
  }

  long long Integer(std::string_view what, long long min, long long max, int* line = nullptr) {
    const Token t = Next(what);
    if (line != nullptr) *line = t.line;
    return ParseIntegerAt(t.text, t.line, what, min, max);
  }

  long long ParseIntegerAt(std::string_view token, int line, std::string_view what, long long min,
                           long long max) const {
    try {
      return io_internal::ParseInteger(token, what, min, max);
    } catch (const FieldError& e) {
      Fail(line, e.what());
    }
  }

  // The rest of the current line, through its end (for text after a token).
  std::string_view RestOfLine() { return TakeLine(); }

  // The next whole line; `what` names it if the file ends first.
  std::string_view Line(std::string_view what) {
    if (pos_ == text_.size())
      Fail(last_text_line_, "truncated: expected " + std::string(what) + " at the end of the file");
    return TakeLine();
  }

  int line() const { return line_; }
  // Line of the line last returned by Line() or RestOfLine().
  int last_line() const { return last_line_; }
  long long remaining_bytes() const { return static_cast<long long>(text_.size() - pos_); }

 private:
  void SkipSpace() {
    while (pos_ < text_.size() && IsSpace(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }

  std::string_view TakeLine() {
    last_line_ = last_text_line_ = line_;
    const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
    std::string_view line = text_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end < text_.size() ? end + 1 : end;
    if (end < text_.size()) ++line_;
    return line;
  }

  std::string_view text_;
  const std::string& name_;
  std::size_t pos_ = 0;
  int line_ = 1;
  int last_line_ = 1;
  int last_text_line_ = 1;
};

std::vector<std::string_view> Words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t pos = 0;
  while (pos < line.size()) {
    while (pos < line.size() && IsSpace(line[pos])) ++pos;
    if (pos == line.size()) break;
    std::size_t end = pos;
    while (end < line.size() && !IsSpace(line[end])) ++end;
    words.push_back(line.substr(pos, end - pos));
    pos = end;
  }
  return words;
}

// Rejects a count of items (each at least `values` numbers) the rest of the text cannot hold.
void CheckFits(const Scanner& s, int line, long long count, long long values,
               std::string_view what) {
  if (count > s.remaining_bytes() / (kMinBytesPerValue * values)) {
    s.Fail(line, "truncated: " + std::string(what) + " " + std::to_string(count) +
                     " is more than the rest of the file can hold");
  }
}

// Storage 0: `n n` again, then n² values in column-major order.
void ReadDense(Scanner& s, int n, Triplets& entries) {
  int line = 0;
  const long long rows = s.Integer("dense matrix rows", 0, kMaxIndex, &line);
  const long long cols = s.Integer("dense matrix columns", 0, kMaxIndex);
  if (rows != n || cols != n) {
    s.Fail(line, "dense matrix is " + std::to_string(rows) + " x " + std::to_string(cols) +
                     ", expected " + std::to_string(n) + " x " + std::to_string(n));
  }
  CheckFits(s, line, static_cast<long long>(n) * n, 1, "number of dense matrix values");
  for (int col = 0; col < n; ++col) {
    for (int row = 0; row < n; ++row) {
      const double v = s.Double("a value of the dense matrix W");
      if (v != 0.0) entries.emplace_back(row, col, v);
    }
  }
}

// The cumulative block ends (2 4 … 2nc): only 2×2 blocks, one per contact, are accepted.
void ReadBlockEnds(Scanner& s, int nc, std::string_view what) {
  for (int b = 0; b < nc; ++b) {
    int line = 0;
    const long long end = s.Integer(what, 0, kMaxIndex, &line);
    if (end != 2LL * (b + 1)) {
      s.Fail(line, "bad block structure: " + std::string(what) + " " + std::to_string(b) + " is " +
                       std::to_string(end) + ", expected " + std::to_string(2 * (b + 1)) +
                       " (2x2 blocks, one per contact)");
    }
  }
}

// Block-row pointers and block column indices of a sparse-block matrix with `blocks` blocks.
void ReadBlockIndex(Scanner& s, int nc, long long blocks, std::vector<long long>& row_start,
                    std::vector<int>& col) {
  row_start.resize(nc + 1);
  for (int i = 0; i <= nc; ++i) {
    int line = 0;
    row_start[i] = s.Integer("block row pointer", 0, blocks, &line);
    const bool ok = i == 0
                        ? row_start[i] == 0
                        : (row_start[i] >= row_start[i - 1] && (i < nc || row_start[i] == blocks));
    if (!ok)
      s.Fail(line, "bad block structure: block row pointer " + std::to_string(i) + " is " +
                       std::to_string(row_start[i]) +
                       " (pointers must rise from 0 to the number of blocks, " +
                       std::to_string(blocks) + ")");
  }
  col.resize(blocks);
  for (int i = 0; i < nc; ++i) {
    for (long long b = row_start[i]; b < row_start[i + 1]; ++b) {
      int line = 0;
      col[b] = static_cast<int>(s.Integer("block column index", 0, nc - 1, &line));
      if (b > row_start[i] && col[b] <= col[b - 1]) {
        s.Fail(line, "bad block structure: block column indices of block row " + std::to_string(i) +
                         " must increase, got " + std::to_string(col[b - 1]) + " then " +
                         std::to_string(col[b]));
      }
    }
  }
}

// Storage 1 (SparseBlockStructuredMatrix, SBM_new_from_file).
void ReadSparseBlock(Scanner& s, int nc, Triplets& entries) {
  int line = 0;
  const long long blocks = s.Integer("number of blocks", 0, static_cast<long long>(nc) * nc, &line);
  if (blocks == 0) return;  // Siconos writes nothing more for an empty matrix
  for (const char* what : {"number of block rows", "number of block columns"}) {
    const long long count = s.Integer(what, 0, kMaxIndex, &line);
    if (count != nc)
      s.Fail(line, "bad block structure: " + std::string(what) + " is " + std::to_string(count) +
                       ", expected the number of contacts, " + std::to_string(nc));
  }
  ReadBlockEnds(s, nc, "block row end");
  ReadBlockEnds(s, nc, "block column end");
  if (const long long filled1 = s.Integer("number of block row pointers", 0, kMaxIndex, &line);
      filled1 != nc + 1) {
    s.Fail(line, "bad block structure: " + std::to_string(filled1) +
                     " block row pointers, expected " + std::to_string(nc + 1));
  }
  if (const long long filled2 = s.Integer("number of block column indices", 0, kMaxIndex, &line);
      filled2 != blocks) {
    s.Fail(line, "bad block structure: " + std::to_string(filled2) +
                     " block column indices, expected the number of blocks, " +
                     std::to_string(blocks));
  }
  CheckFits(s, line, blocks, 1, "number of blocks");
  std::vector<long long> row_start;
  std::vector<int> col;
  ReadBlockIndex(s, nc, blocks, row_start, col);
  for (int i = 0; i < nc; ++i) {
    for (long long b = row_start[i]; b < row_start[i + 1]; ++b) {
      if (const long long k = s.Integer("block number", 0, kMaxIndex, &line); k != b) {
        s.Fail(line, "bad block structure: block number " + std::to_string(k) + ", expected " +
                         std::to_string(b));
      }
      for (int v = 0; v < 4; ++v) {  // column-major: W_nn W_tn W_nt W_tt
        const double x = s.Double("a value of a 2x2 block of W");
        if (x != 0.0) entries.emplace_back(2 * i + v % 2, 2 * col[b] + v / 2, x);
      }
    }
  }
}

// "m-by-n," → m and n.
void ParseShape(const Scanner& s, std::string_view word, int line, long long& m, long long& n) {
  if (!word.empty() && word.back() == ',') word.remove_suffix(1);
  const std::size_t by = word.find("-by-");
  if (by == std::string_view::npos)
    s.Fail(line, "sparse matrix size line: expected 'M-by-N', got " + io_internal::Quote(word));
  m = s.ParseIntegerAt(word.substr(0, by), line, "sparse matrix rows", 0, kMaxIndex);
  n = s.ParseIntegerAt(word.substr(by + 4), line, "sparse matrix columns", 0, kMaxIndex);
}

// The size line of cs_print: "[triplet: ]M-by-N, nzmax: Z nnz: NNZ[, 1-norm: X]". Returns NNZ.
long long ReadSparseSize(Scanner& s, int n, bool triplet) {
  const std::vector<std::string_view> w = Words(s.Line("the sparse matrix size line"));
  const int line = s.last_line();
  const std::size_t first = triplet ? 1 : 0;
  const bool shape_ok = w.size() >= first + 5 && (triplet == (w[0] == "triplet:")) &&
                        w[first + 1] == "nzmax:" && w[first + 3] == "nnz:";
  if (!shape_ok) {
    s.Fail(line, std::string("sparse matrix size line: expected '") + (triplet ? "triplet: " : "") +
                     "M-by-N, nzmax: Z nnz: NNZ...' (origin " +
                     (triplet ? "1, triplet" : "2, CSC") + ")");
  }
  long long m = 0, cols = 0;
  ParseShape(s, w[first], line, m, cols);
  if (m != n || cols != n)
    s.Fail(line, "W is " + std::to_string(m) + " x " + std::to_string(cols) + ", expected " +
                     std::to_string(n) + " x " + std::to_string(n));
  std::string_view nnz = w[first + 4];
  if (!nnz.empty() && nnz.back() == ',') nnz.remove_suffix(1);
  const long long count = s.ParseIntegerAt(nnz, line, "number of non-zeros", 0, kMaxIndex);
  CheckFits(s, line, count, 2, "number of non-zeros");
  return count;
}

// One entry line: "I : VALUE" (CSC) or "I J : VALUE" (triplet).
void ReadEntry(Scanner& s, int n, int column, Triplets& entries) {
  const std::vector<std::string_view> w = Words(s.Line("a sparse matrix entry"));
  const int line = s.last_line();
  const std::size_t indices = column < 0 ? 2 : 1;
  if (w.size() != indices + 2 || w[indices] != ":") {
    s.Fail(line, std::string("sparse matrix entry: expected '") + (column < 0 ? "I J" : "I") +
                     " : VALUE', got " + std::to_string(w.size()) + " fields");
  }
  const long long row = s.ParseIntegerAt(w[0], line, "row index", 0, n - 1);
  const long long col =
      column < 0 ? s.ParseIntegerAt(w[1], line, "column index", 0, n - 1) : column;
  try {
    entries.emplace_back(row, col, io_internal::ParseDouble(w[indices + 1], "value"));
  } catch (const FieldError& e) {
    s.Fail(line, e.what());
  }
}

void ReadCompressedColumns(Scanner& s, int n, long long nnz, Triplets& entries) {
  long long next = 0;
  for (int j = 0; j < n; ++j) {
    const std::vector<std::string_view> w = Words(s.Line("a column header"));
    const int line = s.last_line();
    if (w.size() != 7 || w[0] != "col" || w[2] != ":" || w[3] != "locations" || w[5] != "to") {
      s.Fail(line,
             "CSC column header: expected 'col " + std::to_string(j) + " : locations P0 to P1'");
    }
    const long long col = s.ParseIntegerAt(w[1], line, "column number", 0, kMaxIndex);
    const long long p0 = s.ParseIntegerAt(w[4], line, "first location", 0, kMaxIndex);
    const long long p1 = s.ParseIntegerAt(w[6], line, "last location", -1, kMaxIndex);
    if (col != j || p0 != next || p1 < p0 - 1 || p1 >= nnz) {
      s.Fail(line, "CSC column header: expected column " + std::to_string(j) +
                       " with locations from " + std::to_string(next) + " to at most " +
                       std::to_string(nnz - 1));
    }
    for (long long p = p0; p <= p1; ++p) ReadEntry(s, n, j, entries);
    next = p1 + 1;
  }
  if (next != nnz)
    s.Fail(s.last_line(), "CSC: " + std::to_string(next) + " entries listed, the size line says " +
                              std::to_string(nnz));
}

// Storage 2 (NumericsSparseMatrix, NSM_new_from_file + CSparseMatrix_new_from_file).
void ReadSparse(Scanner& s, int n, Triplets& entries) {
  int line = 0;
  const long long origin = s.Integer("sparse origin", 0, kMaxIndex, &line);
  if (origin != 1 && origin != 2) {
    s.Fail(line, "sparse origin " + std::to_string(origin) +
                     ": only 1 (triplet) and 2 (CSC) are read" +
                     (origin == 3 ? " (CSR is not)" : ""));
  }
  if (!Words(s.RestOfLine()).empty())
    s.Fail(s.last_line(), "unexpected text after the sparse origin");
  s.Line("the CSparse header line");  // "CSparse Version …": informative only
  const bool triplet = origin == 1;
  const long long nnz = ReadSparseSize(s, n, triplet);
  entries.reserve(nnz);
  if (triplet) {
    for (long long p = 0; p < nnz; ++p) ReadEntry(s, n, -1, entries);
  } else {
    ReadCompressedColumns(s, n, nnz, entries);
  }
}

// W = H M⁻¹ Hᵀ of a mechanical problem has a positive diagonal: each row of H moves some
// body. Where an entry is zero or negative the problem is ill-posed (W = 0 has r = 0 for an
// answer whatever q says), and a backend's "converged" would be a wrong answer reported as
// right; so it is refused here, at `line`, where W begins.
void CheckDelassusDiagonal(const Scanner& s, const Eigen::SparseMatrix<double>& w, int line) {
  for (Eigen::Index i = 0; i < w.rows(); ++i) {
    const double d = w.coeff(i, i);
    if (d > 0.0) continue;
    const std::string row = std::to_string(i);
    s.Fail(line,
           "contact " + std::to_string(i / 2) + ": W[" + row + "][" + row + "] (its " +
               (i % 2 == 0 ? "normal" : "tangential") + " diagonal entry) is " +
               io_internal::DoubleToString(d) +
               ", not positive: W is not a Delassus operator (H M^-1 H^T has a positive diagonal)");
  }
}

Eigen::SparseMatrix<double> ReadMatrix(Scanner& s, int nc) {
  const int n = 2 * nc;
  int line = 0;
  const long long storage =
      s.Integer("matrix storage type (0 dense, 1 sparse block, 2 sparse)", 0, 2, &line);
  const long long rows = s.Integer("matrix rows", 0, kMaxIndex);
  const long long cols = s.Integer("matrix columns", 0, kMaxIndex);
  if (rows != n || cols != n) {
    s.Fail(line, "W is " + std::to_string(rows) + " x " + std::to_string(cols) + ", expected " +
                     std::to_string(n) + " x " + std::to_string(n) + " (2 rows per contact, " +
                     std::to_string(nc) + " contacts)");
  }
  Triplets entries;
  if (storage == 0) ReadDense(s, n, entries);
  else if (storage == 1) ReadSparseBlock(s, nc, entries);
  else ReadSparse(s, n, entries);
  Eigen::SparseMatrix<double> w(n, n);
  w.setFromTriplets(entries.begin(), entries.end());  // sums repeated entries, as CSparse
  w.prune([](Eigen::Index, Eigen::Index, double v) { return v != 0.0; });
  CheckDelassusDiagonal(s, w, line);
  return w;
}

Eigen::VectorXd ReadVector(Scanner& s, int size, const std::string& what) {
  Eigen::VectorXd v(size);
  for (int i = 0; i < size; ++i) v[i] = s.Double(what + "[" + std::to_string(i) + "]");
  return v;
}

// After the friction coefficients, Siconos before July 2010 (svn r2135, "delete isComplete
// from the problem structure") wrote the problem's `isComplete` member with "%d\n" on a line
// of its own: 1, or 0 for a problem built by hand whose author had not set it (no solver
// ever checked it). Siconos' reader still stops after the last mu, so such files remain in
// its test collection (FrictionContactProblem00031.dat and others). That flag, 0 or 1 alone
// on the line after the last mu and last in the file, is read and ignored; anything else
// there is refused.
void ReadCompletenessFlag(Scanner& s, int last_mu_line) {
  if (s.AtEnd()) return;
  const Token flag = s.Next("");
  const bool is_flag =
      (flag.text == "0" || flag.text == "1") && flag.line > last_mu_line && s.AtEnd();
  if (!is_flag)
    s.Fail(flag.line,
           "unexpected data after the friction coefficients: " + io_internal::Quote(flag.text));
}

DelassusProblem ParseLocalProblem(std::string_view text, const std::string& name) {
  Scanner s(text, name);
  int line = 0;
  const long long dimension = s.Integer("dimension", 0, kMaxIndex, &line);
  if (dimension != 2)
    s.Fail(line, "dimension " + std::to_string(dimension) +
                     ": only 2D friction-contact problems (dimension 2) are read");
  const long long nc = s.Integer("number of contacts", 1, kMaxIndex / 2, &line);
  CheckFits(s, line, nc, 3, "number of contacts");
  DelassusProblem p;
  p.w = ReadMatrix(s, static_cast<int>(nc));
  p.q = ReadVector(s, 2 * static_cast<int>(nc), "q");
  p.laws.resize(nc);
  int last_mu_line = 0;
  for (int k = 0; k < nc; ++k) {
    const Token t = s.Next("mu[" + std::to_string(k) + "]");
    last_mu_line = t.line;
    double mu = 0.0;
    try {
      mu = io_internal::ParseDouble(t.text, "mu[" + std::to_string(k) + "]");
    } catch (const FieldError& e) {
      s.Fail(t.line, e.what());
    }
    if (mu < 0.0)
      s.Fail(t.line, "mu[" + std::to_string(k) + "] = " + io_internal::DoubleToString(mu) +
                         ": a friction coefficient must be >= 0");
    p.laws[k].mu = mu;
  }
  ReadCompletenessFlag(s, last_mu_line);
  return p;
}

// Siconos' global form (globalFrictionContact_printInFile): dimension, nc, M (n x n), H
// (n x dimension·nc), q (n), b (dimension·nc), mu (nc), for M v = q + H r, u = Hᵀ v + b. Its
// start can pass for a local problem (nc = 0, or M of size 2nc), so it is looked for only
// once reading the local form has failed: true with the message to give instead, if M
// (dense or sparse storage; a sparse-block M is not recognised) is followed by the header
// of an n x dimension·nc matrix H.
bool LooksGlobal(std::string_view text, const std::string& name, int& line, std::string& message) {
  try {
    Scanner s(text, name);
    const long long dimension = s.Integer("dimension", 2, 3);
    const long long nc = s.Integer("number of contacts", 0, kMaxIndex / 3);
    int m_line = 0;
    const long long storage = s.Integer("storage of M", 0, 2, &m_line);
    const long long n = s.Integer("rows of M", 1, kMaxIndex);
    if (s.Integer("columns of M", 0, kMaxIndex) != n || storage == 1) return false;
    Triplets ignored;
    if (storage == 0) ReadDense(s, static_cast<int>(n), ignored);
    else ReadSparse(s, static_cast<int>(n), ignored);
    int h_line = 0;
    s.Integer("storage of H", 0, 2, &h_line);
    const long long h_rows = s.Integer("rows of H", 0, kMaxIndex);
    const long long h_cols = s.Integer("columns of H", 0, kMaxIndex);
    if (h_rows != n || h_cols != dimension * nc) return false;
    line = m_line;
    message =
        "global-form friction-contact problem (M, H, q, b): M is " + std::to_string(n) + " x " +
        std::to_string(n) + ", H (line " + std::to_string(h_line) + ") is " +
        std::to_string(h_rows) + " x " + std::to_string(h_cols) + ", " + std::to_string(nc) +
        " contacts in dimension " + std::to_string(dimension) +
        "; it is not read: use the local form, W = H^T M^-1 H and q = H^T M^-1 q + b (Siconos' "
        "globalFrictionContact_reformulation_FrictionContact)";
    return true;
  } catch (const InputError&) {
    return false;
  }
}

}  // namespace

DelassusProblem ParseSiconosProblem(std::string_view text, const std::string& name) {
  try {
    return ParseLocalProblem(text, name);
  } catch (const InputError&) {
    int line = 0;
    std::string message;
    if (LooksGlobal(text, name, line, message)) throw InputError(name, line, message);
    throw;
  }
}

DelassusProblem ReadSiconosProblem(const std::filesystem::path& path) {
  return ParseSiconosProblem(ReadInputText(path), path.string());
}

}  // namespace unjam
