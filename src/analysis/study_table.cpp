#include "unjam/analysis/study_table.hpp"

#include <cmath>

namespace unjam {

namespace {

bool SameNumber(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

// One quantity over a set's runs (the rule of AggregateStudy).
MeanAndError Combine(const std::vector<const StudyRun*>& runs, MeanAndError StudyRun::*quantity) {
  std::vector<const MeanAndError*> known;
  for (const StudyRun* r : runs)
    if (std::isfinite((r->*quantity).mean)) known.push_back(&(r->*quantity));
  if (known.empty()) return {kNoValue, kNoValue, 0};
  if (known.size() == 1) return *known.front();
  std::vector<double> means;
  for (const MeanAndError* m : known) means.push_back(m->mean);
  return MeanWithError(means);
}

// A per-packing number as a sample of the set.
MeanAndError Combine(const std::vector<const StudyRun*>& runs, double StudyRun::*quantity) {
  std::vector<double> values;
  for (const StudyRun* r : runs)
    if (std::isfinite(r->*quantity)) values.push_back(r->*quantity);
  if (values.empty()) return {kNoValue, kNoValue, 0};
  return MeanWithError(values);
}

StudyRow RowOf(const std::vector<const StudyRun*>& runs) {
  StudyRow row;
  row.key = runs.front()->key;
  row.packings = static_cast<int>(runs.size());
  for (const StudyRun* r : runs) {
    row.perturbations += r->perturbations;
    row.used += r->used;
    row.dynamic += r->dynamic;
    row.nonlinear += r->nonlinear;
    row.not_converged += r->not_converged;
    row.blocked += r->blocked;
    row.shift_rattlers += r->shift_rattlers;
    row.particles += r->particles;
    row.rattlers += r->rattlers;
    row.seconds += r->seconds;
  }
  row.packing_fraction = Combine(runs, &StudyRun::packing_fraction);
  row.z = Combine(runs, &StudyRun::z);
  row.z_with_rattlers = Combine(runs, &StudyRun::z_with_rattlers);
  row.height = Combine(runs, &StudyRun::height);
  row.mean_contact_force = Combine(runs, &StudyRun::mean_contact_force);
  for (auto [to, from] : {std::pair{&StudyRow::f_crit, &StudyRun::f_crit},
                          {&StudyRow::f_reference, &StudyRun::f_reference},
                          {&StudyRow::delta, &StudyRun::delta},
                          {&StudyRow::ratio, &StudyRun::ratio},
                          {&StudyRow::ratio_all, &StudyRun::ratio_all},
                          {&StudyRow::alpha, &StudyRun::alpha},
                          {&StudyRow::tail_scale, &StudyRun::tail_scale},
                          {&StudyRow::f_crit_any, &StudyRun::f_crit_any},
                          {&StudyRow::rattler_f_crit, &StudyRun::rattler_f_crit},
                          {&StudyRow::lp_min, &StudyRun::lp_min},
                          {&StudyRow::lp_max, &StudyRun::lp_max},
                          {&StudyRow::lp_position, &StudyRun::lp_position}})
    row.*to = Combine(runs, from);
  row.dynamic_share =
      row.perturbations > 0 ? static_cast<double>(row.dynamic) / row.perturbations : kNoValue;
  return row;
}

}  // namespace

bool StudyKey::operator==(const StudyKey& o) const {
  return protocol == o.protocol && n == o.n && SameNumber(width, o.width) &&
         SameNumber(pressure, o.pressure) && mu == o.mu && kind == o.kind;
}

std::vector<StudyRow> AggregateStudy(const std::vector<StudyRun>& runs) {
  std::vector<std::vector<const StudyRun*>> sets;
  for (const StudyRun& r : runs) {
    auto it = sets.begin();
    while (it != sets.end() && !(it->front()->key == r.key)) ++it;
    if (it == sets.end()) sets.push_back({&r});
    else it->push_back(&r);
  }
  std::vector<StudyRow> rows;
  for (const auto& set : sets) rows.push_back(RowOf(set));
  return rows;
}

}  // namespace unjam
