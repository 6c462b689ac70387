#include "bounds_records.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "cli_common.hpp"
#include "unjam/io/json_lines.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam::cli {

namespace {
constexpr const char* kOtherRun = "remove it or choose another --output";
}  // namespace

BoundsRecords::BoundsRecords(const BoundsFlags& f, const EquilibriumSystem& s, std::size_t selected,
                             const BoundsOptions& o, int rank)
    : base_(f.output + ".records.jsonl"), own_(RankPath(base_, rank)),
      contacts_(static_cast<int>(s.contacts.size())),
      header_({{"unjam_bounds_records", 1},
               {"packing", std::filesystem::path(f.file).filename().string()},
               {"packing_fnv1a", FileFingerprint(f.file)},
               {"contacts", f.contacts},
               {"selected", selected},
               {"ensemble_contacts", s.contacts.size()},
               {"lp", f.lp},
               {"warm_start", o.warm_start},
               {"gap_tolerance", f.gap_tolerance},
               {"lp_tolerance", o.lp_tolerance}}) {
  ReadAll();
  resumed_ = static_cast<long long>(known_.size());
  resumed_iterations_ = KnownIterations();
  resumed_shortcuts_ = KnownShortcuts();
  log_ = AppendTo(own_, header_);
}

void BoundsRecords::Add(const BoundRecord& r) {
  log_ << nlohmann::json{{"contact", r.contact},
                         {"kind", ToString(r.kind)},
                         {"status", ToString(r.bound.status)},
                         {"value",
                          r.bound.ok() ? nlohmann::json(r.bound.value) : nlohmann::json(nullptr)},
                         {"iterations", r.iterations},
                         {"shortcut", r.shortcut}}
              .dump()
       << '\n'
       << std::flush;
  if (!log_) throw OutputError(own_.string() + ": cannot append a bound");
  ++written_;
  written_iterations_ += r.iterations;
  written_shortcuts_ += r.shortcut ? 1 : 0;
}

void BoundsRecords::Merge() {
  log_.close();
  MergeRankFiles(base_, header_, kOtherRun);
  ReadAll();
  written_ = written_iterations_ = written_shortcuts_ = 0;
}

void BoundsRecords::Remove() {
  log_.close();
  // Rank files this run took back (an mpirun stopped before its merge, or one refused by
  // another run's lock while a rank had solved its share) go with the rest.
  MergeRankFiles(base_, header_, kOtherRun);
  std::filesystem::remove(base_);
}

// Every rank file's bounds (a bound recorded twice, by an mpirun interrupted while merging,
// counts once); a torn last line of this process's own file is cut off.
void BoundsRecords::ReadAll() {
  std::map<std::pair<int, BoundKind>, BoundRecord> all;
  for (const std::filesystem::path& path : RankFiles(base_)) {
    const JsonLines file = ReadJsonLines(path);
    RequireHeader(path, file.header, header_, kOtherRun);
    if (path == own_) std::filesystem::resize_file(path, file.valid_bytes);
    for (const auto& [line, j] : file.lines) {
      const BoundRecord r = FromJson(path, j, line);
      all[{r.contact, r.kind}] = r;
    }
  }
  known_.clear();
  for (const auto& [key, r] : all) known_.push_back(r);
}

long long BoundsRecords::KnownIterations() const {
  long long sum = 0;
  for (const BoundRecord& r : known_) sum += r.iterations;
  return sum;
}

long long BoundsRecords::KnownShortcuts() const {
  return std::count_if(known_.begin(), known_.end(),
                       [](const BoundRecord& r) { return r.shortcut; });
}

BoundRecord BoundsRecords::FromJson(const std::filesystem::path& path, const nlohmann::json& j,
                                    int line) const {
  auto bad = [&](const std::string& why) {
    return InputError(path.string(), line, "bad bound record: " + why);
  };
  BoundRecord r;
  try {
    r.contact = j.at("contact").get<int>();
    const std::optional<BoundKind> kind = BoundKindFromString(j.at("kind").get<std::string>());
    const std::optional<BoundStatus> status =
        BoundStatusFromString(j.at("status").get<std::string>());
    if (!kind || !status) throw bad("unknown kind or status");
    r.kind = *kind;
    r.bound.status = *status;
    if (r.bound.ok()) r.bound.value = j.at("value").get<double>();
    r.iterations = j.at("iterations").get<long long>();
    r.shortcut = j.at("shortcut").get<bool>();
  } catch (const nlohmann::json::exception& e) {
    throw bad(e.what());
  }
  if (r.contact < 0 || r.contact >= contacts_)
    throw bad("contact " + std::to_string(r.contact) + " is not in the ensemble");
  if (r.bound.ok() && !std::isfinite(r.bound.value))
    throw bad("a value that is not a finite number");
  return r;
}

}  // namespace unjam::cli
