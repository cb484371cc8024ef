#pragma once
// Our numerical uncertainty u_num beside every compared number (issue 40; ASME V&V 20-2009,
// Sec. 5: the comparison error E = ours − study is judged together with the uncertainty of our
// own number; the part from the discretisation by Roache's grid convergence index).
//
// The Δt part, from runs at Δt_1 < Δt_2 < Δt_3 (ratio r = Δt_{k+1}/Δt_k) with values f_1, f_2,
// f_3:
//   e_21 = f_2 − f_1,  e_32 = f_3 − f_2
//   observed order   p = ln(e_32 / e_21) / ln r          (three levels, same sign: monotone)
//   GCI of f_1       u_Δt = F_s |e_21| / (r^q − 1)
//   GCI of f_2       u_Δt = F_s |e_21| r^q / (r^q − 1)   (the reported run is the middle level:
//                    a finer run was made as evidence only, Roache's coarse-grid GCI)
// with q = min(p, formal order) (no credit for an order above the scheme's: the runs are not
// shown to be asymptotic beyond it) and F_s = 1.25 when p lies in [formal/2, 2 formal], else 3
// (Roache's factor for an order that was not observed). Two levels, or three that oscillate:
// q = the formal order and F_s = 3.
//
// The start ensemble's part: the sample standard deviation s of the members (the study ran one
// arrangement; ours at an arbitrary start is uncertain by s, not by s/√n).
// The averaging window's part: the sample standard deviation of the means over the last
// `count` windows of the row's length (both the time noise and a remaining drift).
// u_num = sqrt(u_Δt² + s² + u_window²) (V&V 20's root-sum-square of independent parts).
//
// The mesh is reported apart ("converged in h"): the runs are at the study's h, so the mesh
// error is one the study's own number carries too; the column says what a finer mesh gives.
#include <optional>
#include <string>
#include <vector>

namespace rbc {

struct RefinementUncertainty {
  int levels = 0;               // runs used (0: none)
  double u = 0;                 // the GCI of the reported run (the finest, or the next), in the value's unit
  int reported = 0;             // which level u is for: 0 the finest, 1 the next coarser
  double observed_order = 0;    // NaN with two levels or oscillating values
  double order_used = 0, safety_factor = 0;
  double extrapolated = 0;      // f_1 + (f_1 − f_2)/(r^q − 1): the Δt → 0 (or h → 0) estimate
  std::string label;            // the levels, set by the caller: "Δt 1.5/3/6 us"
  // e.g. "Δt 1.5/3/6 us: p = 0.93, GCI 0.042 (Fs 1.25)"; `digits` significant digits.
  std::string describe(int digits = 2) const;
};

// finest_first: the values at the finest level first, then each coarser one (ratio r apart);
// reported: the level whose GCI u is (0: the finest, 1: the next coarser).
// Throws std::invalid_argument for fewer than two values, a ratio ≤ 1, a formal order ≤ 0 or a
// reported level other than 0 and 1.
RefinementUncertainty grid_convergence_index(const std::vector<double>& finest_first, double ratio, double formal_order, int reported = 0);

// Sample standard deviation (n − 1); NaN for fewer than two values.
double sample_std(const std::vector<double>& v);

// The standard deviation of the means of the last `count` windows of length `window` ending at
// t.back() (t ascending); NaN when the series is shorter than count windows.
double window_noise(const std::vector<double>& t, const std::vector<double>& v, double window, int count = 5);

// The parts of one row's u_num, each in the row's unit (absent: not measured).
struct NumericalUncertainty {
  std::optional<RefinementUncertainty> dt;
  std::optional<double> ensemble;  // s of the start ensemble
  int members = 0;
  std::optional<double> window;    // the averaging window's noise
  std::string other;               // a part named in words (e.g. "area drift 0.0003 %")
  std::optional<double> other_value;
  std::string missing;             // parts whose evidence runs did not finish: u_num is incomplete
                                   // and the verdict treats it as not measured
  // sqrt of the sum of the squares of the parts measured; empty when none is.
  std::optional<double> total() const;
  std::string describe(int digits = 2) const;
};

}  // namespace rbc
