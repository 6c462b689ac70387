#include "check_records.hpp"

#include <optional>

#include "cli_common.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam::cli {

namespace {

std::optional<SolveStatus> SolveStatusFromString(const std::string& name) {
  for (SolveStatus s :
       {SolveStatus::kConverged, SolveStatus::kIterationLimit, SolveStatus::kNumericalFailure,
        SolveStatus::kUnsupported, SolveStatus::kRelaxedModel}) {
    if (name == ToString(s)) return s;
  }
  return std::nullopt;
}

std::optional<StabilityVerdict> VerdictFromString(const std::string& name) {
  for (StabilityVerdict v :
       {StabilityVerdict::kSolved, StabilityVerdict::kReported, StabilityVerdict::kFailed}) {
    if (name == ToString(v)) return v;
  }
  return std::nullopt;
}

StabilityRow RowFromJson(const RunRecords::Entry& e) {
  const nlohmann::json& j = e.record;
  StabilityRow r;
  try {
    r.name = j.at("case").get<std::string>();
    r.backend = j.at("backend").get<std::string>();
    r.contacts = j.at("contacts").get<int>();
    const std::optional<SolveStatus> status = SolveStatusFromString(j.at("status"));
    const std::optional<StabilityVerdict> verdict = VerdictFromString(j.at("verdict"));
    if (!status || !verdict) throw InputError(e.file.string(), e.line, "unknown status or verdict");
    r.report.status = *status;
    r.verdict = *verdict;
    r.report.residual = NumberOrNaN(j.at("residual"));
    r.report.seconds = j.at("seconds").get<double>();
    r.siconos_error = NumberOrNaN(j.at("siconos_error"));
    r.equilibrium = NumberOrNaN(j.at("equilibrium"));
    r.finite = j.at("finite").get<bool>();
    r.reproducible = j.at("reproducible").get<bool>();
    r.steps = j.at("steps").get<int>();
    r.max_overlap = NumberOrNaN(j.at("max_overlap"));
    r.overlap_growth = NumberOrNaN(j.at("overlap_growth"));
    r.energy_change = NumberOrNaN(j.at("energy_change"));
    r.message = j.at("message").get<std::string>();
  } catch (const nlohmann::json::exception& x) {
    throw InputError(e.file.string(), e.line, std::string("bad check record: ") + x.what());
  }
  return r;
}

}  // namespace

nlohmann::json RowJson(const StabilityRow& r) {
  return {{"case", r.name},
          {"backend", r.backend},
          {"contacts", r.contacts},
          {"status", ToString(r.report.status)},
          {"residual", NumberOrNull(r.report.residual)},
          {"siconos_error", NumberOrNull(r.siconos_error)},
          {"equilibrium", NumberOrNull(r.equilibrium)},
          {"finite", r.finite},
          {"reproducible", r.reproducible},
          {"steps", r.steps},
          {"max_overlap", NumberOrNull(r.max_overlap)},
          {"overlap_growth", NumberOrNull(r.overlap_growth)},
          {"energy_change", NumberOrNull(r.energy_change)},
          {"seconds", r.report.seconds},
          {"verdict", ToString(r.verdict)},
          {"message", r.message}};
}

CheckRecords::CheckRecords(const std::filesystem::path& dir, const nlohmann::json& header)
    : records_(dir / "stability.records.jsonl", header, 0,
               "remove it, rerun with the options and cases that made it, or choose another -o") {
  for (const RunRecords::Entry& e : records_.Entries()) {
    StabilityRow row = RowFromJson(e);
    rows_[{row.name, row.backend}] = std::move(row);
  }
  resumed_ = rows_.size();
}

const StabilityRow* CheckRecords::Find(const std::string& name, const std::string& backend) const {
  const auto it = rows_.find({name, backend});
  return it == rows_.end() ? nullptr : &it->second;
}

void CheckRecords::Add(const StabilityRow& row) {
  records_.Append(RowJson(row));
  rows_[{row.name, row.backend}] = row;
}

}  // namespace unjam::cli
