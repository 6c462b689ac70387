// What the files of a perturbation share (src/protocols/perturbation*.cpp): deciding a
// perturbation before solving (perturbation_decide.cpp), choosing and running its solve
// (perturbation_backend.cpp, perturbation_solve.cpp) and measuring the answer
// (perturbation_measure.cpp). Not part of the library's interface.
#pragma once

#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "perturbation_rate.hpp"
#include "unjam/protocols/perturbation.hpp"
#include "unjam/protocols/static_solve.hpp"

namespace unjam {

struct RateBaseSlot {
  std::once_flag once;
  RateBase rate;
};

namespace perturbation_internal {

using Clock = std::chrono::steady_clock;

// The small-gap regime (check_linearity). Tolerances: the displacements are resolved to 1 %
// of their size (response_tolerance), so 5 % leaves room for two such solves; F_crit of a
// linear response moves only by its inertial part, O(ξ) (below 3e-5 of F_cont measured).
constexpr double kLinearityGapFactor = 10.0;
constexpr double kLinearityMisfit = 0.05;
constexpr double kLinearityForceChange = 1e-3;  // of the mean contact force

// perturbation.cpp
Scene PerturbedScene(const PerturbationBase& base, const PerturbationTarget& t,
                     const PerturbationOptions& o);
void CheckTarget(const PerturbationBase& base, const PerturbationTarget& t);

// perturbation_backend.cpp: the options of the one step of a perturbation.
StaticSolveOptions StepOptions(const PerturbationBase& base, const PerturbationOptions& options);

// perturbation_measure.cpp
double EffectiveWeight(int p, const std::vector<Contact>& contacts,
                       const std::vector<Eigen::Vector2d>& forces);
void SetOriginAndReference(const PerturbationBase& base, const PerturbationTarget& t,
                           PerturbationResult& r);
void Measure(const PerturbationBase& base, const PerturbationOptions& options,
             const StaticSolveOptions& solve, const StaticSolution& s, PerturbationResult& r);
void JudgeLinearity(const PerturbationBase& base, const PerturbationResult& scaled,
                    PerturbationResult& r);

// perturbation_decide.cpp
PerturbationResult DecidedWithoutSolving(const PerturbationBase& base,
                                         const std::string& decided_by, const std::string& why,
                                         PerturbationResult r, Clock::time_point start);
PerturbationResult Blocked(const PerturbationBase& base, const std::string& decided_by,
                           const std::string& why, PerturbationResult r, Clock::time_point start);

}  // namespace perturbation_internal
}  // namespace unjam
