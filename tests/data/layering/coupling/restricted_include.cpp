// Input of the layering check's test of restricted headers (tests/CMakeLists.txt): coupling may use
// lbm and parallel, but not lbm's block exchange protocol, which only parallel includes. Never
// compiled.
#include "lbm/block_exchange.hpp"
#include "lbm/solver.hpp"
#include "parallel/lattice_steps.hpp"
