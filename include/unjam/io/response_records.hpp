// Reduced perturbation responses as JSON, one object per line (JSON Lines): the record a
// long `unjam perturb` run writes as it goes and resumes from (docs/format.md).
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "unjam/io/run_records.hpp"
#include "unjam/protocols/response_ensemble.hpp"

namespace unjam {

nlohmann::json ToJson(const ReducedResponse& record);
// Throws InputError naming `where` if a field is missing or has the wrong type.
ReducedResponse ReducedResponseFromJson(const nlohmann::json& j, const std::string& where);

// The records of a run (run_records.hpp) by target index, each under "index". A target
// recorded twice (an mpirun interrupted while merging) counts once. Throws InputError
// naming the file and line of a record without an integer index or with a bad field.
std::map<int, ReducedResponse> RecordsByIndex(const std::vector<RunRecords::Entry>& entries);

}  // namespace unjam
