#pragma once
// Our numerical uncertainty u_num beside every compared number (ASME V&V 20-2009,
// Sec. 5: the comparison error E = ours − study is judged together with the uncertainty of our
// own number). Every part is at one coverage, 95 %.
//
// The Δt part (and the h part), by the least-squares procedure of Eça & Hoekstra (J. Comput.
// Phys. 262 (2014) 104–130) for values that scatter. Runs at n levels h_k = r^k (k = 0 the
// finest, in units of its step; r the ratio between levels) give values φ_k; q is the scheme's
// formal order (1 for Δt, 2 for h).
//   fits, least squares over all n levels (m unknowns each):
//     δ_RE     φ_k = φ_0 + α h_k^p                      observed order p (m = 3; only for
//                                                        monotone values; n = 3: exact,
//                                                        p = ln(e_32/e_21)/ln r, e_ij = φ_i − φ_j)
//     δ_a      φ_k = φ_0 + α h_k^a                      fixed orders a = 1 and b = 2, the
//     δ_b      φ_k = φ_0 + α h_k^b                      paper's (for Δt the formal order and twice
//                                                        it; for h a first-order part, e.g. from
//                                                        the interface, stays in view); for q < 1
//                                                        a = q, b = 2q (m = 2 each)
//     δ_ab     φ_k = φ_0 + α_1 h_k^a + α_2 h_k^b        the two-term expansion (m = 3, n ≥ 4)
//   the fit's standard deviation   σ = sqrt(Σ_k (φ_k − φ_fit(h_k))² / (n − m))
//   the data range                 Δ_φ = (φ_max − φ_min)/(n − 1)
//   order thresholds: the paper's 0.5, 2 and 2.1 are for second-order methods; here they are
//   scaled to the formal order, by q/2:  p_lo = q/4,  p_hi = q,  p_fs = 1.05 q  (Δt: 0.25, 1, 1.05)
//   the choice: δ_RE when the values are monotone and p_lo ≤ p ≤ p_hi; otherwise the one
//     of δ_a, δ_b, δ_ab with the smallest σ
//     (the paper, for p above its range, also weighs δ_RE against the fixed-order fits by σ; we
//     drop δ_RE there: an order above the scheme's is not credited)
//   few points (n = 3): δ_RE fits exactly (no degree of freedom) and δ_ab is not used; δ_RE's σ
//     is then min(σ_a, σ_b), one degree of freedom each: how far the data are from the
//     expansions the scheme has
//   s given (the standard deviation of one run's value from other sources, e.g. a start
//     ensemble): every fixed-order fit with σ ≤ max(σ_choice, 2 s) describes the data within
//     their noise, and the data cannot tell it from the choice; of these the one with the
//     largest ε_k is used. And σ* = max(σ, s): no fit is closer to the data than their scatter
//     (without s, σ* = σ)
//   error of level k   ε_k = |φ_fit(h_k) − φ_0|,  φ_0 the fit's limit (the extrapolated value)
//   safety factor      F_s = 1.25 when monotone, p_lo ≤ p < p_fs and σ* < Δ_φ; else 3
//   U_k = F_s ε_k + σ* + |φ_k − φ_fit(h_k)|              when σ* < Δ_φ
//   U_k = 3 σ*/Δ_φ (ε_k + σ* + |φ_k − φ_fit(h_k)|)       when σ* ≥ Δ_φ (scatter larger than the
//                                                         steps: noise, no order observed)
//   two levels: Roache's GCI with q and F_s = 3,  U_k = 3 |e_21| r^(qk)/(r^q − 1) (+ 2 s if given)
//   all values equal: U_k = 2 s (0 without s)
// Noise. Given s, the levels are told from noise by the slope α_a of δ_a: its standard error is
// SE = s/sqrt(S_xx), S_xx = Σ_k (h_k^a − mean)²; |α_a| ≤ 2 SE (for two levels: |e_21| ≤ 2√2 s)
// is noise: no order is observed, the limit is δ_a's φ_0 and
//   U_k = 2 s + (|α_a| + 2 SE) h_k^a
// (the run's own scatter at 95 % plus the largest first-order error the data allow).
// U is that of the reported level k (0 the finest; a row run at a coarser level than the finest
// evidence run reports its own), against the Δt → 0 (h → 0) limit, at 95 %.
// Where s is given, the fit's σ* and the start ensemble's own part (below) both carry s: σ* is the
// uncertainty of the fitted limit from scattered levels, 2 s that of the reported run's value
// about its ensemble; they overlap, and both are kept (conservative, never smaller).
//
// The start ensemble's part: the sample standard deviation s of the members (the study ran one
// arrangement; ours at an arbitrary start is uncertain by s, not by s/√n).
// The averaging window's part: the sample standard deviation u_w of the means over the last
// `count` windows of the row's length (both the time noise and a remaining drift).
// Both are 1σ: at 95 % they count 2 s and 2 u_w (k = 2). With a part u_o named in words:
//   u_num = sqrt(U_Δt² + (2 s)² + (2 u_w)² + u_o²)
// (V&V 20's root-sum-square of independent parts).
//
// The mesh is reported apart ("converged in h"): the runs are at the study's h, so the mesh
// error is one the study's own number carries too; the column says what a finer mesh gives.
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace rbc {

// The fit an estimate came from (see above).
enum class RefinementFit { TwoLevels, ObservedOrder, FixedLow, FixedHigh, TwoTerm, Noise, Constant };

struct RefinementUncertainty {
  int levels = 0;               // values used (0: none)
  double u = 0;                 // U of the reported level at 95 %, in the value's unit
  int reported = 0;             // which level u is for: 0 the finest, 1 the next coarser, ...
  double observed_order = 0;    // p of δ_RE; NaN with two levels, values that are not monotone, noise, or σ* ≥ Δ_φ
  double order_used = 0;        // the order of the fit used (p, a or b; a for δ_ab; q with two levels)
  double safety_factor = 0;     // F_s (NaN for noise: no factor)
  double extrapolated = 0;      // the fit's limit φ_0: the Δt → 0 (or h → 0) estimate
  RefinementFit fit = RefinementFit::TwoLevels;
  double fit_sigma = NAN;       // σ* of the fit used (NaN when it has no degree of freedom and no s is given)
  double data_range = 0;        // Δ_φ
  double noise = NAN;           // s as given (NaN: not known)
  double formal_order = 0;      // q as given
  std::vector<double> values;   // φ_k as given, finest first (what a record keeps to estimate U again)
  double ratio = 0;             // r as given
  bool noise_dominated = false; // no convergence observed: noise, or σ* ≥ Δ_φ
  std::string label;            // the levels, set by the caller: "Δt 1.5/3/6 us"
  // e.g. "Δt 1.5/3/6 us: p = 0.93, fit σ 0.004, U 0.042 (Fs 1.25)",
  // "Δt 0.75/1.5/3/6 us: p = 1.7; fit p = 1, fit σ 0.024, U 0.28 of the second finest (Fs 3)" or
  // "Δt 1.5/3/6 us: noise: no convergence observed (s 0.023), U 0.07"; `digits` significant digits.
  // Where richardson() gives an estimate, it follows as the change from the finest level (values
  // may be recorded relative to a level): " [Richardson: the limit +0.12 from the finest ± 0.02]".
  std::string describe(int digits = 2) const;
};

// finest_first: the values at the finest level first, then each coarser one (ratio r apart);
// reported: the level whose U u is (0: the finest, 1: the next coarser, ...); noise: the standard
// deviation s of one run's value from other sources (NaN: not known).
// Throws std::invalid_argument for fewer than two values, a ratio ≤ 1, a formal order ≤ 0, a
// reported level outside the levels given, or a negative noise.
RefinementUncertainty grid_convergence_index(const std::vector<double>& finest_first, double ratio, double formal_order, int reported = 0,
                                             double noise = NAN);

// Richardson extrapolation to Δt → 0 (h → 0) at the formal order q, for a sequence that shows its
// asymptotic range by the estimator's own test (F_s = 1.25: monotone, q/4 ≤ p < 1.05 q, σ* < Δ_φ;
// with two levels: not read as noise), from the finest two levels φ_0, φ_1:
//   φ_R = φ_0 + (φ_0 − φ_1)/(r^q − 1),
// and its own U at 95 %, from the same extrapolation one level coarser (φ_1, φ_2), φ_R', and the
// estimator's own limit φ_fit:
//   U_R = max(1.25 |φ_R − φ_R'|, |φ_R − φ_fit|)
// (the extrapolate's change over one refinement bounds its remainder where that is of a higher
// order; where the observed order is below q the fit's limit lies further, and U_R reaches it);
// NaN with two levels. None for a sequence outside its asymptotic range, scattered, noise, or
// one given a spread of starts s (a chaotic quantity: the crowds, the four cells).
// The extrapolation itself, of two levels r apart at order q: φ_f + (φ_f − φ_c)/(r^q − 1).
inline double richardson_extrapolate(double fine, double coarse, double ratio, double order) {
  return fine + (fine - coarse) / (std::pow(ratio, order) - 1);
}
struct RichardsonEstimate {
  double value = NAN;  // φ_R, in the value's unit
  double u = NAN;      // U_R at 95 % (NaN: two levels, no U of its own)
};
std::optional<RichardsonEstimate> richardson(const RefinementUncertainty& r);

// Sample standard deviation (n − 1); NaN for fewer than two values.
double sample_std(const std::vector<double>& v);

// The standard deviation of the means of the last `count` windows of length `window` ending at
// t.back() (t ascending); NaN when the series is shorter than count windows.
double window_noise(const std::vector<double>& t, const std::vector<double>& v, double window, int count = 5);

// The parts of one row's u_num, each in the row's unit (absent: not measured).
struct NumericalUncertainty {
  std::optional<RefinementUncertainty> dt;  // at 95 % already
  std::optional<double> ensemble;  // s of the start ensemble (1σ)
  int members = 0;
  bool of_mean = false;            // the value is the members' mean: its part is s/√members
  std::optional<double> window;    // the averaging window's noise (1σ)
  std::string other;               // a part named in words (e.g. "area drift 0.0003 %")
  std::optional<double> other_value;  // taken as given
  std::string missing;             // parts whose evidence runs did not finish: u_num is incomplete
                                   // and the verdict treats it as not measured
  std::string provenance;          // where parts read back from a record were measured (commit, source)
  // u_num at 95 %: sqrt(U_Δt² + (2 s)² + (2 u_w)² + u_o²) over the parts measured (2 s/√members
  // for a mean); empty when none is.
  std::optional<double> total() const;
  std::string describe(int digits = 2) const;
};

}  // namespace rbc
