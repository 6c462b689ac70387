// Reduced perturbation responses as JSON, one object per line (JSON Lines): the record a
// long `unjam perturb` run writes as it goes and resumes from (docs/format.md).
#pragma once

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "unjam/protocols/response_ensemble.hpp"

namespace unjam {

nlohmann::json ToJson(const ReducedResponse& record);
// Throws InputError naming `where` if a field is missing or has the wrong type.
ReducedResponse ReducedResponseFromJson(const nlohmann::json& j, const std::string& where);

// A records file: the first line is `header`, then one record per line, each with its
// target index under "index".
struct RecordsFile {
  nlohmann::json header;
  std::vector<std::pair<int, ReducedResponse>> records;
  std::uintmax_t valid_bytes = 0;  // length of the complete lines (a torn last line is not)
};
// Reads a records file; a last line cut short by an interruption is ignored (and reported
// by valid_bytes), any other bad line is an InputError naming the file and line.
RecordsFile ReadRecords(const std::filesystem::path& path);

}  // namespace unjam
