#include "packing_checks.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>

#include "text_fields.hpp"
#include "unjam/contacts/contact.hpp"

namespace unjam::io_internal {

namespace {

std::string Index(int k) { return std::to_string(k); }

// Periodic images only make sense along periodic axes.
void CheckImage(const std::array<int, 2>& image, Periodicity periodicity, const std::string& name,
                int line) {
  if (image[0] != 0 && !PeriodicX(periodicity))
    throw InputError(name, line, "image x must be 0: x is not periodic");
  if (image[1] != 0 && !PeriodicY(periodicity))
    throw InputError(name, line, "image y must be 0: y is not periodic");
}

// Positions along periodic axes must already be wrapped into [0, L): the reader does not
// move particles, so that what is read is exactly what was written.
void CheckPositions(const Scene& scene, const SourceLines& source, const std::string& name) {
  const Periodicity periodicity = scene.cell.periodicity;
  const Vec2& size = scene.cell.size;
  for (std::size_t k = 0; k < scene.particles.size(); ++k) {
    const Vec2& x = scene.particles[k].position;
    for (int axis = 0; axis < 2; ++axis) {
      const bool periodic = axis == 0 ? PeriodicX(periodicity) : PeriodicY(periodicity);
      if (!periodic || (x[axis] >= 0.0 && x[axis] < size[axis])) continue;
      const char* label = axis == 0 ? "x" : "y";
      throw InputError(name, source.particles[k],
                       "particle " + Index(static_cast<int>(k)) + ": " + label + " = " +
                           DoubleToString(x[axis]) + " lies outside the periodic cell [0, " +
                           DoubleToString(size[axis]) + ")");
    }
  }
}

void CheckPrescribed(const Scene& scene, const SourceLines& source, const std::string& name) {
  const int n = static_cast<int>(scene.particles.size());
  std::vector<int> motion_line(scene.particles.size(), 0);
  const auto& motions = scene.effects.prescribed_motion;
  for (std::size_t k = 0; k < motions.size(); ++k) {
    const int p = motions[k].particle;
    const int line = source.motions[k];
    if (p >= n)
      throw InputError(
          name, line,
          "prescribed-motion particle " + Index(p) + " out of range (" + Index(n) + " particles)");
    if (motion_line[p] != 0) {
      throw InputError(name, line,
                       "particle " + Index(p) + " already has a prescribed motion (line " +
                           Index(motion_line[p]) + ")");
    }
    motion_line[p] = line;
  }
  const auto& gaps = scene.effects.prescribed_gaps;
  for (std::size_t k = 0; k < gaps.size(); ++k) {
    const int line = source.gaps[k];
    if (gaps[k].i >= n || gaps[k].j >= n) {
      throw InputError(name, line,
                       "prescribed-gap particle out of range (" + Index(n) + " particles)");
    }
    if (gaps[k].i == gaps[k].j)
      throw InputError(name, line, "prescribed-gap needs two different particles");
    CheckImage(gaps[k].image, scene.cell.periodicity, name, line);
  }
}

// The contact a force line names, the same whichever of its two disks comes first: (i, j)
// at image m is (j, i) at image −m. A wall (j < 0) is always second.
std::tuple<int, int, int, int> ContactKey(const ContactForce& f) {
  if (IsWallIndex(f.j) || f.i < f.j) return {f.i, f.j, f.image[0], f.image[1]};
  return {f.j, f.i, -f.image[0], -f.image[1]};
}

// A contact has one force: a second line for it would be counted as a second contact
// (coordination, force statistics) and give the warm start two values.
void CheckDuplicateForces(const Scene& scene, const SourceLines& source, const std::string& name) {
  std::map<std::tuple<int, int, int, int>, int> first_line;
  for (std::size_t k = 0; k < scene.forces.size(); ++k) {
    const ContactForce& f = scene.forces[k];
    const auto [first, inserted] = first_line.emplace(ContactKey(f), source.forces[k]);
    if (inserted) continue;
    const std::string contact =
        IsWallIndex(f.j) ? "particle " + Index(f.i) + " on wall " + Index(JToWallIndex(f.j)) + " ("
                         : "particles " + Index(f.i) + " and " + Index(f.j) + " (image " +
                               Index(f.image[0]) + " " + Index(f.image[1]) + "; ";
    throw InputError(
        name, source.forces[k],
        "duplicate force of " + contact + "first given on line " + Index(first->second) + ")");
  }
}

// j is a particle index, or a wall encoded as −1 − wall.
void CheckForces(const Scene& scene, const SourceLines& source, const std::string& name) {
  const int n = static_cast<int>(scene.particles.size());
  const int walls = static_cast<int>(scene.cell.walls.size());
  for (std::size_t k = 0; k < scene.forces.size(); ++k) {
    const ContactForce& f = scene.forces[k];
    const int line = source.forces[k];
    if (f.i >= n)
      throw InputError(
          name, line,
          "force particle i = " + Index(f.i) + " out of range (" + Index(n) + " particles)");
    if (IsWallIndex(f.j)) {
      if (JToWallIndex(f.j) >= walls) {
        throw InputError(name, line,
                         "force wall j = " + Index(f.j) + " (wall " + Index(JToWallIndex(f.j)) +
                             ") out of range (" + Index(walls) + " walls)");
      }
      if (f.image != std::array<int, 2>{0, 0})
        throw InputError(name, line, "a wall force has image 0 0");
      continue;
    }
    if (f.j >= n)
      throw InputError(
          name, line,
          "force particle j = " + Index(f.j) + " out of range (" + Index(n) + " particles)");
    if (f.i == f.j) throw InputError(name, line, "a force needs two different particles");
    CheckImage(f.image, scene.cell.periodicity, name, line);
  }
  CheckDuplicateForces(scene, source, name);
}

// Contact detection uses minimum images, which needs periodic lengths of at least
// 2 (2 R_max + margin); a smaller cell cannot be simulated, so it is bad input.
void CheckCellSize(const Scene& scene, double margin, const SourceLines& source,
                   const std::string& name) {
  const double needed = 2.0 * (2.0 * MaxRadius(scene) + margin);
  for (int axis = 0; axis < 2; ++axis) {
    const bool periodic =
        axis == 0 ? PeriodicX(scene.cell.periodicity) : PeriodicY(scene.cell.periodicity);
    if (!periodic || scene.cell.size[axis] >= needed) continue;
    throw InputError(name, source.cell,
                     std::string("periodic cell length ") + (axis == 0 ? "Lx" : "Ly") + " = " +
                         DoubleToString(scene.cell.size[axis]) +
                         " is too small for the largest disk: at least " + DoubleToString(needed) +
                         " (4 R_max - 2 overlap tolerance) is needed");
  }
}

void CheckOverlaps(const Scene& scene, const SourceLines& source, const std::string& name,
                   const ReadOptions& options) {
  const double margin = -options.overlap_tolerance;
  CheckCellSize(scene, margin, source, name);
  std::vector<Contact> contacts;
  try {
    contacts = DetectContacts(scene, margin);
  } catch (const std::invalid_argument& e) {
    throw InputError(name, source.cell, e.what());
  }
  // Report the overlap that shows up first in the file: the one whose later disk comes first.
  const Contact* first = nullptr;
  int first_line = std::numeric_limits<int>::max();
  for (const Contact& c : contacts) {
    if (!(c.gap < margin)) continue;
    const int line = source.particles[c.WithWall() ? c.i : std::max(c.i, c.j)];
    if (line < first_line) {
      first = &c;
      first_line = line;
    }
  }
  if (first == nullptr) return;
  const std::string amount = " by " + DoubleToString(-first->gap) + " (tolerance " +
                             DoubleToString(options.overlap_tolerance) + ")";
  if (first->WithWall()) {
    throw InputError(
        name, first_line,
        "particle " + Index(first->i) + " overlaps wall " + Index(JToWallIndex(first->j)) + amount);
  }
  throw InputError(
      name, first_line,
      "particles " + Index(first->i) + " and " + Index(first->j) + " overlap" + amount);
}

}  // namespace

void CheckPacking(const Scene& scene, const SourceLines& source, const std::string& name,
                  const ReadOptions& options) {
  if (scene.effects.pressure_bath && scene.cell.periodicity != Periodicity::kXY) {
    throw InputError(name, source.pressure_bath,
                     "pressure-bath needs a fully periodic cell (periodic xy)");
  }
  CheckPositions(scene, source, name);
  CheckPrescribed(scene, source, name);
  CheckForces(scene, source, name);
  CheckOverlaps(scene, source, name, options);
}

}  // namespace unjam::io_internal
