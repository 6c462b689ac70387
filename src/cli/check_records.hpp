// The records of `unjam check -o DIR` (DIR/stability.records.jsonl, run_records.hpp): one
// per (case, backend) row, appended as the row is obtained. A rerun of the same command on
// the same cases takes them back and runs only the rest; the records are removed once
// DIR/stability.csv holds every row.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "unjam/io/run_records.hpp"
#include "unjam/protocols/stability_check.hpp"

namespace unjam::cli {

nlohmann::json RowJson(const StabilityRow& row);

class CheckRecords {
 public:
  // `header`: what makes two runs the same (the options and the cases' fingerprints); a
  // records file of another header is refused, naming it.
  CheckRecords(const std::filesystem::path& dir, const nlohmann::json& header);
  const StabilityRow* Find(const std::string& name, const std::string& backend) const;
  void Add(const StabilityRow& row);  // appended and flushed
  std::size_t Resumed() const { return resumed_; }
  void Remove() { records_.Remove(); }

 private:
  RunRecords records_;
  std::map<std::pair<std::string, std::string>, StabilityRow> rows_;
  std::size_t resumed_ = 0;
};

}  // namespace unjam::cli
