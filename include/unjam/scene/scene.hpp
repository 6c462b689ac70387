// The scene: particles, the cell that holds them, and the effects the scene declares.
//
// A scene is plain data. Every effect is optional and the engine composes only what is
// declared: no gravity means no gravity work, zero friction means one unknown per contact
// and no rotational degrees of freedom, no pressure bath means a fixed cell.
//
// Units: the unit of length is the largest disk radius, density 1 by default, so a disk of
// radius r has mass density·π·r² and moment of inertia m·r²/2.
#pragma once

#include <array>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace unjam {

using Vec2 = Eigen::Vector2d;

// 2D cross product (z component) and the perpendicular t = perp(n) = (-n_y, n_x).
inline double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
inline Vec2 Perp(const Vec2& n) { return Vec2(-n.y(), n.x()); }

struct Particle {
  Vec2 position = Vec2::Zero();
  double angle = 0.0;  // orientation, radians
  Vec2 velocity = Vec2::Zero();
  double spin = 0.0;  // angular velocity, radians per unit time
  double radius = 1.0;
  double density = 1.0;
  bool fixed = false;  // a fixed disk never moves (rough bed, obstacle)

  double Mass() const { return density * std::numbers::pi * radius * radius; }
  double Inertia() const { return 0.5 * Mass() * radius * radius; }
};

enum class Periodicity { kNone, kX, kXY };

inline bool PeriodicX(Periodicity p) { return p != Periodicity::kNone; }
inline bool PeriodicY(Periodicity p) { return p == Periodicity::kXY; }

// A straight, fixed, infinite wall: the half-plane (x − point)·normal ≥ 0 is the inside.
struct Wall {
  Vec2 point = Vec2::Zero();
  Vec2 normal = Vec2(0.0, 1.0);  // unit, pointing into the domain
};

// The simulation cell [0, Lx) × [0, Ly). Along a periodic axis positions are wrapped into
// the cell and contacts are found across the boundary (minimum image). Along a
// non-periodic axis the size is only descriptive.
struct Cell {
  Vec2 size = Vec2(1.0, 1.0);
  Periodicity periodicity = Periodicity::kNone;
  std::vector<Wall> walls;
};

// Disks in the plane: the D of the virial pressure and of the barostat's cell mass M_λ D V.
inline constexpr double kDimension = 2.0;

// Constant external pressure on a fully periodic cell whose size is a degree of freedom
// (Andersen-type barostat): M_λ dλ/dt = P_in − P_ext with λ = L̇/L. See docs/method.md.
struct PressureBath {
  double pressure = 1.0;     // P_ext
  double cell_mass = 100.0;  // M_λ, density × length² units
  double strain_rate = 0.0;  // λ, the cell's state
};

// A particle whose velocity is imposed during the step (infinite mass for the solver).
struct PrescribedMotion {
  int particle = -1;
  Vec2 velocity = Vec2::Zero();
  double spin = 0.0;
};

// A contact held at a given gap at the end of the step: a bilateral constraint whose normal
// impulse may take either sign and which carries no friction (contact opening).
struct PrescribedGap {
  int i = -1;
  int j = -1;
  std::array<int, 2> image = {0, 0};  // periodic image of j, in cell lengths
  double gap = 0.0;
};

struct Effects {
  std::optional<Vec2> gravity;  // acceleration
  double friction = 0.0;        // Coulomb μ, particle–particle and particle–fixed
  std::optional<PressureBath> pressure_bath;
  std::vector<PrescribedMotion> prescribed_motion;
  std::vector<PrescribedGap> prescribed_gaps;

  bool Frictional() const { return friction > 0.0; }
};

// Static contact force between particle i and particle j (image of j), or a wall
// (j = -1 − wall index). Normal from i to j; tangent Perp(normal). Forces act on j, and the
// opposite on i.
struct ContactForce {
  int i = -1;
  int j = -1;
  std::array<int, 2> image = {0, 0};
  double normal = 0.0;
  double tangential = 0.0;
};

struct Scene {
  Cell cell;
  Effects effects;
  std::vector<Particle> particles;
  std::uint64_t seed = 0;
  std::string provenance;            // how the scene was made (command line, tool version)
  std::vector<ContactForce> forces;  // optional: static contact forces of this state
};

// Index encoding of walls on the j side of a contact.
inline bool IsWallIndex(int j) { return j < 0; }
inline int WallIndexToJ(int wall) { return -1 - wall; }
inline int JToWallIndex(int j) { return -1 - j; }

double MaxRadius(const Scene& scene);
// Per particle: 1 if it moves under the contact forces (neither fixed nor given a
// prescribed motion), 0 otherwise.
std::vector<char> MovableParticles(const Scene& scene);
// Disk area (free and fixed) over the cell area; when y is not periodic (a pile), over the
// width times the height spanned by the disks, bottom of the lowest to top of the highest.
double PackingFraction(const Scene& scene);
// Wraps positions into the cell along periodic axes.
void WrapPositions(Scene& scene);
// The barostat's inertia for the strain rate λ, M_λ D V (docs/method.md); the scene must
// have a pressure bath.
double CellInertia(const Scene& scene);
// The smallest normal force that counts as carried: 1e-10 of the mean positive normal force
// (the static solves' relative tolerance). Static solves leave round-off forces, 1e-18 of
// the mean and below, on contacts that carry nothing; counting them would hide rattlers.
double CarryingThreshold(const std::vector<double>& normal_forces);
// The same over stored forces.
double CarryingThreshold(const std::vector<ContactForce>& forces);
// The stored forces that carry load (above CarryingThreshold) between two particles (not
// walls, not two fixed disks), in the order the scene stores them: the numbering of
// `--contact K` and `--contacts K`.
std::vector<ContactForce> ForceCarryingPairs(const Scene& scene);
// Zero velocities, spins and the cell strain rate: the state a static solve or a
// perturbation starts from.
void BringToRest(Scene& scene);
// The vector v at its shortest periodic image (separations, displacements from a point).
Vec2 MinimumImage(const Cell& cell, Vec2 v);

}  // namespace unjam
