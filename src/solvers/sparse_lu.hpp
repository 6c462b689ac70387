// UMFPACK's fill-reducing order for the sparse step systems that newton and the pattern solve
// factorise ([M, −HᵀE; H, ·]: grains and contacts, a graph as planar as the packing).
#pragma once

#include <Eigen/SparseCore>
#include <Eigen/UmfPackSupport>

namespace unjam::solvers_internal {

// METIS (nested dissection) suits a packing's planar contact graph: on a square cell its
// factors fill in several times less than with UMFPACK's default (AMD/COLAMD), but its
// ordering costs more. Newton analyses once per solve and factorises at every iteration:
// METIS from 10 000 rows (1.6× faster at N = 3000). The pattern solve analyses every system
// anew: METIS from 15 000 rows (1.9× faster at N = 3000, 2–2.7× at N = 8000; 1.4× slower on the
// 1600-disk pile, 11 000 rows, which AMD orders well). Below a threshold the default stays,
// and with it the pivot order and the bits of every smaller solve (docs/performance.md).
constexpr Eigen::Index kNewtonMetisRows = 10000;
constexpr Eigen::Index kPatternMetisRows = 15000;

template <class Lu>
void ChooseOrdering(Lu& lu, Eigen::Index rows, Eigen::Index metis_rows) {
  if (rows >= metis_rows) lu.umfpackControl()(UMFPACK_ORDERING) = UMFPACK_ORDERING_METIS;
}

}  // namespace unjam::solvers_internal
