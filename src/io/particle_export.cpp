// Particles, displacements and contact forces for ParaView (legacy VTK) and OVITO
// (extended XYZ). Doubles are printed in their shortest exact form.
#include "unjam/io/particle_export.hpp"

#include <stdexcept>
#include <string>

#include "text_fields.hpp"
#include "unjam/contacts/contact.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam {

namespace {

using io_internal::AppendDouble;
using io_internal::AppendDoubles;

// One line of values separated by single spaces.
void AppendRow(std::string& out, std::initializer_list<double> values) {
  const std::size_t begin = out.size();
  AppendDoubles(out, values);
  out.erase(begin, 1);
  out += '\n';
}

// Bad indices would read out of bounds: reject them before writing anything.
void CheckField(const Scene& scene, const ParticleField& field) {
  const int n = static_cast<int>(scene.particles.size());
  if (!field.displacement.empty() && static_cast<int>(field.displacement.size()) != n) {
    throw std::invalid_argument("particle export: " + std::to_string(field.displacement.size()) +
                                " displacements for " + std::to_string(n) + " particles");
  }
  const int walls = static_cast<int>(scene.cell.walls.size());
  for (const ContactForce& f : field.forces) {
    const bool i_ok = f.i >= 0 && f.i < n;
    const bool j_ok = IsWallIndex(f.j) ? JToWallIndex(f.j) < walls : f.j < n;
    if (!i_ok || !j_ok) {
      throw std::invalid_argument("particle export: contact force (" + std::to_string(f.i) + ", " +
                                  std::to_string(f.j) + ") names no particle or wall of the scene");
    }
  }
}

Vec2 Displacement(const ParticleField& field, std::size_t k) {
  return field.displacement.empty() ? Vec2::Zero() : field.displacement[k];
}

// The far end of a contact line: the image of j that touches i (so that a line across the
// periodic boundary is drawn whole), or the contact point on i for a wall.
Vec2 LineEnd(const Scene& scene, const ContactForce& f) {
  if (IsWallIndex(f.j)) {
    const Contact c = MakeWallContact(scene, f.i, JToWallIndex(f.j));
    return scene.particles[f.i].position + c.branch_i;
  }
  const Vec2 shift(f.image[0] * scene.cell.size.x(), f.image[1] * scene.cell.size.y());
  return scene.particles[f.j].position + shift;
}

// The normal ΔF of each drawn contact, matched by key; 0 for contacts without a change.
std::vector<double> NormalChanges(const ParticleField& field) {
  std::vector<double> out(field.forces.size(), 0.0);
  if (field.force_change.empty()) return out;
  const ForcesByContact changes(field.force_change);
  for (std::size_t k = 0; k < field.forces.size(); ++k) {
    Contact key;
    key.i = field.forces[k].i;
    key.j = field.forces[k].j;
    key.image = field.forces[k].image;
    if (const ContactForce* change = changes.Find(key)) out[k] = change->normal;
  }
  return out;
}

void AppendScalarHeader(std::string& out, const char* name, const char* type) {
  out += "SCALARS ";
  out += name;
  out += ' ';
  out += type;
  out += " 1\nLOOKUP_TABLE default\n";
}

void AppendVtkGeometry(const Scene& scene, const ParticleField& field, std::string& out) {
  const std::size_t n = scene.particles.size();
  const std::size_t m = field.forces.size();
  out += "POINTS " + std::to_string(n + m) + " double\n";
  for (const Particle& p : scene.particles) AppendRow(out, {p.position.x(), p.position.y(), 0.0});
  for (const ContactForce& f : field.forces) {
    const Vec2 end = LineEnd(scene, f);
    AppendRow(out, {end.x(), end.y(), 0.0});
  }
  if (n > 0) {
    out += "VERTICES " + std::to_string(n) + ' ' + std::to_string(2 * n) + '\n';
    for (std::size_t k = 0; k < n; ++k) out += "1 " + std::to_string(k) + '\n';
  }
  if (m > 0) {
    out += "LINES " + std::to_string(m) + ' ' + std::to_string(3 * m) + '\n';
    for (std::size_t k = 0; k < m; ++k) {
      out += "2 " + std::to_string(field.forces[k].i) + ' ' + std::to_string(n + k) + '\n';
    }
  }
}

void AppendVtkPointData(const Scene& scene, const ParticleField& field, std::string& out) {
  const std::size_t n = scene.particles.size();
  const std::size_t m = field.forces.size();
  out += "POINT_DATA " + std::to_string(n + m) + '\n';
  AppendScalarHeader(out, "radius", "double");
  for (const Particle& p : scene.particles) AppendRow(out, {p.radius});
  for (std::size_t k = 0; k < m; ++k) out += "0\n";
  AppendScalarHeader(out, "fixed", "int");
  for (const Particle& p : scene.particles) out += p.fixed ? "1\n" : "0\n";
  for (std::size_t k = 0; k < m; ++k) out += "0\n";
  out += "VECTORS displacement double\n";
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 d = Displacement(field, k);
    AppendRow(out, {d.x(), d.y(), 0.0});
  }
  for (std::size_t k = 0; k < m; ++k) out += "0 0 0\n";
}

