// The records of a long `unjam bounds` run (docs/indeterminacy.md, "Long runs"): with -o FILE
// every bound is appended to FILE.records.jsonl as it is obtained (under mpirun rank r > 0
// appends to FILE.records.rank<r>.jsonl, merged by rank 0 at the end); a rerun of the same
// command takes those back and solves only the others, and the records are removed once
// FILE is written. Format: docs/format.md, "Bound records".
#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "command_bounds.hpp"
#include "unjam/indeterminacy/force_bounds.hpp"
#include "unjam/io/run_records.hpp"

namespace unjam::cli {

class BoundsRecords {
 public:
  // Reads what every rank file beside FILE holds (throws InputError for a bad line,
  // std::invalid_argument for records of other parameters) and opens this rank's own.
  BoundsRecords(const BoundsFlags& f, const EquilibriumSystem& s, std::size_t selected,
                const BoundsOptions& o, int rank);
  const std::vector<BoundRecord>& Known() const { return known_; }
  const std::filesystem::path& Path() const { return records_.Path(); }
  // Called one at a time (BoundsOptions::on_bound). Throws OutputError if it cannot write.
  void Add(const BoundRecord& r);
  // Rank 0, once every rank is done: the ranks' records in one file, and all of them known.
  void Merge();
  long long Obtained() const { return static_cast<long long>(known_.size()) + written_; }
  long long Resumed() const { return resumed_; }
  long long ResumedIterations() const { return resumed_iterations_; }
  // The simplex iterations of every recorded bound's LP, and of this process's own.
  long long ObtainedIterations() const { return KnownIterations() + written_iterations_; }
  long long WrittenIterations() const { return written_iterations_; }
  // The bounds answered by a shortcut, not an LP, in this run (on every rank, after Merge).
  long long ShortcutsThisRun() const {
    return KnownShortcuts() + written_shortcuts_ - resumed_shortcuts_;
  }
  // The run is written out: the records, this rank's and any other rank files beside them,
  // are no longer needed.
  void Remove();

 private:
  void ReadAll();
  long long KnownIterations() const;
  long long KnownShortcuts() const;
  BoundRecord FromJson(const RunRecords::Entry& e) const;

  int contacts_;
  RunRecords records_;
  std::vector<BoundRecord> known_;
  long long resumed_ = 0, resumed_iterations_ = 0, resumed_shortcuts_ = 0;
  long long written_ = 0, written_iterations_ = 0, written_shortcuts_ = 0;
};

}  // namespace unjam::cli
