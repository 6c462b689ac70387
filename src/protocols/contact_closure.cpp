#include "unjam/protocols/contact_closure.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/SparseCore>

#include "unjam/contacts/contact.hpp"
#include "unjam/indeterminacy/least_norm.hpp"

namespace unjam {

namespace {

Contact Geometry(const Scene& scene, const ContactKey& key) {
  if (IsWallIndex(key.j)) return MakeWallContact(scene, key.i, JToWallIndex(key.j));
  return MakeContact(scene, key.i, key.j, key.image);
}

// Columns of G: (x, y) of every movable particle, then ε if the cell is a degree of freedom.
std::vector<int> NumberColumns(const Scene& scene, int& columns) {
  std::vector<int> column(scene.particles.size(), -1);
  const std::vector<char> movable = MovableParticles(scene);
  columns = 0;
  for (std::size_t i = 0; i < scene.particles.size(); ++i) {
    if (!movable[i]) continue;
    column[i] = columns;
    columns += 2;
  }
  return column;
}

double MaxGap(const Scene& scene, const std::vector<ContactKey>& keys) {
  double worst = 0.0;
  for (const ContactKey& key : keys) worst = std::max(worst, std::abs(Geometry(scene, key).gap));
  return worst;
}

}  // namespace

ClosureReport CloseContacts(Scene& scene, const std::vector<ContactKey>& keys,
                            const ClosureOptions& o) {
  ClosureReport report;
  int columns = 0;
  const std::vector<int> column = NumberColumns(scene, columns);
  const bool cell_moves = scene.effects.pressure_bath.has_value();
  const int cell_column = columns;
  if (cell_moves) ++columns;
  const std::vector<Particle> start = scene.particles;
  report.max_gap = MaxGap(scene, keys);
  // Positions are not wrapped until the end, so that every contact keeps its image.
  while (report.max_gap > o.tolerance && report.iterations < o.iterations) {
    ++report.iterations;
    std::vector<Eigen::Triplet<double>> t;
    Eigen::VectorXd gaps(keys.size());
    for (int k = 0; k < static_cast<int>(keys.size()); ++k) {
      const Contact c = Geometry(scene, keys[k]);
      gaps[k] = c.gap;
      for (auto [p, sign] : {std::pair{c.i, -1.0}, std::pair{c.WithWall() ? -1 : c.j, 1.0}}) {
        if (p < 0 || column[p] < 0) continue;
        t.emplace_back(k, column[p], sign * c.normal.x());
        t.emplace_back(k, column[p] + 1, sign * c.normal.y());
      }
      if (cell_moves && !c.WithWall())
        t.emplace_back(k, cell_column, c.center_to_center.dot(c.normal));
    }
    Eigen::SparseMatrix<double> g(static_cast<int>(keys.size()), columns);
    g.setFromTriplets(t.begin(), t.end());
    const LeastNormSolver least_norm(g, 1e-14);
    if (!least_norm.ok()) break;
    const Eigen::VectorXd delta = least_norm.Solve(-gaps);
    if (!delta.allFinite()) break;
    const double strain = cell_moves ? delta[cell_column] : 0.0;
    for (std::size_t i = 0; i < scene.particles.size(); ++i) {
      Particle& p = scene.particles[i];
      if (p.fixed) continue;
      p.position *= 1.0 + strain;
      if (column[i] >= 0) p.position += Vec2(delta[column[i]], delta[column[i] + 1]);
    }
    scene.cell.size *= 1.0 + strain;
    report.max_gap = MaxGap(scene, keys);
  }
  for (std::size_t i = 0; i < start.size(); ++i) {
    report.max_displacement =
        std::max(report.max_displacement, (scene.particles[i].position - start[i].position).norm());
  }
  WrapPositions(scene);
  report.closed = report.max_gap <= o.tolerance;
  return report;
}

}  // namespace unjam
