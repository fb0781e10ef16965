// The wall rules as coefficients of one link (lbm/wall_rules.hpp), checked on q alone. The model
// the interpolations are built on: along the link, s = 0 at the fluid cell x, s = -1 at x - c_i,
// the wall at s = q. The post-collision populations f*_i leaving towards the wall are a profile
// g(s); the populations coming back are its image in the wall, h(s) = g(2q - 1 - s) + W, so that
// f*_opp(i)(x) (which streams to s = -1) is g(2q) + W and f*_opp(i)(x - c_i) is g(2q + 1) + W.
// The exact returning population at x is h(0) = g(2q - 1) + W. Bouzidi's linear and Ginzburg's
// central linear rule must return it for every linear g, the quadratic rule for every quadratic g.
//
// Tolerances: every value below is of order one or less and every coefficient below 2 in size, so
// a rule's six products and their sum carry a round-off of a few units of 1e-16 of a sum of size
// below 10; 1e-13 leaves a margin of ten or more, while a wrong coefficient misses by a fraction of
// the profile's slope (the controls below see misses of 1e-2 and more).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "lbm/collision.hpp"
#include "lbm/lattice.hpp"
#include "lbm/wall_rules.hpp"

namespace test_wall_rules {

using namespace settle::lbm;

constexpr double kRoundOff = 1e-13;

// Fractions across (0, 1], close to both sides of 1/2 (where Bouzidi's rules switch branch).
std::vector<double> fractions() {
  std::vector<double> q{1e-3, 0.4999999, 0.5, 0.5000001, 1.0};
  for (int k = 1; k < 20; ++k) q.push_back(0.05 * k);
  return q;
}

// The returning population f_opp(i)(x) a rule's coefficients give for profile g and wall term W.
double returned(const WallCoefficients& k, const std::function<double(double)>& g, double q, double wall) {
  const double f_i = g(0.0), f_i_behind = g(-1.0), f_i_behind2 = g(-2.0);
  const double f_opp = g(2.0 * q) + wall, f_opp_behind = g(2.0 * q + 1.0) + wall;
  return k.a * f_i + k.b * f_i_behind + k.c * f_opp + k.b2 * f_i_behind2 + k.c2 * f_opp_behind + k.wall_term(wall);
}
double exact(const std::function<double(double)>& g, double q, double wall) { return g(2.0 * q - 1.0) + wall; }

struct Profile {
  double constant, slope, curvature, wall;
  double operator()(double s) const { return constant + slope * s + curvature * s * s; }
};
const std::vector<Profile> kLinearProfiles = {{0.3, -0.2, 0.0, 0.0}, {-0.05, 0.7, 0.0, 0.04}, {1.0, 1.0, 0.0, -0.1}};
const std::vector<Profile> kQuadraticProfiles = {{0.3, -0.2, 0.25, 0.0}, {-0.05, 0.7, -0.6, 0.04}};

TEST(LbmWallRules, BouzidiAndCentralLinearRulesReturnALinearProfileExactly) {
  for (const WallRule rule : {WallRule::bouzidi, WallRule::central_linear, WallRule::quadratic}) {
    double worst = 0.0;
    for (const double q : fractions()) {
      const WallCoefficients k = wall_coefficients(rule, q, true, true);
      for (const Profile& g : kLinearProfiles) {
        const double miss = returned(k, g, q, g.wall) - exact(g, q, g.wall);
        EXPECT_NEAR(miss, 0.0, kRoundOff) << to_string(rule) << " q = " << q;
        worst = std::max(worst, std::abs(miss));
      }
    }
    std::printf("%s on linear profiles: largest miss %.1e\n", to_string(rule).c_str(), worst);
  }
}

TEST(LbmWallRules, TheQuadraticRuleReturnsAQuadraticProfileExactly) {
  double worst = 0.0;
  for (const double q : fractions()) {
    const WallCoefficients k = wall_coefficients(WallRule::quadratic, q, true, true);
    EXPECT_TRUE(k.reads_third);
    for (const Profile& g : kQuadraticProfiles) {
      const double miss = returned(k, g, q, g.wall) - exact(g, q, g.wall);
      EXPECT_NEAR(miss, 0.0, kRoundOff) << "q = " << q;
      worst = std::max(worst, std::abs(miss));
    }
  }
  std::printf("quadratic on quadratic profiles: largest miss %.1e\n", worst);
}

// Controls: the comparison sees a rule of lower order. Half-way bounce-back returns g(0) + W, off
// by slope (1 - 2q) on a linear profile; Bouzidi's linear rule on g(s) = s^2 is off by the closed
// form of linear interpolation, 2q (1 - 2q) for q < 1/2 and 2q - 1 for q >= 1/2.
TEST(LbmWallRules, LowerOrderRulesMissByTheirClosedFormErrors) {
  for (const double q : fractions()) {
    const Profile linear = kLinearProfiles[1];
    EXPECT_NEAR(returned(wall_coefficients(WallRule::halfway, q, true, true), linear, q, linear.wall) -
                    exact(linear, q, linear.wall),
                linear.slope * (1.0 - 2.0 * q), kRoundOff)
        << "q = " << q;
    const Profile square{0.0, 0.0, 1.0, 0.0};
    const double miss = q < 0.5 ? 2.0 * q * (1.0 - 2.0 * q) : 2.0 * q - 1.0;
    EXPECT_NEAR(returned(wall_coefficients(WallRule::bouzidi, q, true, true), square, q, 0.0) - exact(square, q, 0.0),
                miss, kRoundOff)
        << "q = " << q;
  }
}

// At q = 1/2 the wall sits where half-way bounce-back puts it: every rule is that rule there, and
// Bouzidi's two branches meet (continuity from below, where the q < 1/2 branch applies).
TEST(LbmWallRules, EveryRuleIsHalfWayBounceBackAtQHalf) {
  for (const WallRule rule : {WallRule::bouzidi, WallRule::quadratic, WallRule::central_linear, WallRule::halfway}) {
    const WallCoefficients k = wall_coefficients(rule, 0.5, true, true);
    EXPECT_EQ(k.a, 1.0) << to_string(rule);
    EXPECT_EQ(k.b, 0.0) << to_string(rule);
    EXPECT_EQ(k.c, 0.0) << to_string(rule);
    EXPECT_EQ(k.b2, 0.0) << to_string(rule);
    EXPECT_EQ(k.c2, 0.0) << to_string(rule);
    EXPECT_EQ(k.wall_factor(), 1.0) << to_string(rule);
    // Just below 1/2 the coefficients differ from those at 1/2 by at most 4 (1/2 - q) (the
    // quadratic rule's b = (1 - 2q)(1 + 2q); the derivatives of all others are smaller there),
    // here 4e-9, plus the round-off of 1 - 2q (1e-16).
    const double below = 0.5 - 1e-9;
    const WallCoefficients b = wall_coefficients(rule, below, true, true);
    for (const double d : {b.a - 1.0, b.b, b.c, b.b2, b.c2, b.wall_factor() - 1.0}) {
      EXPECT_LE(std::abs(d), 4.01e-9) << to_string(rule);
    }
  }
}

// A fluid moving with the wall is a fixed point of every rule: with every f* at the equilibrium of
// the wall's velocity u_w, f*_opp(i) = f*_i - 6 w_i c_i.u_w = f*_i + W exactly for the
// equilibrium's linear part (its quadratic part is even in c_i), so the rule must return f*_i + W.
// That holds for every q exactly when the coefficients of the populations sum to 1 (a fluid at rest
// keeps its mass) and c + c2 + the wall factor sum to 1: checked here on both lattices, with the
// fallbacks where the cells behind x are not fluid.
template <Lattice L>
void expect_moving_fluid_returned() {
  const Eigen::Vector3d u_w(0.03, -0.05, 0.02);
  for (const WallRule rule : {WallRule::bouzidi, WallRule::quadratic, WallRule::central_linear, WallRule::halfway}) {
    for (const double q : fractions()) {
      for (const bool second : {true, false}) {
        const WallCoefficients k = wall_coefficients(rule, q, second, second);
        // Five terms below 2.5 in size: a few units of 1e-16 of round-off.
        EXPECT_NEAR(k.a + k.b + k.c + k.b2 + k.c2, 1.0, 4e-15) << to_string(rule) << " q = " << q;
        EXPECT_NEAR(k.c + k.c2 + k.wall_factor(), 1.0, 4e-15) << to_string(rule) << " q = " << q;
        for (int i = 1; i < L::Q; ++i) {
          const double f_i = shifted_equilibrium<L>(i, 0.0, 1.0, u_w.x(), u_w.y(), u_w.z());
          const double f_opp = shifted_equilibrium<L>(opposite(i), 0.0, 1.0, u_w.x(), u_w.y(), u_w.z());
          const double wall = moving_wall_term(L::set.w[i], L::set.c[i], u_w);
          const double back =
              (k.a + k.b + k.b2) * f_i + (k.c + k.c2) * f_opp + k.wall_term(wall);  // every node at equilibrium
          // Populations below 0.2 in size: round-off of a few units of 1e-17.
          EXPECT_NEAR(back, f_opp, 1e-15) << to_string(rule) << " q = " << q << " direction " << i;
        }
      }
    }
  }
}

TEST(LbmWallRules, AFluidMovingWithTheWallIsReturnedUnchanged) {
  expect_moving_fluid_returned<D3Q19>();
  expect_moving_fluid_returned<D3Q27>();
}

// The factor of W as each paper writes it: 1 for half-way bounce-back and for q < 1/2, 1 / 2q for
// Bouzidi's linear and 1 / (q (2q + 1)) for his quadratic rule at q >= 1/2, 2 / (1 + 2q) for the
// central linear rule (Ginzburg et al.'s Table 4).
TEST(LbmWallRules, TheMovingWallFactorIsThePapersClosedForm) {
  for (const double q : fractions()) {
    const auto factor = [&](WallRule rule) { return wall_coefficients(rule, q, true, true).wall_factor(); };
    EXPECT_EQ(factor(WallRule::halfway), 1.0);
    EXPECT_NEAR(factor(WallRule::bouzidi), q < 0.5 ? 1.0 : 1.0 / (2.0 * q), 1e-15) << q;
    EXPECT_NEAR(factor(WallRule::quadratic), q < 0.5 ? 1.0 : 1.0 / (q * (2.0 * q + 1.0)), 1e-15) << q;
    EXPECT_NEAR(factor(WallRule::central_linear), 2.0 / (1.0 + 2.0 * q), 1e-15) << q;
  }
}

// Where the points a rule reads are not fluid it falls back (docs/lbm.md, "Walls inside the grid").
TEST(LbmWallRules, WithoutTheCellsBehindTheRulesFallBack) {
  const WallCoefficients halfway = wall_coefficients(WallRule::halfway, 0.3, true, true);
  const auto same = [](const WallCoefficients& x, const WallCoefficients& y) {
    return x.a == y.a && x.b == y.b && x.c == y.c && x.b2 == y.b2 && x.c2 == y.c2 &&
           x.wall_factor() == y.wall_factor() && x.reads_third == y.reads_third;
  };
  for (const double q : fractions()) {
    // Bouzidi's rules below 1/2 lean on x - c_i; above it they read only x's populations.
    const WallCoefficients linear = wall_coefficients(WallRule::bouzidi, q, false, false);
    EXPECT_TRUE(q < 0.5 ? same(linear, halfway) : same(linear, wall_coefficients(WallRule::bouzidi, q, true, true)));
    EXPECT_TRUE(same(wall_coefficients(WallRule::quadratic, q, false, false), linear)) << q;
    // Without x - 2 c_i the quadratic rule is the linear one.
    EXPECT_TRUE(same(wall_coefficients(WallRule::quadratic, q, true, false),
                     wall_coefficients(WallRule::bouzidi, q, true, true)))
        << q;
    // The central rule reads x - c_i for every q.
    EXPECT_TRUE(same(wall_coefficients(WallRule::central_linear, q, false, false), halfway)) << q;
    EXPECT_FALSE(wall_coefficients(WallRule::central_linear, q, true, true).reads_third);
  }
}

}  // namespace test_wall_rules
