#pragma once
// Carlson's symmetric elliptic integrals, computed by the duplication theorem with the
// fifth-order series of B. C. Carlson, "Numerical computation of real or complex elliptic
// integrals", Numer. Algorithms 10 (1995) 13-26, doi:10.1007/BF02198293 (also DLMF 19.36).
// They give the exact surface area of a triaxial ellipsoid (DLMF 19.33.1) and the complete
// integral E(k) used for mean projected areas, uniformly in the parameters (no special case
// for spheres or spheroids, unlike the Legendre forms).

namespace settle::body {

/// R_F(x, y, z) = 1/2 int_0^inf dt / sqrt((t+x)(t+y)(t+z)); x, y, z >= 0, at most one zero.
/// Relative accuracy about 1e-15.
double carlson_rf(double x, double y, double z);

/// R_D(x, y, z) = 3/2 int_0^inf dt / ((t+z) sqrt((t+x)(t+y)(t+z))); x, y >= 0 (at most one
/// zero), z > 0. Relative accuracy about 1e-15.
double carlson_rd(double x, double y, double z);

/// R_G(x, y, z), the symmetric integral of the second kind (DLMF 19.16.3); x, y, z >= 0.
/// Evaluated through DLMF 19.21.10 with the middle argument as the distinguished one so that
/// no cancellation occurs.
double carlson_rg(double x, double y, double z);

/// Complete elliptic integral of the second kind E(k) = int_0^{pi/2} sqrt(1 - k^2 sin^2 t) dt,
/// 0 <= k <= 1, as 2 R_G(0, 1 - k^2, 1) (DLMF 19.25.1).
double complete_elliptic_e(double k);

}  // namespace settle::body
