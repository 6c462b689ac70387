// JSON Lines files that long runs append to as they go and resume from (`unjam perturb -o`,
// `unjam bounds -o`; docs/format.md): the first line is a header naming the run's
// parameters, then one JSON object per line.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace unjam {

// JSON has no NaN or infinity: records write a number that is not finite as null, and read
// null back as NaN (any other non-number is a type error, nlohmann::json::exception).
nlohmann::json NumberOrNull(double x);
double NumberOrNaN(const nlohmann::json& j);

struct JsonLines {
  nlohmann::json header;
  std::vector<std::pair<int, nlohmann::json>> lines;  // (line number, object) after the header
  std::uintmax_t valid_bytes = 0;  // length of the complete lines (a torn last line is not)
};

// A last line cut short by an interruption is ignored (valid_bytes ends before it); any other
// line that is not JSON, or a file without a header, is an InputError naming the file and line.
JsonLines ReadJsonLines(const std::filesystem::path& path);

// True if the file holds its header line whole. Under mpirun a rank may read another's file
// between its creation and its header: such a file, or one a crash left so, holds nothing
// yet and is passed over (RankFiles' readers), or started afresh (its own rank).
bool HasHeaderLine(const std::filesystem::path& path);

// Opens a run's own file for appending; one without its header line (new, or cut short by a
// crash) is started afresh with `header`. Throws OutputError naming the path.
std::ofstream AppendTo(const std::filesystem::path& path, const nlohmann::json& header);

// Throws std::invalid_argument (a usage error) naming `path` and the keys that differ when
// `found` (its header) is not `expected`; `remedy` says what to do.
void RequireHeader(const std::filesystem::path& path, const nlohmann::json& found,
                   const nlohmann::json& expected, const std::string& remedy);

// Under mpirun every rank appends to its own file: `path` (X.jsonl) for rank 0, X.rank<r>.jsonl
// for rank r, beside it.
std::filesystem::path RankPath(const std::filesystem::path& path, int rank);
// `path` if it exists, then the rank files beside it (sorted by name): what a run or an
// interrupted mpirun left. Files without their header line are left out (HasHeaderLine).
std::vector<std::filesystem::path> RankFiles(const std::filesystem::path& path);
// Appends the complete lines (after the header) of every rank file beside `path` to `path`,
// as they were written, and removes those files (also any without a header line), so that
// one file holds the run and only ever grew. Each file's header must be `header`
// (RequireHeader, with `remedy`).
void MergeRankFiles(const std::filesystem::path& path, const nlohmann::json& header,
                    const std::string& remedy);

}  // namespace unjam