// VTK orders cells vertices first, then lines: the vertices carry zeros.
void AppendVtkCellData(const Scene& scene, const ParticleField& field, std::string& out) {
  const std::size_t n = scene.particles.size();
  const std::vector<double> changes = NormalChanges(field);
  out += "CELL_DATA " + std::to_string(n + field.forces.size()) + '\n';
  const auto append_scalar = [&](const char* name, auto value_of_line) {
    AppendScalarHeader(out, name, "double");
    for (std::size_t k = 0; k < n; ++k) out += "0\n";
    for (std::size_t k = 0; k < field.forces.size(); ++k) AppendRow(out, {value_of_line(k)});
  };
  append_scalar("normal_force", [&](std::size_t k) { return field.forces[k].normal; });
  append_scalar("tangential_force", [&](std::size_t k) { return field.forces[k].tangential; });
  append_scalar("force_change", [&](std::size_t k) { return changes[k]; });
}

const char* Flag(bool value) { return value ? "T" : "F"; }

}  // namespace

void WriteVtk(const Scene& scene, const ParticleField& field, const std::filesystem::path& path) {
  CheckField(scene, field);
  std::string out =
      "# vtk DataFile Version 3.0\nunjam particles and contact forces\nASCII\nDATASET POLYDATA\n";
  AppendVtkGeometry(scene, field, out);
  if (!scene.particles.empty() || !field.forces.empty()) {
    AppendVtkPointData(scene, field, out);
    AppendVtkCellData(scene, field, out);
  }
  WriteFileAtomically(path, out);
}

void WriteExtendedXyz(const Scene& scene, const ParticleField& field,
                      const std::filesystem::path& path) {
  CheckField(scene, field);
  const Periodicity periodicity = scene.cell.periodicity;
  std::string out = std::to_string(scene.particles.size()) + "\nLattice=\"";
  AppendDouble(out, scene.cell.size.x());
  out += " 0 0 0 ";
  AppendDouble(out, scene.cell.size.y());
  out += " 0 0 0 1\" Properties=id:I:1:pos:R:3:radius:R:1:fixed:I:1:displacement:R:3 pbc=\"";
  out += Flag(PeriodicX(periodicity));
  out += ' ';
  out += Flag(PeriodicY(periodicity));
  out += " F\"\n";
  for (std::size_t k = 0; k < scene.particles.size(); ++k) {
    const Particle& p = scene.particles[k];
    const Vec2 d = Displacement(field, k);
    out += std::to_string(k);
    AppendDoubles(out, {p.position.x(), p.position.y(), 0.0, p.radius});
    out += p.fixed ? " 1" : " 0";
    AppendDoubles(out, {d.x(), d.y(), 0.0});
    out += '\n';
  }
  WriteFileAtomically(path, out);
}

}  // namespace unjam
