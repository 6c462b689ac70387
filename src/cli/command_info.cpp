// `unjam info FILE`: what a saved packing holds.
#include <cstdio>

#include "cli_common.hpp"
#include "unjam/analysis/equilibrium.hpp"
#include "unjam/analysis/hanging_grains.hpp"
#include "unjam/contacts/contact.hpp"
#include "unjam/io/packing_file.hpp"

namespace unjam::cli {

namespace {
constexpr double kClosedGap = 1e-9;  // contacts with a gap at most this are counted as closed
}

int RunInfo(const std::string& path, bool json) {
  const Scene scene = ReadPacking(path);
  int fixed = 0;
  for (const Particle& p : scene.particles) fixed += p.fixed ? 1 : 0;
  const std::vector<Contact> closed = DetectContacts(scene, kClosedGap);
  const bool has_forces = !scene.forces.empty();
  const Coordination z = ComputeCoordination(scene, scene.forces);
  const double phi = PackingFraction(scene);
  const std::vector<int> hanging = HangingGrains(scene, closed);
  if (json) {
    nlohmann::json out = {{"file", path},
                          {"particles", scene.particles.size()},
                          {"fixed", fixed},
                          {"cell", {scene.cell.size.x(), scene.cell.size.y()}},
                          {"periodic", PeriodicityName(scene.cell.periodicity)},
                          {"effects", EffectsSummary(scene)},
                          {"contacts", closed.size()},
                          {"packing_fraction", phi},
                          {"stored_forces", scene.forces.size()},
                          {"seed", scene.seed},
                          {"provenance", scene.provenance}};
    out["coordination"] = has_forces ? nlohmann::json(z.z) : nlohmann::json(nullptr);
    out["rattlers"] = has_forces ? nlohmann::json(z.rattlers) : nlohmann::json(nullptr);
    out["hanging_grains"] =
        scene.effects.gravity ? nlohmann::json(hanging) : nlohmann::json(nullptr);
    std::printf("%s\n", out.dump().c_str());
    return kOk;
  }
  std::printf("file              %s\n", path.c_str());
  std::printf("particles         %zu (%d fixed)\n", scene.particles.size(), fixed);
  std::printf("cell              %.6g x %.6g, periodic %s, %zu walls\n", scene.cell.size.x(),
              scene.cell.size.y(), PeriodicityName(scene.cell.periodicity),
              scene.cell.walls.size());
  std::printf("effects           %s\n", EffectsSummary(scene).c_str());
  std::printf("packing fraction  %.6f\n", phi);
  std::printf("contacts          %zu with gap <= %g\n", closed.size(), kClosedGap);
  if (has_forces) {
    std::printf("stored forces     %zu (%d force-carrying)\n", scene.forces.size(),
                z.force_carrying_contacts);
    std::printf("coordination z    %.4f (rattlers excluded: %d)\n", z.z, z.rattlers);
  } else {
    std::printf("stored forces     none (run `unjam solve` to compute them)\n");
  }
  if (scene.effects.gravity) {
    std::printf("hanging grains    %zu", hanging.size());
    for (std::size_t k = 0; k < hanging.size() && k < 20; ++k)
      std::printf("%s%d", k == 0 ? ": " : " ", hanging[k]);
    std::printf("%s\n", hanging.size() > 20 ? " ..." : "");
  }
  std::printf("seed              %llu\n", static_cast<unsigned long long>(scene.seed));
  if (!scene.provenance.empty()) std::printf("provenance        %s\n", scene.provenance.c_str());
  return kOk;
}

}  // namespace unjam::cli
