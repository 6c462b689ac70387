#include "study_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "unjam/analysis/equilibrium.hpp"
#include "unjam/io/packing_file.hpp"
#include "unjam/io/read_text.hpp"

namespace unjam::cli {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// A number as a file name reads it: %g, so 0.5 → "0.5" and 1e-08 → "1e-08".
std::string Short(double x) { return Format("%g", x); }

std::string PackingName(const StudyKey& k, std::uint64_t seed) {
  if (k.protocol == "gravity")
    return Format("gravity-n%d-w%s-mu%s-seed%llu", k.n, Short(k.width).c_str(), Short(k.mu).c_str(),
                  static_cast<unsigned long long>(seed));
  return Format("pressure-n%d-p%s-mu%s-seed%llu", k.n, Short(k.pressure).c_str(),
                Short(k.mu).c_str(), static_cast<unsigned long long>(seed));
}

int AddPacking(StudyPlan& plan, StudyKey key, std::uint64_t seed, int max_steps) {
  const std::string name = PackingName(key, seed);
  for (std::size_t p = 0; p < plan.packings.size(); ++p) {
    if (plan.packings[p].name != name) continue;
    plan.packings[p].max_steps = std::max(plan.packings[p].max_steps, max_steps);
    return static_cast<int>(p);
  }
  plan.packings.push_back({key, seed, name, max_steps, plan.config.packings / (name + ".unjam")});
  return static_cast<int>(plan.packings.size()) - 1;
}

void AddRun(StudyPlan& plan, StudyRunPlan run) {
  for (const StudyRunPlan& r : plan.runs)
    if (r.dir == run.dir) return;  // listed by two sets
  plan.runs.push_back(std::move(run));
}

// --- reading a run's outputs ---------------------------------------------------------

struct Csv {
  std::string file;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  int Column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw InputError(file, 1, "has no column '" + name + "'");
    return static_cast<int>(it - header.begin());
  }
};

