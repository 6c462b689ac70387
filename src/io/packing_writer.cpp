// Writing `.unjam` packings (docs/format.md). Doubles are printed in their shortest exact
// decimal form, so reading the text back gives the same bits.
#include <string>

#include "text_fields.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam {

namespace {

using io_internal::AppendDouble;
using io_internal::AppendDoubles;

void AppendInts(std::string& out, std::initializer_list<long long> values) {
  for (const long long v : values) {
    out += ' ';
    out += std::to_string(v);
  }
}

const char* PeriodicityName(Periodicity p) {
  switch (p) {
    case Periodicity::kX: return "x";
    case Periodicity::kXY: return "xy";
    case Periodicity::kNone: break;
  }
  return "none";
}

void AppendHeaderAndEffects(const Scene& scene, std::string& out) {
  out += "unjam-packing 1\n";
  out += "cell";
  AppendDoubles(out, {scene.cell.size.x(), scene.cell.size.y()});
  out += "\nperiodic ";
  out += PeriodicityName(scene.cell.periodicity);
  out += '\n';
  for (const Wall& w : scene.cell.walls) {
    out += "wall";
    AppendDoubles(out, {w.point.x(), w.point.y(), w.normal.x(), w.normal.y()});
    out += '\n';
  }
  const Effects& effects = scene.effects;
  if (effects.gravity) {
    out += "gravity";
    AppendDoubles(out, {effects.gravity->x(), effects.gravity->y()});
    out += '\n';
  }
  out += "friction";
  AppendDoubles(out, {effects.friction});
  out += '\n';
  if (effects.pressure_bath) {
    const PressureBath& bath = *effects.pressure_bath;
    out += "pressure-bath";
    AppendDoubles(out, {bath.pressure, bath.cell_mass, bath.strain_rate});
    out += '\n';
  }
  for (const PrescribedMotion& m : effects.prescribed_motion) {
    out += "prescribed-motion";
    AppendInts(out, {m.particle});
    AppendDoubles(out, {m.velocity.x(), m.velocity.y(), m.spin});
    out += '\n';
  }
  for (const PrescribedGap& g : effects.prescribed_gaps) {
    out += "prescribed-gap";
    AppendInts(out, {g.i, g.j, g.image[0], g.image[1]});
    AppendDoubles(out, {g.gap});
    out += '\n';
  }
  out += "seed " + std::to_string(scene.seed) + "\n";
  // An empty provenance is simply left out: the reader's default is empty.
  if (!scene.provenance.empty())
    out += "provenance " + io_internal::EscapeText(scene.provenance) + "\n";
}

}  // namespace

std::string FormatPacking(const Scene& scene) {
  std::string out;
  // About 9 numbers of up to 24 characters per particle line.
  out.reserve(512 + 120 * scene.particles.size() + 80 * scene.forces.size());
  AppendHeaderAndEffects(scene, out);
  out += "particles " + std::to_string(scene.particles.size()) + "\n";
  out += "# x y angle vx vy spin radius density fixed\n";
  for (const Particle& p : scene.particles) {
    AppendDouble(out, p.position.x());
    AppendDoubles(out, {p.position.y(), p.angle, p.velocity.x(), p.velocity.y(), p.spin, p.radius,
                        p.density});
    out += p.fixed ? " 1\n" : " 0\n";
  }
  if (!scene.forces.empty()) {
    out += "forces " + std::to_string(scene.forces.size()) + "\n";
    out += "# i j image_x image_y normal tangential (j < 0: wall -1-j)\n";
    for (const ContactForce& f : scene.forces) {
      out += std::to_string(f.i);
      AppendInts(out, {f.j, f.image[0], f.image[1]});
      AppendDoubles(out, {f.normal, f.tangential});
      out += '\n';
    }
  }
  out += "end\n";
  return out;
}

void WritePacking(const Scene& scene, const std::filesystem::path& path) {
  WriteFileAtomically(path, FormatPacking(scene));
}

}  // namespace unjam
