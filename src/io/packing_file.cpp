// Reading `.unjam` packings (docs/format.md). The parser walks the text once, line by
// line, without copying it; every failure becomes an InputError naming the file and line.
#include "unjam/io/packing_file.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "packing_checks.hpp"
#include "text_fields.hpp"
#include "unjam/io/read_text.hpp"

namespace unjam {

using io_internal::DoubleToString;
using io_internal::FieldError;
using io_internal::Fields;
using io_internal::ParseDouble;
using io_internal::ParseInteger;
using io_internal::Quote;
using io_internal::SourceLines;

namespace {

std::string FormatWhat(const std::string& file, int line, const std::string& message) {
  return line > 0 ? file + ":" + std::to_string(line) + ": " + message : file + ": " + message;
}

}  // namespace

InputError::InputError(const std::string& file, int line, const std::string& message)
    : std::runtime_error(FormatWhat(file, line, message)), file_(file), line_(line),
      message_(message) {}

namespace {

constexpr std::string_view kHeader = "unjam-packing";
constexpr long long kVersion = 1;
constexpr double kWallNormalTolerance = 1e-12;
// The shortest possible particle and force lines ("0 0 0 0 0 0 1 1 0\n", "0 1 0 0 0 0\n"):
// a declared count never reserves more entries than the rest of the text could hold.
constexpr std::size_t kMinParticleLineBytes = 18;
constexpr std::size_t kMinForceLineBytes = 12;

bool IsKey(std::string_view token) {
  static const std::set<std::string_view> kKeys = {"cell",
                                                   "periodic",
                                                   "wall",
                                                   "gravity",
                                                   "friction",
                                                   "pressure-bath",
                                                   "prescribed-motion",
                                                   "prescribed-gap",
                                                   "seed",
                                                   "provenance",
                                                   "particles",
                                                   "forces",
                                                   "end"};
  return kKeys.count(token) > 0;
}

// Keys that describe one property of the scene and so may appear at most once.
bool IsSingleKey(std::string_view token) {
  return token != "wall" && token != "prescribed-motion" && token != "prescribed-gap";
}

bool LooksNumeric(std::string_view token) {
  const char c = token.front();
  return (c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.';
}

class PackingParser {
 public:
  PackingParser(std::string_view text, const std::string& name, const ReadOptions& options)
      : text_(text), name_(name), options_(options) {
    // Tolerate a UTF-8 byte order mark that some editors insert.
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = 3;
  }
  Scene Parse();

 private:
  [[noreturn]] void Fail(int line, const std::string& message) const {
    throw InputError(name_, line, message);
  }
  int LastLine() const { return std::max(line_number_, 1); }
  bool NextRecord();
  void ExpectValues(long long count, std::string_view usage) const;
  double Value(int k, std::string_view what) const { return ParseDouble(fields_[k], what); }
  std::size_t Reservable(long long count, std::size_t min_line_bytes) const;
  void NextSectionLine(std::string_view section, long long count, long long found);
  void ParseHeader();
  void ParseKeyLine();
  void ParseSimpleKey(std::string_view key);
  void ParseParticles();
  void ParseParticleLine();
  void ParseForces();
  void ParseProvenance();
  void Validate() const;

  std::string_view text_;
  const std::string& name_;
  const ReadOptions& options_;
  std::size_t pos_ = 0;
  int line_number_ = 0;
  std::string_view line_;
  Fields fields_;
  std::map<std::string_view, int> single_keys_;  // key → line of its first use
  std::string_view previous_section_;            // a counted section that just ended
  long long previous_count_ = 0;
  Scene scene_;
  SourceLines source_;
};

// Advances to the next line that has fields. Lines end at '\n'; a trailing '\r' is dropped
// so that files edited on Windows read the same.
bool PackingParser::NextRecord() {
  while (pos_ < text_.size()) {
    const std::size_t newline = text_.find('\n', pos_);
    const std::size_t end = newline == std::string_view::npos ? text_.size() : newline;
    line_ = text_.substr(pos_, end - pos_);
    pos_ = newline == std::string_view::npos ? text_.size() : newline + 1;
    if (line_number_ < INT_MAX) ++line_number_;
    if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);
    fields_ = io_internal::SplitFields(line_);
    if (!fields_.empty()) return true;
  }
  return false;
}

void PackingParser::ExpectValues(long long count, std::string_view usage) const {
  if (fields_.count == count + 1) return;
  throw FieldError(std::string(fields_[0]) + " expects " + std::to_string(count) + " value(s) (" +
                   std::string(usage) + "), got " + std::to_string(fields_.count - 1));
}

std::size_t PackingParser::Reservable(long long count, std::size_t min_line_bytes) const {
  const std::size_t fit = (text_.size() - pos_) / min_line_bytes + 1;
  return std::min(static_cast<std::size_t>(count), fit);
}

// Moves to line `found` (0-based) of a counted section, which must not be a key line.
void PackingParser::NextSectionLine(std::string_view section, long long count, long long found) {
  const std::string expected = "expected " + std::to_string(count) + " " + std::string(section) +
                               " line(s), found " + std::to_string(found);
  if (!NextRecord()) Fail(LastLine(), "truncated: " + expected);
  if (IsKey(fields_[0])) Fail(line_number_, expected + " before " + Quote(fields_[0]));
}

Scene PackingParser::Parse() {
  try {
    ParseHeader();
    bool ended = false;
    while (NextRecord()) {
      if (fields_[0] == "end") {
        ExpectValues(0, "end");
        source_.end = line_number_;
        ended = true;
        break;
      }
      ParseKeyLine();
    }
    if (!ended) Fail(LastLine(), "truncated: missing 'end'");
    if (NextRecord()) Fail(line_number_, "unexpected content after 'end': " + Quote(fields_[0]));
  } catch (const FieldError& e) {
    Fail(line_number_, e.what());
  }
  Validate();
  return std::move(scene_);
}

void PackingParser::ParseHeader() {
  const std::string expected =
      "expected the header '" + std::string(kHeader) + " " + std::to_string(kVersion) + "'";
  if (!NextRecord()) Fail(LastLine(), "missing header: " + expected + " (empty file)");
  if (fields_[0] != kHeader)
    Fail(line_number_, "missing header: " + expected + ", got " + Quote(fields_[0]));
  ExpectValues(1, "format version");
  const long long version = ParseInteger(fields_[1], "format version", 0, LLONG_MAX);
  if (version != kVersion) {
    Fail(line_number_, "unsupported format version " + std::to_string(version) +
                           " (this reader reads version " + std::to_string(kVersion) + ")");
  }
}

void PackingParser::ParseKeyLine() {
  const std::string_view key = fields_[0];
  if (!IsKey(key)) {
    if (!previous_section_.empty() && LooksNumeric(key)) {
      Fail(line_number_, "more " + std::string(previous_section_) + " lines than the declared " +
                             std::to_string(previous_count_));
    }
    Fail(line_number_, "unknown key " + Quote(key));
  }
  previous_section_ = {};
  if (IsSingleKey(key)) {
    const auto [first, inserted] = single_keys_.emplace(key, line_number_);
    if (!inserted) {
      Fail(line_number_, "duplicate key " + Quote(key) + " (first given on line " +
                             std::to_string(first->second) + ")");
    }
  }
  if (key == "particles") {
    ParseParticles();
  } else if (key == "forces") {
    ParseForces();
  } else if (key == "provenance") {
    ParseProvenance();
  } else {
    ParseSimpleKey(key);
  }
}

// Keys whose values all sit on their own line.
void PackingParser::ParseSimpleKey(std::string_view key) {
  Effects& effects = scene_.effects;
  if (key == "cell") {
    ExpectValues(2, "Lx Ly");
    const Vec2 size(Value(1, "cell Lx"), Value(2, "cell Ly"));
    if (!(size.x() > 0.0 && size.y() > 0.0)) throw FieldError("cell size must be positive");
    scene_.cell.size = size;
    source_.cell = line_number_;
  } else if (key == "periodic") {
    ExpectValues(1, "none | x | xy");
    const std::string_view axes = fields_[1];
    if (axes != "none" && axes != "x" && axes != "xy") {
      throw FieldError("periodic must be none, x or xy, got " + Quote(axes));
    }
    scene_.cell.periodicity = axes == "none" ? Periodicity::kNone
                              : axes == "x"  ? Periodicity::kX
                                             : Periodicity::kXY;
  } else if (key == "wall") {
    ExpectValues(4, "point x y, inward normal x y");
    Wall wall;
    wall.point = Vec2(Value(1, "wall point x"), Value(2, "wall point y"));
    wall.normal = Vec2(Value(3, "wall normal x"), Value(4, "wall normal y"));
    // The solver relies on a unit normal; silently rescaling would change the file's meaning.
    const double length = std::hypot(wall.normal.x(), wall.normal.y());
    if (!(std::abs(length - 1.0) <= kWallNormalTolerance)) {
      throw FieldError("wall normal must be a unit vector (within 1e-12), its length is " +
                       DoubleToString(length));
    }
    scene_.cell.walls.push_back(wall);
  } else if (key == "gravity") {
    ExpectValues(2, "gx gy");
    effects.gravity = Vec2(Value(1, "gravity x"), Value(2, "gravity y"));
  } else if (key == "friction") {
    ExpectValues(1, "Coulomb coefficient");
    effects.friction = Value(1, "friction");
    if (effects.friction < 0.0) throw FieldError("friction must not be negative");
  } else if (key == "pressure-bath") {
    ExpectValues(3, "P_ext cell_mass strain_rate");
    PressureBath bath{Value(1, "pressure"), Value(2, "cell mass"), Value(3, "strain rate")};
    if (!(bath.cell_mass > 0.0)) throw FieldError("pressure-bath cell mass must be positive");
    effects.pressure_bath = bath;
    source_.pressure_bath = line_number_;
  } else if (key == "prescribed-motion") {
    ExpectValues(4, "particle vx vy spin");
    PrescribedMotion motion;
    motion.particle = static_cast<int>(ParseInteger(fields_[1], "particle index", 0, INT_MAX));
    motion.velocity = Vec2(Value(2, "vx"), Value(3, "vy"));
    motion.spin = Value(4, "spin");
    effects.prescribed_motion.push_back(motion);
    source_.motions.push_back(line_number_);
  } else if (key == "prescribed-gap") {
    ExpectValues(5, "i j image_x image_y gap");
    PrescribedGap gap;
    gap.i = static_cast<int>(ParseInteger(fields_[1], "particle i", 0, INT_MAX));
    gap.j = static_cast<int>(ParseInteger(fields_[2], "particle j", 0, INT_MAX));
    gap.image = {static_cast<int>(ParseInteger(fields_[3], "image x", -1, 1)),
                 static_cast<int>(ParseInteger(fields_[4], "image y", -1, 1))};
    gap.gap = Value(5, "gap");
    effects.prescribed_gaps.push_back(gap);
    source_.gaps.push_back(line_number_);
  } else if (key == "seed") {
    ExpectValues(1, "unsigned 64-bit integer");
    scene_.seed = io_internal::ParseUnsigned64(fields_[1], "seed");
  }
}

void PackingParser::ParseParticles() {
  ExpectValues(1, "count");
  const long long count = ParseInteger(fields_[1], "particle count", 0, INT_MAX);
  const std::size_t reserve = Reservable(count, kMinParticleLineBytes);
  scene_.particles.reserve(reserve);
  source_.particles.reserve(reserve);
  for (long long k = 0; k < count; ++k) {
    NextSectionLine("particle", count, k);
    ParseParticleLine();
  }
  previous_section_ = "particle";
  previous_count_ = count;
}

void PackingParser::ParseParticleLine() {
  if (fields_.count != 9) {
    throw FieldError(
        "a particle line has 9 fields (x y angle vx vy spin radius density fixed), got " +
        std::to_string(fields_.count));
  }
  Particle p;
  p.position = Vec2(Value(0, "x"), Value(1, "y"));
  p.angle = Value(2, "angle");
  p.velocity = Vec2(Value(3, "vx"), Value(4, "vy"));
  p.spin = Value(5, "spin");
  p.radius = Value(6, "radius");
  p.density = Value(7, "density");
  if (!(p.radius > 0.0))
    throw FieldError("radius must be positive, got " + DoubleToString(p.radius));
  if (!(p.density > 0.0))
    throw FieldError("density must be positive, got " + DoubleToString(p.density));
  if (fields_[8] != "0" && fields_[8] != "1")
    throw FieldError("fixed must be 0 or 1, got " + Quote(fields_[8]));
  p.fixed = fields_[8] == "1";
  scene_.particles.push_back(p);
  source_.particles.push_back(line_number_);
}

void PackingParser::ParseForces() {
  ExpectValues(1, "count");
  const long long count = ParseInteger(fields_[1], "force count", 0, INT_MAX);
  const std::size_t reserve = Reservable(count, kMinForceLineBytes);
  scene_.forces.reserve(reserve);
  source_.forces.reserve(reserve);
  for (long long k = 0; k < count; ++k) {
    NextSectionLine("force", count, k);
    if (fields_.count != 6) {
      throw FieldError("a force line has 6 fields (i j image_x image_y normal tangential), got " +
                       std::to_string(fields_.count));
    }
    ContactForce force;
    force.i = static_cast<int>(ParseInteger(fields_[0], "particle i", 0, INT_MAX));
    force.j = static_cast<int>(ParseInteger(fields_[1], "particle or wall j", INT_MIN, INT_MAX));
    force.image = {static_cast<int>(ParseInteger(fields_[2], "image x", -1, 1)),
                   static_cast<int>(ParseInteger(fields_[3], "image y", -1, 1))};
    force.normal = Value(4, "normal force");
    force.tangential = Value(5, "tangential force");
    // A contact pushes, never pulls: a negative normal force is no static force of rigid disks.
    if (force.normal < 0.0)
      throw FieldError("normal force must not be negative, got " + DoubleToString(force.normal));
    scene_.forces.push_back(force);
    source_.forces.push_back(line_number_);
  }
  previous_section_ = "force";
  previous_count_ = count;
}

// The rest of the line after one separator, verbatim: free text may contain '#'.
void PackingParser::ParseProvenance() {
  const std::size_t key_end =
      static_cast<std::size_t>(fields_[0].data() - line_.data()) + fields_[0].size();
  std::string_view rest = line_.substr(key_end);
  if (!rest.empty() && io_internal::IsFieldSeparator(rest.front())) {
    rest.remove_prefix(1);
  } else {
    rest = {};  // "provenance" alone, or followed directly by a comment
  }
  scene_.provenance = io_internal::UnescapeText(rest);
}

// Checks that need the whole file run once everything is read, so that keys may come in
// any order.
void PackingParser::Validate() const {
  if (!single_keys_.contains("cell")) Fail(source_.end, "missing 'cell'");
  if (!single_keys_.contains("particles")) Fail(source_.end, "missing 'particles'");
  io_internal::CheckPacking(scene_, source_, name_, options_);
}

}  // namespace

Scene ParsePacking(std::string_view text, const std::string& name, const ReadOptions& options) {
  return PackingParser(text, name, options).Parse();
}

Scene ReadPacking(const std::filesystem::path& path, const ReadOptions& options) {
  return ParsePacking(ReadInputText(path), path.string(), options);
}

}  // namespace unjam