std::vector<std::string> SplitComma(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream is(line);
  while (std::getline(is, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

Csv ReadCsv(const fs::path& path) {
  Csv csv{path.string(), {}, {}};
  std::istringstream is(ReadInputText(path));
  std::string line;
  int number = 0;
  while (std::getline(is, line)) {
    ++number;
    if (line.empty()) continue;
    std::vector<std::string> cells = SplitComma(line);
    if (csv.header.empty()) {
      csv.header = std::move(cells);
    } else if (cells.size() != csv.header.size()) {
      throw InputError(csv.file, number,
                       Format("has %zu fields, the header %zu", cells.size(), csv.header.size()));
    } else {
      csv.rows.push_back(std::move(cells));
    }
  }
  if (csv.header.empty()) throw InputError(csv.file, 0, "is empty");
  return csv;
}

double ToNumber(const std::string& s) {
  if (s.empty() || s == "nan") return kNoValue;
  try {
    return std::stod(s);
  } catch (const std::exception&) {
    return kNoValue;
  }
}

double JsonNumber(const Json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : kNoValue;
}

MeanAndError JsonMean(const Json& j, const char* mean, const char* error, int count) {
  const double m = JsonNumber(j, mean);
  if (!std::isfinite(m)) return {kNoValue, kNoValue, 0};
  return {m, JsonNumber(j, error), count};
}

MeanAndError MeanOf(const std::vector<double>& x) {
  if (x.empty()) return {kNoValue, kNoValue, 0};
  return MeanWithError(x);
}

void ReadPackingQuantities(const StudyPacking& packing, StudyRun& out) {
  const Scene scene = ReadPacking(packing.file.string());
  const Coordination z = ComputeCoordination(scene, scene.forces);
  out.packing_fraction = PackingFraction(scene);
  out.z = z.z;
  out.z_with_rattlers = z.z_with_rattlers;
  out.rattlers = z.rattlers;
  out.particles = 0;
  double bed = -INFINITY, top = -INFINITY;
  for (const Particle& p : scene.particles) {
    if (p.fixed) {
      bed = std::max(bed, p.position.y() + p.radius);
    } else {
      ++out.particles;
      top = std::max(top, p.position.y() + p.radius);
    }
  }
  if (packing.key.protocol == "gravity") out.height = std::isfinite(bed) ? top - bed : top;
}

void ReadSummary(const fs::path& dir, StudyRun& out) {
  const fs::path path = dir / "summary.json";
  Json s;
  try {
    s = Json::parse(ReadInputText(path));
  } catch (const Json::parse_error& e) {
    throw InputError(path.string(), 0, std::string("not valid JSON: ") + e.what());
  }
  if (!s.value("complete", false))
    throw InputError(path.string(), 0, "the perturbations are not all done");
  out.perturbations = s.value("perturbations", 0);
  out.used = s.value("used", 0);
  out.dynamic = s.value("dynamic", 0);
  out.nonlinear = s.value("nonlinear", 0);
  out.not_converged = s.value("not_converged", 0);
  out.blocked = s.value("blocked", 0);
  out.shift_rattlers = s.value("rattlers", 0);
  out.seconds = JsonNumber(s, "seconds");
  out.mean_contact_force =
      JsonNumber(s, out.key.protocol == "gravity" ? "mean_fcont" : "mean_fcont_all");
  out.f_crit = JsonMean(s, "mean_fcrit", "mean_fcrit_error", out.used);
  out.f_reference = JsonMean(s, "mean_freference", "", out.used);
  out.delta = JsonMean(s, "mean_delta", "mean_delta_error", out.used);
  out.ratio = JsonMean(s, "ratio_fcrit_freference", "ratio_error", out.used);
  out.ratio_all = JsonMean(s, "ratio_fcrit_fcont_all", "ratio_fcrit_fcont_all_error", out.used);
  out.alpha = JsonMean(s, "alpha", "alpha_error", out.used);
  out.tail_scale =
      JsonMean(s, "fcrit_tail_scale", "fcrit_tail_scale_error", s.value("fcrit_tail_samples", 0));
}

// A perturbation's row, keyed by what names it in both CSVs.
std::string TargetKey(bool shift, int i, int j, int ix, int iy) {
  if (shift) return Format("p%d", i);
  if (i > j) {
    std::swap(i, j);
    ix = -ix;
    iy = -iy;
  }
  return Format("c%d-%d:%d,%d", i, j, ix, iy);
}

// An interval narrower than this fraction of its top is a point for F_crit, whose inertial part
// alone is up to 3e-6 of it (docs/perturbations.md): no position in it.
constexpr double kPointInterval = 1e-4;

struct Interval {
  double low = kNoValue, high = kNoValue;
};

std::map<std::string, Interval> ReadBounds(const fs::path& path, bool shift) {
  const Csv csv = ReadCsv(path);
  const int low = csv.Column("min");
  const int high = csv.Column(shift ? "max" : "max_without_friction");
  const int i = csv.Column(shift ? "particle" : "i");
  std::map<std::string, Interval> out;
  for (const auto& row : csv.rows) {
    const std::string key =
        shift ? TargetKey(true, std::stoi(row[i]), -1, 0, 0)
              : TargetKey(false, std::stoi(row[i]), std::stoi(row[csv.Column("j")]),
                          std::stoi(row[csv.Column("image_x")]),
                          std::stoi(row[csv.Column("image_y")]));
    out[key] = {ToNumber(row[low]), ToNumber(row[high])};
  }
  return out;
}

void ReadPerturbationRows(const StudyRunPlan& plan, StudyRun& out) {
  const Csv csv = ReadCsv(plan.dir / "perturbations.csv");
  const bool shift = plan.kind == "top" || plan.kind == "bottom";
  const std::map<std::string, Interval> bounds =
      plan.bounds ? ReadBounds(plan.bounds_csv, shift) : std::map<std::string, Interval>{};
  const int f_crit = csv.Column("f_crit"), status = csv.Column("status"),
            rattler = csv.Column("rattler"), i = csv.Column("i"), j = csv.Column("j"),
            ix = csv.Column("image_x"), iy = csv.Column("image_y");
  std::vector<double> any, rattlers, low, high, position;
  for (const auto& row : csv.rows) {
    const double f = ToNumber(row[f_crit]);
    const bool is_rattler = row[rattler] == "1";
    if (is_rattler && std::isfinite(f)) rattlers.push_back(f);
    if (!is_rattler && std::isfinite(f) && std::isfinite(out.mean_contact_force))
      any.push_back(f / out.mean_contact_force);
    if (row[status] != "ok" || is_rattler) continue;
    const auto b = bounds.find(TargetKey(shift, std::stoi(row[i]), std::stoi(row[j]),
                                         std::stoi(row[ix]), std::stoi(row[iy])));
    if (b == bounds.end() || !std::isfinite(b->second.low) || !std::isfinite(b->second.high))
      continue;
    low.push_back(b->second.low);
    high.push_back(b->second.high);
    // μ → 0: the interval is one point, and it places nothing.
    const double width = b->second.high - b->second.low;
    if (width > kPointInterval * std::abs(b->second.high))
      position.push_back((f - b->second.low) / width);
  }
  out.f_crit_any = MeanOf(any);
  out.rattler_f_crit = MeanOf(rattlers);
  out.lp_min = MeanOf(low);
  out.lp_max = MeanOf(high);
  out.lp_position = MeanOf(position);
}

// --- writing the tables ----------------------------------------------------------------

std::string Num(double x) { return std::isfinite(x) ? Format("%.10g", x) : ""; }
std::string Triple(const MeanAndError& m) {
  return Num(m.mean) + "," + Num(m.error) + "," + std::to_string(m.count);
}

const std::vector<std::pair<std::string, MeanAndError StudyRow::*>> kRowQuantities = {
    {"packing_fraction", &StudyRow::packing_fraction},
    {"z", &StudyRow::z},
    {"z_with_rattlers", &StudyRow::z_with_rattlers},
    {"height", &StudyRow::height},
    {"mean_contact_force", &StudyRow::mean_contact_force},
    {"f_crit", &StudyRow::f_crit},
    {"f_reference", &StudyRow::f_reference},
    {"ratio_fcrit_freference", &StudyRow::ratio},
    {"ratio_fcrit_fcont_all", &StudyRow::ratio_all},
    {"ratio_any_fcont_all", &StudyRow::f_crit_any},
    {"delta", &StudyRow::delta},
    {"alpha", &StudyRow::alpha},
    {"tail_scale", &StudyRow::tail_scale},
    {"rattler_fcrit", &StudyRow::rattler_f_crit},
    {"lp_min", &StudyRow::lp_min},
    {"lp_max", &StudyRow::lp_max},
    {"lp_position", &StudyRow::lp_position}};

std::string KeyColumns(const StudyKey& k) {
  return std::to_string(k.n) + "," + Num(k.width) + "," + Num(k.pressure) + "," + Num(k.mu) + "," +
         k.kind;
}

std::string SummaryCsv(const std::vector<StudyRow>& rows, const std::string& protocol) {
  std::ostringstream os;
  os << "n,width,pressure,mu,kind,packings,particles,rattlers,perturbations,ok,dynamic,nonlinear,"
        "not_converged,blocked,shift_rattlers,dynamic_share,seconds";
  for (const auto& [name, q] : kRowQuantities)
    os << "," << name << "," << name << "_error," << name << "_count";
  os << "\n";
  for (const StudyRow& r : rows) {
    if (r.key.protocol != protocol) continue;
    os << KeyColumns(r.key) << "," << r.packings << "," << r.particles << "," << r.rattlers << ","
       << r.perturbations << "," << r.used << "," << r.dynamic << "," << r.nonlinear << ","
       << r.not_converged << "," << r.blocked << "," << r.shift_rattlers << ","
       << Num(r.dynamic_share) << "," << Format("%.1f", r.seconds);
    for (const auto& [name, q] : kRowQuantities) os << "," << Triple(r.*q);
    os << "\n";
  }
  return os.str();
}

std::string RunsCsv(const StudyPlan& plan, const std::vector<StudyRun>& runs) {
  std::ostringstream os;
  os << "protocol,n,width,pressure,mu,kind,seed,packing,run_dir,bounds_csv,perturbations,ok,"
        "dynamic,nonlinear,not_converged,blocked,packing_fraction,z,z_with_rattlers,height,"
        "mean_contact_force,ratio,ratio_error,ratio_all,ratio_all_error,delta,delta_error,alpha,"
        "alpha_error,lp_position,seconds\n";
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const StudyRun& r = runs[k];
    const StudyRunPlan& p = plan.runs[k];
    const auto rel = [&](const fs::path& f) { return f.lexically_relative(plan.output).string(); };
    os << r.key.protocol << "," << KeyColumns(r.key) << "," << r.seed << ","
       << rel(plan.packings[p.packing].file) << "," << rel(p.dir) << ","
       << (p.bounds ? rel(p.bounds_csv) : "") << "," << r.perturbations << "," << r.used << ","
       << r.dynamic << "," << r.nonlinear << "," << r.not_converged << "," << r.blocked << ","
       << Num(r.packing_fraction) << "," << Num(r.z) << "," << Num(r.z_with_rattlers) << ","
       << Num(r.height) << "," << Num(r.mean_contact_force) << "," << Num(r.ratio.mean) << ","
       << Num(r.ratio.error) << "," << Num(r.ratio_all.mean) << "," << Num(r.ratio_all.error) << ","
       << Num(r.delta.mean) << "," << Num(r.delta.error) << "," << Num(r.alpha.mean) << ","
       << Num(r.alpha.error) << "," << Num(r.lp_position.mean) << "," << Format("%.1f", r.seconds)
       << "\n";
  }
  return os.str();
}

// "1.207 ± 0.022 (200)": a mean, its error and the samples behind it; "–" for none.
std::string Cell(const MeanAndError& m, const char* format = "%.4g") {
  if (!std::isfinite(m.mean)) return "–";
  std::string s = Format(format, m.mean);
  if (std::isfinite(m.error) && m.error > 0.0) s += " ± " + Format("%.2g", m.error);
  return s + Format(" (%d)", m.count);
}

// A Markdown table's header line "| a | b |" and the rule under it, one "---|" per column.
std::string TableHeader(const std::string& header) {
  std::string rule = "|";
  for (std::size_t c = 1;
       c < static_cast<std::size_t>(std::count(header.begin(), header.end(), '|')); ++c)
    rule += "---|";
  return header + "\n" + rule + "\n";
}

// "[0.32, 1.64] (9)": the mean LP interval over `reference`, and how many perturbations.
std::string IntervalCell(const StudyRow& r, double reference) {
  if (!std::isfinite(r.lp_min.mean) || !(reference > 0.0)) return "–";
  return Format("[%.3g, %.3g] (%d)", r.lp_min.mean / reference, r.lp_max.mean / reference,
                r.lp_min.count);
}

std::string PressureTable(const std::vector<StudyRow>& rows) {
  std::ostringstream out;
  out << TableHeader(
      "| N | μ | mode | packings | openings | ok | dynamic | nonlinear | not-converged | blocked "
      "| ⟨F_crit⟩/⟨F_cont⟩ (ok) | ⟨F_crit⟩/⟨F⟩ all contacts | any step force / ⟨F⟩ | ⟨δ⟩ | α | "
      "LP [min, max] / ⟨F⟩ | F_crit in LP interval | z | z with rattlers | φ |");
  for (const StudyRow& r : rows) {
    if (r.key.protocol != "pressure") continue;
    const double f = r.mean_contact_force.mean;
    out << "| " << r.key.n << " | " << Short(r.key.mu) << " | " << r.key.kind << " | " << r.packings
        << " | " << r.perturbations << " | " << r.used << " | " << r.dynamic << " | " << r.nonlinear
        << " | " << r.not_converged << " | " << r.blocked << " | " << Cell(r.ratio) << " | "
        << Cell(r.ratio_all) << " | " << Cell(r.f_crit_any) << " | " << Cell(r.delta) << " | "
        << Cell(r.alpha) << " | " << IntervalCell(r, f) << " | " << Cell(r.lp_position, "%.3g")
        << " | " << Cell(r.z) << " | " << Cell(r.z_with_rattlers) << " | "
        << Cell(r.packing_fraction) << " |\n";
  }
  return out.str();
}

std::string GravityTable(const std::vector<StudyRow>& rows) {
  std::ostringstream os;
  os << TableHeader(
      "| N | width | μ | side | piles | shifts | ok | dynamic | nonlinear | not-converged | "
      "blocked "
      "| rattlers | ⟨F_crit⟩/⟨F_y⟩ | ⟨F_y⟩ | ⟨δ⟩ | rattlers' F_crit | LP [min, max] / ⟨F_y⟩ | "
      "F_crit in LP interval | height | z | z with rattlers |");
  for (const StudyRow& r : rows) {
    if (r.key.protocol != "gravity") continue;
    const double f = r.f_reference.mean;
    os << "| " << r.key.n << " | " << Short(r.key.width) << " | " << Short(r.key.mu) << " | "
       << r.key.kind << " | " << r.packings << " | " << r.perturbations << " | " << r.used << " | "
       << r.dynamic << " | " << r.nonlinear << " | " << r.not_converged << " | " << r.blocked
       << " | " << r.shift_rattlers << " | " << Cell(r.ratio) << " | " << Cell(r.f_reference)
       << " | " << Cell(r.delta) << " | " << Cell(r.rattler_f_crit) << " | " << IntervalCell(r, f)
       << " | " << Cell(r.lp_position, "%.3g") << " | " << Cell(r.height) << " | " << Cell(r.z)
       << " | " << Cell(r.z_with_rattlers) << " |\n";
  }
  return os.str();
}

std::string Report(const StudyPlan& plan, const std::vector<StudyRow>& rows, double seconds) {
  std::ostringstream os;
  os << "# Friction study: "
     << (plan.config.description.empty() ? plan.config.file : plan.config.description) << "\n\n";
  os << "Made by `unjam study " << plan.config.file
     << (plan.config.size.empty() ? "" : " --size " + plan.config.size) << "` (unjam "
     << UNJAM_VERSION << "), " << plan.threads << " thread(s); this run " << Format("%.0f", seconds)
     << " s. The configuration as run: `study.json`; one row per packing and kind: `runs.csv`; "
        "the rows below: `summary-pressure.csv`, `summary-gravity.csv`; figures: `figures/`.\n\n";
  os << "Each cell: mean ± standard error (samples). With one packing the error and samples are "
        "its perturbations'; with several, the mean of the packings' means and the error from "
        "their scatter (samples: packings). ⟨F_crit⟩/⟨F_cont⟩ (ok): the quasi-static openings, "
        "over their own ⟨F_cont⟩; over ⟨F⟩ of all contacts: the paper's denominator; any step "
        "force: every opening whose step a backend solved (ok, nonlinear, and dynamic ones "
        "solved; the static LP's dynamic ones have no step force) over ⟨F⟩ of all contacts. α: "
        "the decay exponent of the displacement field averaged in the contact frame (the "
        "paper's). LP [min, max]: the admissible range of the same contacts' forces "
        "(docs/indeterminacy.md), ok openings only; F_crit in LP interval: (F_crit − min)/(max − "
        "min).\n\n";
  if (!plan.config.pressure.empty())
    os << "## Packings under pressure: contact openings\n\n" << PressureTable(rows) << "\n";
  if (!plan.config.gravity.empty())
    os << "## Piles under gravity: particle shifts\n\n" << GravityTable(rows) << "\n";
  return os.str();
}

}  // namespace

StudyPlan MakeStudyPlan(StudyConfig config, const std::string& output_override, int threads) {
  StudyPlan plan;
  plan.output = output_override.empty() ? config.output : fs::path(output_override);
  if (plan.output.empty())
    throw std::invalid_argument("no output folder: give -o DIR or \"output\" in " + config.file);
  if (config.packings.empty()) config.packings = plan.output / "packings";
  plan.threads = threads;
  plan.config = std::move(config);
  const fs::path runs = plan.output / "runs";
  for (const PressureSet& set : plan.config.pressure) {
    for (double mu : set.mu) {
      for (std::uint64_t seed : set.seeds) {
        StudyKey key{"pressure", set.n, kNoValue, set.pressure, mu, ""};
        const int p = AddPacking(plan, key, seed, set.max_steps);
        const fs::path dir = runs / plan.packings[p].name;
        for (const std::string& mode : set.modes)
          AddRun(plan, {p, mode, set.openings, set.bounds, dir / ("openings-" + mode),
                        dir / Format("bounds-openings%d.csv", set.openings)});
      }
    }
  }
  for (const GravitySet& set : plan.config.gravity) {
    for (double mu : set.mu) {
      for (std::uint64_t seed : set.seeds) {
        StudyKey key{"gravity", set.n, set.width, kNoValue, mu, ""};
        const int p = AddPacking(plan, key, seed, set.max_steps);
        const fs::path dir = runs / plan.packings[p].name;
        for (const std::string& side : set.sides)
          AddRun(plan, {p, side, 0, set.bounds, dir / ("shifts-" + side),
                        dir / ("bounds-" + side + ".csv")});
      }
    }
  }
  return plan;
}

StudyRun ReadStudyRun(const StudyPlan& plan, const StudyRunPlan& run) {
  const StudyPacking& packing = plan.packings[run.packing];
  StudyRun out;
  out.key = packing.key;
  out.key.kind = run.kind;
  out.seed = packing.seed;
  ReadPackingQuantities(packing, out);
  ReadSummary(run.dir, out);
  ReadPerturbationRows(run, out);
  return out;
}

void WriteStudyTables(const StudyPlan& plan, const std::vector<StudyRun>& runs,
                      const std::vector<StudyRow>& rows, double seconds) {
  WriteFileAtomically(plan.output / "runs.csv", RunsCsv(plan, runs));
  if (!plan.config.pressure.empty())
    WriteFileAtomically(plan.output / "summary-pressure.csv", SummaryCsv(rows, "pressure"));
  if (!plan.config.gravity.empty())
    WriteFileAtomically(plan.output / "summary-gravity.csv", SummaryCsv(rows, "gravity"));
  WriteFileAtomically(plan.output / "report.md", Report(plan, rows, seconds));
}

}  // namespace unjam::cli
