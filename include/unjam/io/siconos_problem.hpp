// 2D friction-contact problems in the Siconos numerics text format (`.dat`, as written by
// frictionContact_printInFile and read by frictionContact_newFromFile; docs/format.md,
// "Siconos problem format"):
//
//   2            dimension (only 2 is read)
//   nc           number of contacts
//   <W>          storage 0 (dense), 1 (sparse block) or 2 (sparse: triplet or CSC)
//   q[0] … q[2nc−1]
//   mu[0] … mu[nc−1]
//
// Reading never crashes on bad input: every problem throws InputError (a std::runtime_error)
// whose what() reads "FILE:LINE: message". Writing uses the sparse-block storage (the one
// Siconos' 2D NSGS uses natively) or dense, with shortest round-trip doubles, so that
// write → read gives back W, q and μ bit for bit; it goes through WriteFileAtomically, so
// no partial file is ever left behind.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "unjam/problem/delassus_problem.hpp"

namespace unjam {

// Every contact of a problem read from a file is unilateral; W is stored without explicit
// zeros (repeated sparse entries are summed, as CSparse does).
DelassusProblem ReadSiconosProblem(const std::filesystem::path& path);
// Parses text already in memory; `name` is used in error messages.
DelassusProblem ParseSiconosProblem(std::string_view text, const std::string& name);

enum class SiconosStorage { kDense = 0, kSparseBlock = 1 };

// The file text. Throws std::invalid_argument if the problem has a held (bilateral)
// contact, which Siconos' friction-contact problem cannot express, or inconsistent sizes.
// Sparse block: every diagonal block (zero or not) and every off-diagonal 2×2 block with a
// stored entry, in row-major block order.
std::string FormatSiconosProblem(const DelassusProblem& problem,
                                 SiconosStorage storage = SiconosStorage::kSparseBlock);
// Throws OutputError naming the path, for the reasons above or a failed write.
void WriteSiconosProblem(const DelassusProblem& problem, const std::filesystem::path& path,
                         SiconosStorage storage = SiconosStorage::kSparseBlock);

// A solution as plain text: one line "r_n r_t" per contact, shortest round-trip doubles.
// Written atomically; throws OutputError naming the path.
void WriteImpulses(const Eigen::VectorXd& impulses, const std::filesystem::path& path);

}  // namespace unjam
