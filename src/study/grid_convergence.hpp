#pragma once
// The observed order of convergence, Richardson's extrapolate and Roache's grid convergence index
// from three grids, by the procedure of Celik, Ghia, Roache, Freitas, Coleman and Raad 2008
// ("Procedure for estimation and reporting of uncertainty due to discretization in CFD
// applications", J. Fluids Eng. 130, 078001, doi:10.1115/1.2960953), which allows unequal
// refinement ratios; the index with the safety factor 1.25 that Roache (1994, J. Fluids Eng. 116,
// 405, doi:10.1115/1.2910291) gives for three or more grids where they confirm the scheme's order
// (2, within 10%), else the safety factor 3 he gives for an order not confirmed, with the observed
// order held within [0.5, 2] (grid_convergence.cpp says why).
#include <optional>

namespace settle::study {

/// A figure on three grids, finest first: h is the cell size (1 / cells per diameter will do).
struct ThreeGrids {
  double h_fine, h_medium, h_coarse;
  double fine, medium, coarse;
};

struct GridConvergence {
  std::optional<double> observed_order;  ///< p; empty when two grids give the same value
  std::optional<double> extrapolated;    ///< Richardson's estimate of the h -> 0 value
  std::optional<double> gci_fine;        ///< relative uncertainty of the fine value (0.01 = 1%)
  bool oscillatory = false;              ///< the differences change sign: p and the GCI are doubtful
  bool order_confirmed = false;          ///< p within 10% of 2 and not oscillatory: gci_fine uses 1.25, else 3
};

/// Throws std::invalid_argument unless h_fine < h_medium < h_coarse.
GridConvergence grid_convergence(const ThreeGrids& grids);

}  // namespace settle::study
