#include "unjam/io/run_records.hpp"

#include <utility>

#include "unjam/io/json_lines.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam {

RunRecords::RunRecords(std::filesystem::path path, nlohmann::json header, int rank,
                       std::string remedy)
    : path_(std::move(path)), own_(RankPath(path_, rank)), header_(std::move(header)),
      remedy_(std::move(remedy)) {
  Read(true);
  own_file_ = AppendTo(own_, header_);
}

void RunRecords::Read(bool cut_own) {
  entries_.clear();
  for (const std::filesystem::path& file : RankFiles(path_)) {
    JsonLines lines = ReadJsonLines(file);
    RequireHeader(file, lines.header, header_, remedy_);
    if (cut_own && file == own_) std::filesystem::resize_file(file, lines.valid_bytes);
    for (auto& [line, record] : lines.lines) entries_.push_back({file, line, std::move(record)});
  }
}

void RunRecords::Append(const nlohmann::json& record) {
  own_file_ << record.dump() << '\n' << std::flush;
  if (!own_file_) throw OutputError(own_.string() + ": cannot append a record");
}

bool RunRecords::HasRankFiles() const { return RankFiles(path_).size() > 1; }

void RunRecords::Merge() {
  Close();
  MergeRankFiles(path_, header_, remedy_);
  Read(false);
}

void RunRecords::Remove() {
  Close();
  // Rank files this run took back (an mpirun stopped before its merge) go with the rest.
  MergeRankFiles(path_, header_, remedy_);
  std::filesystem::remove(path_);
}

}  // namespace unjam
