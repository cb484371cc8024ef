// The Δt (and h) part of u_num, Eça & Hoekstra's least-squares procedure
// (lib/reference/uncertainty.hpp): it covers the Δt → 0 limit in noisy synthetic refinement
// sequences like ours (steps of the size of the start spread), it reads pure noise as noise,
// and on clean sequences it reduces to the grid convergence index with the exact order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "reference/uncertainty.hpp"

namespace rbc {
namespace {

struct Draws {
  double covered = 0;     // fraction with |f_reported − f0| ≤ u
  double read_noise = 0;  // fraction read as noise (no order observed)
  double median_u = 0;    // the median estimate: coverage alone would pass u = ∞
};

// f_k = f0 + a Δt_0 2^k + ε_k at Δt_k = Δt_0 2^k (k = 0 the finest), ε_k Gaussian with standard
// deviation s, drawn `draws` times from a fixed seed; the estimate is asked with s as the
// noise (pass_noise) or without it (NaN).
Draws draw(int levels, double a_dt0, double s, int reported, bool pass_noise, int draws = 1000) {
  std::mt19937_64 rng(2455);
  std::normal_distribution<double> scatter(0.0, s);
  const double f0 = 9.1;
  Draws d;
  std::vector<double> us;
  for (int i = 0; i < draws; ++i) {
    std::vector<double> f;
    for (int k = 0; k < levels; ++k) f.push_back(f0 + a_dt0 * std::ldexp(1.0, k) + scatter(rng));
    const RefinementUncertainty u = grid_convergence_index(f, 2.0, 1.0, reported, pass_noise ? s : NAN);
    if (std::abs(f[reported] - f0) <= u.u) d.covered += 1.0 / draws;
    if (u.fit == RefinementFit::Noise && !std::isfinite(u.observed_order)) d.read_noise += 1.0 / draws;
    us.push_back(u.u);
  }
  std::nth_element(us.begin(), us.begin() + us.size() / 2, us.end());
  d.median_u = us[us.size() / 2];
  return d;
}

std::string name(int levels, double s, int reported) {
  return std::to_string(levels) + " levels, s " + std::to_string(s) + ", reported level " + std::to_string(reported);
}

TEST(UncertaintyEstimator, CoversTheLimitInNinetyPercentOfNoisyFirstOrderSequencesGivenTheirNoise) {
  // With the start spread s passed as the noise, u covers f0 in at least 90 % of 1,000 draws of
  // f0 + 0.04·2^k + ε (steps of the size of s = 0.023 as in our Δt runs, and a cleaner
  // s = 0.002), for 3 and 4 levels, at the finest level and the next (measured 0.985 to 1.0).
  for (int levels : {3, 4})
    for (double s : {0.023, 0.002})
      for (int reported : {0, 1}) EXPECT_GE(draw(levels, 0.04, s, reported, true).covered, 0.90) << name(levels, s, reported);
}

TEST(UncertaintyEstimator, IsSharpTheMedianEstimateStaysWithinThreeTimesTheTrueErrorPlusTwiceTheNoise) {
  // Coverage alone is met by u = ∞: the median u stays below 3 (|a Δt_k| + 2 s), the reported
  // level's true first-order error and the scatter at 95 %, in every case of the coverage test.
  for (int levels : {3, 4})
    for (double s : {0.023, 0.002})
      for (int reported : {0, 1}) {
        const double bound = 3 * (0.04 * std::ldexp(1.0, reported) + 2 * s);
        EXPECT_LE(draw(levels, 0.04, s, reported, true).median_u, bound) << name(levels, s, reported);
      }
}

TEST(UncertaintyEstimator, CoversTheLimitInNinetyPercentOfCleanerSequencesWithoutTheirNoise) {
  // Without the noise (NaN: the paper's procedure alone) u covers f0 in at least 90 % when the
  // steps are well above the scatter (s = 0.002; measured 1.0); with steps of the
  // scatter's size (s = 0.023) three levels cannot be told from convergence (measured 0.71 for
  // the finest of 3 levels, 0.88 of 4), and passing s never covers less.
  for (int levels : {3, 4})
    for (int reported : {0, 1}) {
      EXPECT_GE(draw(levels, 0.04, 0.002, reported, false).covered, 0.90) << name(levels, 0.002, reported);
      const double with = draw(levels, 0.04, 0.023, reported, true).covered, without = draw(levels, 0.04, 0.023, reported, false).covered;
      EXPECT_GE(with, without) << name(levels, 0.023, reported);
      RecordProperty("coverage without s, " + name(levels, 0.023, reported), std::to_string(without));
    }
}

TEST(UncertaintyEstimator, NoiseOnlySequencesAreReadAsNoiseAndStillCovered) {
  // f_k = f0 + ε_k (no Δt dependence) with s passed: at least 90 % of the draws are read as noise
  // with no observed order (the slope test's 95 %; measured 0.945 to 0.956), and u still covers
  // f0 in at least 90 % (measured 0.98 to 1.0).
  for (int levels : {3, 4, 5})
    for (int reported : {0, 1}) {
      const Draws d = draw(levels, 0.0, 0.023, reported, true);
      EXPECT_GE(d.read_noise, 0.90) << name(levels, 0.023, reported);
      EXPECT_GE(d.covered, 0.90) << name(levels, 0.023, reported);
    }
}

TEST(UncertaintyEstimator, CleanFirstOrderSequencesGiveOrderOneFsOneQuarterAndTheirLimit) {
  // f = 3 + 0.5 Δt at Δt = 1, 2, 4 (and 0.5 .. 4): observed order 1, F_s 1.25, limit 3, and
  // U = 1.25 times the level's distance to the limit (the GCI: covers it by a quarter).
  for (const std::vector<double>& f : {std::vector<double>{3.5, 4.0, 5.0}, std::vector<double>{3.25, 3.5, 4.0, 5.0}})
    for (int reported : {0, 1}) {
      const RefinementUncertainty u = grid_convergence_index(f, 2, 1, reported);
      EXPECT_EQ(u.levels, static_cast<int>(f.size()));
      EXPECT_EQ(u.fit, RefinementFit::ObservedOrder);
      EXPECT_NEAR(u.observed_order, 1.0, 1e-9);
      EXPECT_DOUBLE_EQ(u.safety_factor, 1.25);
      EXPECT_NEAR(u.extrapolated, 3.0, 1e-9);
      EXPECT_NEAR(u.fit_sigma, 0.0, 1e-9);
      const double error = f[reported] - 3.0;
      EXPECT_GE(u.u, error);
      EXPECT_NEAR(u.u, 1.25 * error, 1e-9);
      EXPECT_FALSE(u.noise_dominated);
    }
  // With a small noise given the order is still observed and U gains s (σ* = max(σ, s) = s).
  const RefinementUncertainty u = grid_convergence_index({3.5, 4.0, 5.0}, 2, 1, 0, 0.001);
  EXPECT_NEAR(u.observed_order, 1.0, 1e-9);
  EXPECT_NEAR(u.u, 1.25 * 0.5 + 0.001, 1e-9);
}

TEST(UncertaintyEstimator, CleanSecondOrderSequenceInASecondOrderUseGivesOrderTwo) {
  // f = 3 + 0.5 h² at h = 1, 2, 4 (and 8) with formal order 2: observed order 2, F_s 1.25 (the
  // paper's own thresholds 0.5 .. 2.1), limit 3, U = 1.25 · 0.5 at the finest.
  for (const std::vector<double>& f : {std::vector<double>{3.5, 5.0, 11.0}, std::vector<double>{3.5, 5.0, 11.0, 35.0}}) {
    const RefinementUncertainty u = grid_convergence_index(f, 2, 2);
    EXPECT_NEAR(u.observed_order, 2.0, 1e-9);
    EXPECT_DOUBLE_EQ(u.safety_factor, 1.25);
    EXPECT_NEAR(u.extrapolated, 3.0, 1e-9);
    EXPECT_NEAR(u.u, 0.625, 1e-9);
  }
}

TEST(UncertaintyEstimator, TwoLevelsWithinTwoRootTwoOfTheNoiseAreNoise) {
  // Two levels whose difference is within 2√2 s are noise: U = 2 s + (|e| + 2√2 s) (the largest
  // first-order error at Δt_0: slope |e|/(2 − 1) plus two standard errors √2 s); beyond it the
  // GCI with the formal order and F_s 3, plus 2 s (the scatter at 95 %).
  const double s = 0.023;
  RefinementUncertainty u = grid_convergence_index({9.10, 9.16}, 2, 1, 0, s);
  EXPECT_EQ(u.fit, RefinementFit::Noise);
  EXPECT_FALSE(std::isfinite(u.observed_order));
  EXPECT_NEAR(u.u, 2 * s + 0.06 + 2 * std::sqrt(2.0) * s, 1e-12);
  EXPECT_NE(u.describe().find("noise: no convergence observed"), std::string::npos) << u.describe();
  u = grid_convergence_index({9.10, 9.17}, 2, 1, 0, s);
  EXPECT_EQ(u.fit, RefinementFit::TwoLevels);
  EXPECT_NEAR(u.u, 3 * 0.07 + 2 * s, 1e-12);
  EXPECT_THROW(grid_convergence_index({9.10, 9.17}, 2, 1, 0, -s), std::invalid_argument);
}

TEST(UncertaintyEstimator, DescribeNamesTheOrderTheFitsSigmaAndTheSafetyFactor) {
  // A reader sees "p = …, fit σ …, … (Fs …)" for a converging sequence.
  RefinementUncertainty u = grid_convergence_index({3.5, 4.0, 5.0}, 2, 1);
  u.label = "dt 1/2/4 us";
  // (then Richardson's change from the finest, its U here round-off: the fit's limit is 3 too)
  EXPECT_EQ(u.describe(3).rfind("dt 1/2/4 us: p = 1, fit σ 0, U 0.625 (Fs 1.25) [Richardson: the limit -0.5 from the finest ± ", 0), 0u)
      << u.describe(3);
}

TEST(UncertaintyEstimator, RichardsonExtrapolatesInTheAsymptoticRangeWithItsOwnU) {
  // φ(Δt) = 1 + Δt + 0.01 Δt² at Δt = 1, 2, 4 (first order with a small second-order part):
  // φ_R = 2 φ(1) − φ(2) = 0.98, from one level coarser 2 φ(2) − φ(4) = 0.92, U_R = 1.25 × 0.06;
  // the limit 1 lies within φ_R ± U_R.
  auto phi = [](double dt) { return 1 + dt + 0.01 * dt * dt; };
  const RefinementUncertainty u = grid_convergence_index({phi(1), phi(2), phi(4)}, 2, 1);
  const auto R = richardson(u);
  ASSERT_TRUE(R.has_value()) << u.describe();
  EXPECT_NEAR(R->value, 0.98, 1e-12);
  EXPECT_NEAR(R->u, 1.25 * 0.06, 1e-12);
  EXPECT_LE(std::abs(R->value - 1.0), R->u);
  // Two levels: the value, no U of its own.
  const auto two = richardson(grid_convergence_index({phi(1), phi(2)}, 2, 1));
  ASSERT_TRUE(two.has_value());
  EXPECT_NEAR(two->value, 0.98, 1e-12);
  EXPECT_TRUE(std::isnan(two->u));
  // Second order in h: φ_R = φ_0 + (φ_0 − φ_1)/3.
  const auto h = richardson(grid_convergence_index({1.25, 2.0}, 2, 2));
  ASSERT_TRUE(h.has_value());
  EXPECT_NEAR(h->value, 1.0, 1e-12);
}

TEST(UncertaintyEstimator, RichardsonsUReachesTheLimitWhereTheObservedOrderIsBelowTheFormal) {
  // φ(Δt) = 1 + √Δt at Δt = 1, 2, 4: p = 0.5, inside the estimator's F_s = 1.25 range for q = 1;
  // the first-order extrapolation 1.586 stays 0.586 from the limit, and U_R reaches it.
  auto phi = [](double dt) { return 1 + std::sqrt(dt); };
  const RefinementUncertainty u = grid_convergence_index({phi(1), phi(2), phi(4)}, 2, 1);
  const auto R = richardson(u);
  ASSERT_TRUE(R.has_value()) << u.describe();
  EXPECT_LE(std::abs(R->value - 1.0), R->u * (1 + 1e-12)) << u.describe();
}

TEST(UncertaintyEstimator, RichardsonRefusesNoiseAndSequencesOutsideTheAsymptoticRange) {
  // Steps within the noise of a start ensemble (a chaotic quantity, s = 0.1): no extrapolation.
  EXPECT_FALSE(richardson(grid_convergence_index({9.10, 9.15, 9.25}, 2, 1, 0, 0.1)).has_value());
  // Not monotone: outside the asymptotic range.
  EXPECT_FALSE(richardson(grid_convergence_index({3.0, 3.4, 3.1}, 2, 1)).has_value());
  // An observed order far above the formal one (p = 3 for a first-order scheme): F_s = 3, none.
  EXPECT_FALSE(richardson(grid_convergence_index({1.001, 1.008, 1.064}, 2, 1)).has_value());
  // Two levels of a row given a spread of starts (a crowd's layer, recorded relative to the finer
  // level): none, though the step is above the noise.
  EXPECT_FALSE(richardson(grid_convergence_index({0.0, 0.9015}, 2, 1, 0, 0.051)).has_value());
  // Steps that hardly shrink (p = 0.07): outside the range.
  EXPECT_FALSE(richardson(grid_convergence_index({9.115, 9.156, 9.199}, 2, 1)).has_value());
  // The noisy sequence without noise, converging at first order, is extrapolated.
  EXPECT_TRUE(richardson(grid_convergence_index({9.10, 9.15, 9.25}, 2, 1)).has_value());
}

}  // namespace
}  // namespace rbc
