#pragma once
// Fast direct solver for A x = b when A is invariant under translation in x1 (periodic, nx nodes)
// and couples rows j, j' only for |j - j'| <= b (the fast solvers of the study's Section 2.4).
//
// Because A commutes with the shift in x1, the discrete Fourier transform in x1 block-
// diagonalises it:  (A x)^_k = Â_k x̂_k,  Â_k[j][j'] = Σ_d a_{j,j'}(d) e^{-2πi k d / nx},
// where a_{j,j'}(d) is the response in row j, column d, to a unit value at (0, j').
// We read the symbol off A itself by applying it to a unit value in each row of column 0 (a
// "probe"; rows farther apart than twice the band probed together, the .cpp says how), factor
// every Â_k (Hermitian and banded) by LU once, and then each solve costs one
// real FFT pair in x1 plus nx/2+1 banded triangular solves. An operator symmetric in x1
// (a_{j,j'}(d) = a_{j,j'}(−d) for every tap, as step 4's) has a real symbol; its substitutions
// multiply by reals only. With OpenMP one field's rows' transforms and modes' substitutions are
// shared between threads; two fields (solve_pair) go one to a thread, whole. Each mode and row is
// computed the same way whatever the thread count, so the result does not depend on it.
//
// A singular A whose kernel is the constant field (a Neumann problem) is handled at k = 0 by
// replacing the last equation with x̂_0[rows-1] = 0; the solution is then defined up to the
// constant, which the caller fixes (e.g. mean-zero pressure).
//
// Real is the precision of the transforms and substitutions: double (every solve of the fluid
// steps), or float for solves that feed an iteration with a far looser tolerance (the semi-
// implicit coupling's GMRES products, semi_implicit/coupling_products.hpp: relative error
// ≈ 1e-7 against GMRES's 1e-4). Right-hand sides and solutions are double either way; the
// factors are computed in double and rounded once.
#include <type_traits>
#include <complex>
#include <functional>
#include <vector>

#include <fftw3.h>

namespace rbc {

namespace detail {
struct Tap {  // a_{j,j'}(d): the response in row j, column d, to a unit value at (0, j')
  int j, jp, d;
  double a;
  bool operator==(const Tap&) const = default;
};
// The taps of an operator, as the solvers read them (the .cpp says how); one_row_at_a_time: one
// probe per row, what grouping the rows must give bit for bit (tests).
std::vector<Tap> probe_taps(int nx, int rows, const std::function<void(const std::vector<double>&, std::vector<double>&)>& apply,
                            bool one_row_at_a_time = false);
}  // namespace detail

template <class Real>
class BasicPeriodicBandedSolver;
// A double solver whose factors another solver of the same operator takes (below).
struct FactorsOf {
  const BasicPeriodicBandedSolver<double>& solver;
};

template <class Real>
class BasicPeriodicBandedSolver {
  static_assert(std::is_same_v<Real, double> || std::is_same_v<Real, float>);

 public:
  using Field = std::vector<double>;  // nx * rows values, x1 fastest
  using Operator = std::function<void(const Field& in, Field& out)>;

  BasicPeriodicBandedSolver(int nx, int rows, const Operator& apply, bool constant_kernel);
  // The solver of a double solver's operator, from its factors (rounded once to Real): the same,
  // bit for bit, as the solver built from that operator, without probing it again.
  explicit BasicPeriodicBandedSolver(FactorsOf factored);
  ~BasicPeriodicBandedSolver();
  BasicPeriodicBandedSolver(const BasicPeriodicBandedSolver&) = delete;
  BasicPeriodicBandedSolver& operator=(const BasicPeriodicBandedSolver&) = delete;

  // x = A^{-1} b (b and x may alias). For a constant kernel, b must be compatible (zero sum).
  void solve(const double* b, double* x);
  // x1 = A^{-1} b1 and x2 = A^{-1} b2 at once: the factors are read once for both, and each
  // result is the same, bit for bit, as solve() gives it (same plans, same operations).
  void solve_pair(const double* b1, const double* b2, double* x1, double* x2);
  // solve_pair that leaves b1 and b2 zero: each half of a field's rows is cleared just after its
  // transform has read it, while it is still in the thread's cache, so that a caller building the
  // next right-hand side by adding into zeros (the GMRES products' spreading) needs no pass of its
  // own to clear them. x1, x2 as solve_pair's, bit for bit.
  void solve_pair_clearing(double* b1, double* b2, double* x1, double* x2);
  int half_bandwidth() const { return band_; }
  // Every factor real (an operator symmetric in x1): the substitutions multiply by reals only.
  bool real_symbol() const { return real_symbol_; }
  int nx() const { return nx_; }
  int rows() const { return rows_; }

 private:
  using cplx = std::complex<double>;
  int nx_, rows_, nk_, band_ = 0;
  std::vector<cplx> lu_;  // per mode: rows x (2 band + 1), entry (j, j') at [j*(2b+1) + j'-j+b]
  // The factors again, laid out for the solve: for row j and offset o = j'-j+b, the nk_ modes
  // are contiguous (real and imaginary parts apart), so the substitutions run over all modes at
  // once in unit stride; the diagonal holds 1/pivot.
  std::vector<Real> fre_, fim_;
  bool real_symbol_ = false;
  Real* real_ = nullptr;  // the plans' arrays: rows of nx values, and rows of nk interleaved complex values
  Real* spec_ = nullptr;
  Real* real2_ = nullptr;  // the second field of solve_pair (same alignment: the plans run on it too)
  Real* spec2_ = nullptr;
  // clear: null, or b again as writable arrays, zeroed once read (solve_pair_clearing).
  void solve_fields(int fields, const double* const* b, double* const* x, double* const* clear = nullptr);
  // The rows in two halves, each with its own pair of plans, so that two threads can transform
  // them at once; the halves are the same whatever the thread count (results do not depend on it).
  int half_ = 0;  // first row of the second half
  using Plan = std::conditional_t<std::is_same_v<Real, double>, fftw_plan, fftwf_plan>;
  Plan forward_[2] = {nullptr, nullptr}, backward_[2] = {nullptr, nullptr};
  void lay_out_and_plan();  // fre_, fim_ from lu_, and the transforms' arrays and plans
  template <class>
  friend class BasicPeriodicBandedSolver;
  cplx& entry(int k, int j, int jp) { return lu_[(std::size_t(k) * rows_ + j) * (2 * band_ + 1) + (jp - j + band_)]; }
};

using PeriodicBandedSolver = BasicPeriodicBandedSolver<double>;
// The same solver in single precision (double in and out): see the top of this file.
using SinglePeriodicBandedSolver = BasicPeriodicBandedSolver<float>;

}  // namespace rbc
