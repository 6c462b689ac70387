#include "bounds_records.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "cli_common.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam::cli {

namespace {
constexpr const char* kOtherRun = "remove it or choose another --output";

nlohmann::json BoundsHeader(const BoundsFlags& f, const EquilibriumSystem& s, std::size_t selected,
                            const BoundsOptions& o) {
  return {{"unjam_bounds_records", 1},
          {"packing", std::filesystem::path(f.file).filename().string()},
          {"packing_fnv1a", FileFingerprint(f.file)},
          {"contacts", f.contacts},
          {"selected", selected},
          {"ensemble_contacts", s.contacts.size()},
          {"lp", f.lp},
          {"warm_start", o.warm_start},
          {"gap_tolerance", f.gap_tolerance},
          {"lp_tolerance", o.lp_tolerance}};
}
}  // namespace

BoundsRecords::BoundsRecords(const BoundsFlags& f, const EquilibriumSystem& s, std::size_t selected,
                             const BoundsOptions& o, int rank)
    : contacts_(static_cast<int>(s.contacts.size())),
      records_(f.output + ".records.jsonl", BoundsHeader(f, s, selected, o), rank, kOtherRun) {
  ReadAll();
  resumed_ = static_cast<long long>(known_.size());
  resumed_iterations_ = KnownIterations();
  resumed_shortcuts_ = KnownShortcuts();
}

void BoundsRecords::Add(const BoundRecord& r) {
  records_.Append(
      {{"contact", r.contact},
       {"kind", ToString(r.kind)},
       {"status", ToString(r.bound.status)},
       {"value", r.bound.ok() ? nlohmann::json(r.bound.value) : nlohmann::json(nullptr)},
       {"iterations", r.iterations},
       {"shortcut", r.shortcut}});
  ++written_;
  written_iterations_ += r.iterations;
  written_shortcuts_ += r.shortcut ? 1 : 0;
}

void BoundsRecords::Merge() {
  records_.Merge();
  ReadAll();
  written_ = written_iterations_ = written_shortcuts_ = 0;
}

void BoundsRecords::Remove() { records_.Remove(); }

// Every rank file's bounds (a bound recorded twice, by an mpirun interrupted while merging,
// counts once).
void BoundsRecords::ReadAll() {
  std::map<std::pair<int, BoundKind>, BoundRecord> all;
  for (const RunRecords::Entry& e : records_.Entries()) {
    const BoundRecord r = FromJson(e);
    all[{r.contact, r.kind}] = r;
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

BoundRecord BoundsRecords::FromJson(const RunRecords::Entry& e) const {
  const nlohmann::json& j = e.record;
  auto bad = [&](const std::string& why) {
    return InputError(e.file.string(), e.line, "bad bound record: " + why);
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
