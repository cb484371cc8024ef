#include "fast_solvers/periodic_banded_solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <tuple>
#include <utility>

#include <omp.h>

#include "mesh/channel_mesh.hpp"  // wrap_index

namespace rbc {

namespace {
// Smallest grid (nx × rows) whose solve is shared between threads: the wide channel's coarse
// pressure grid (160 × 81) pays (exact projection 0.27-0.30 → 0.21-0.23 ms, 2 threads).
constexpr std::size_t kParallelSize = 8192;
// FFTW's planner is not thread-safe (its execution is): plans are made and destroyed under a lock,
// so that independent simulations may be built on different threads.
std::mutex& fftw_planner_lock() {
  static std::mutex m;
  return m;
}

// FFTW's double (fftw_) and single (fftwf_) interfaces under one name; complex arrays are
// handled as interleaved Real pairs.
template <class Real>
struct Fftw;
template <>
struct Fftw<double> {
  using Plan = fftw_plan;
  static double* alloc(std::size_t n) { return fftw_alloc_real(n); }
  static void free(double* p) { fftw_free(p); }
  static int alignment_of(double* p) { return fftw_alignment_of(p); }
  static Plan r2c(int* n, int count, double* re, int nx, double* sp, int nk) {
    return fftw_plan_many_dft_r2c(1, n, count, re, nullptr, 1, nx, reinterpret_cast<fftw_complex*>(sp), nullptr, 1, nk, FFTW_ESTIMATE);
  }
  static Plan c2r(int* n, int count, double* sp, int nk, double* re, int nx) {
    return fftw_plan_many_dft_c2r(1, n, count, reinterpret_cast<fftw_complex*>(sp), nullptr, 1, nk, re, nullptr, 1, nx, FFTW_ESTIMATE);
  }
  static void destroy(Plan p) { fftw_destroy_plan(p); }
  static void r2c(Plan p, double* re, double* sp) { fftw_execute_dft_r2c(p, re, reinterpret_cast<fftw_complex*>(sp)); }
  static void c2r(Plan p, double* sp, double* re) { fftw_execute_dft_c2r(p, reinterpret_cast<fftw_complex*>(sp), re); }
};
template <>
struct Fftw<float> {
  using Plan = fftwf_plan;
  static float* alloc(std::size_t n) { return fftwf_alloc_real(n); }
  static void free(float* p) { fftwf_free(p); }
  static int alignment_of(float* p) { return fftwf_alignment_of(p); }
  static Plan r2c(int* n, int count, float* re, int nx, float* sp, int nk) {
    return fftwf_plan_many_dft_r2c(1, n, count, re, nullptr, 1, nx, reinterpret_cast<fftwf_complex*>(sp), nullptr, 1, nk, FFTW_ESTIMATE);
  }
  static Plan c2r(int* n, int count, float* sp, int nk, float* re, int nx) {
    return fftwf_plan_many_dft_c2r(1, n, count, reinterpret_cast<fftwf_complex*>(sp), nullptr, 1, nk, re, nullptr, 1, nx, FFTW_ESTIMATE);
  }
  static void destroy(Plan p) { fftwf_destroy_plan(p); }
  static void r2c(Plan p, float* re, float* sp) { fftwf_execute_dft_r2c(p, re, reinterpret_cast<fftwf_complex*>(sp)); }
  static void c2r(Plan p, float* sp, float* re) { fftwf_execute_dft_c2r(p, reinterpret_cast<fftwf_complex*>(sp), re); }
};
}  // namespace

namespace detail {
// The taps of A, read by probes: A applied to unit values at (0, j'). One row's response reaches
// the rows within the band of it, so rows 2b + 2 apart can be probed together (b: the band of a
// middle row, probed alone first) and each response given to the nearest probed row: 2b + 4
// products instead of one per row. The same taps, bit for bit, as probing each row alone, for an
// operator whose output in a row reads its input only in the rows within the band (every operator
// the package probes: step 4's Helmholtz operator, the Schur complement B M⁻¹ Bᵀ, the Neumann
// Laplacian): the inputs there are the same in both probes. A response farther than b from every
// probed row (a wider band near the walls), or a product on a pseudo-random field that the taps do
// not give back to 1e-12, sends it to one probe per row; that check bounds, but does not make
// bit for bit, an operator that reads farther than its band with contributions below 1e-12.
// The taps come out by (j', j, d), as one probe per row lists them.
std::vector<Tap> probe_taps(int nx, int rows, const std::function<void(const std::vector<double>&, std::vector<double>&)>& apply,
                            bool one_row_at_a_time) {
  std::vector<double> e(std::size_t(nx) * rows, 0.0), r(e.size(), 0.0);
  std::vector<Tap> taps;
  // Rows first, first + stride, ... probed at once; each response to its nearest probed row.
  // False where a response lies farther than reach from it.
  auto probe = [&](int first, int stride, int reach) {
    e.assign(e.size(), 0.0);
    for (int jp = first; jp < rows; jp += stride) e[std::size_t(jp) * nx] = 1.0;
    apply(e, r);
    const int last = first + (rows - 1 - first) / stride * stride;
    for (int j = 0; j < rows; ++j)
      for (int d = 0; d < nx; ++d)
        if (double a = r[std::size_t(j) * nx + d]; a != 0.0) {
          const int jp = std::clamp(first + (j - first + stride / 2) / stride * stride, first, last);
          if (std::abs(j - jp) > reach) return false;
          taps.push_back({j, jp, d, a});
        }
    return true;
  };
  const int middle = rows / 2;
  probe(middle, rows, rows);
  int band = 0;
  for (const Tap& t : taps) band = std::max(band, std::abs(t.j - t.jp));
  taps.clear();
  const int stride = 2 * band + 2;
  bool together = stride < rows && !one_row_at_a_time;
  for (int first = 0; together && first < stride; ++first) together = probe(first, stride, band);
  if (together) {
    // The check: A x against the taps' sum on a field of values in [0.5, 1.5), to 1e-12 of Σ|a x|.
    std::vector<double> x(e.size()), sum(e.size(), 0.0), bound(e.size(), 0.0);
    for (std::size_t n = 0; n < x.size(); ++n) x[n] = 0.5 + double((n * 2654435761u) % 1000003u) / 1000003.0;
    apply(x, r);
    for (const Tap& t : taps)
      for (int i = 0; i < nx; ++i) {
        const double ax = t.a * x[std::size_t(t.jp) * nx + wrap_index(i - t.d, nx)];
        sum[std::size_t(t.j) * nx + i] += ax;
        bound[std::size_t(t.j) * nx + i] += std::abs(ax);
      }
    for (std::size_t n = 0; together && n < x.size(); ++n) together = std::abs(r[n] - sum[n]) <= 1e-12 * bound[n] + 1e-300;
  }
  if (!together) {
    taps.clear();
    for (int jp = 0; jp < rows; ++jp) probe(jp, rows, rows);
  }
  std::sort(taps.begin(), taps.end(), [](const Tap& a, const Tap& b) { return std::tie(a.jp, a.j, a.d) < std::tie(b.jp, b.j, b.d); });
  return taps;
}
}  // namespace detail

template <class Real>
BasicPeriodicBandedSolver<Real>::BasicPeriodicBandedSolver(int nx, int rows, const Operator& apply, bool constant_kernel)
    : nx_(nx), rows_(rows), nk_(nx / 2 + 1) {
  if (nx < 2 || rows < 1) throw std::invalid_argument("PeriodicBandedSolver: empty grid");
  const std::vector<detail::Tap> taps = detail::probe_taps(nx, rows, apply);
  for (const detail::Tap& t : taps) band_ = std::max(band_, std::abs(t.j - t.jp));
  // The symbol Â_k, mode by mode, in banded storage.
  lu_.assign(std::size_t(nk_) * rows_ * (2 * band_ + 1), cplx(0.0));
  // An operator symmetric in x1 (every tap a(j, j', d) equal to a(j, j', −d), checked exactly; step
  // 4's is) has a real symbol: its imaginary parts, round-off of sines that cancel, are set to
  // zero, and the solve takes the real path below (half the multiplications).
  std::map<std::tuple<int, int, int>, double> tap_at;
  for (const detail::Tap& t : taps) tap_at[{t.j, t.jp, t.d}] = t.a;
  real_symbol_ = std::all_of(taps.begin(), taps.end(), [&](const detail::Tap& t) {
    const auto mirror = tap_at.find({t.j, t.jp, (nx_ - t.d) % nx_});
    return mirror != tap_at.end() && mirror->second == t.a;
  });
  for (const detail::Tap& t : taps)
    for (int k = 0; k < nk_; ++k) {
      const double phase = -2.0 * std::numbers::pi * double(k) * double(t.d) / double(nx_);
      entry(k, t.j, t.jp) += t.a * cplx(std::cos(phase), real_symbol_ ? 0.0 : std::sin(phase));
    }
  if (constant_kernel) {
    const int last = rows_ - 1;
    for (int jp = std::max(0, last - band_); jp < rows_; ++jp) entry(0, last, jp) = 0.0;
    entry(0, last, last) = 1.0;
  }
  // LU without pivoting of each banded Â_k (Hermitian positive definite, or made regular above).
  for (int k = 0; k < nk_; ++k)
    for (int p = 0; p < rows_; ++p) {
      const cplx pivot = entry(k, p, p);
      if (std::abs(pivot) == 0.0) throw std::runtime_error("PeriodicBandedSolver: singular mode");
      for (int r2 = p + 1; r2 <= std::min(rows_ - 1, p + band_); ++r2) {
        const cplx l = entry(k, r2, p) / pivot;
        entry(k, r2, p) = l;
        for (int c = p + 1; c <= std::min(rows_ - 1, p + band_); ++c) entry(k, r2, c) -= l * entry(k, p, c);
      }
    }
  lay_out_and_plan();
}

template <class Real>
BasicPeriodicBandedSolver<Real>::BasicPeriodicBandedSolver(FactorsOf factored)
    : nx_(factored.solver.nx_),
      rows_(factored.solver.rows_),
      nk_(factored.solver.nk_),
      band_(factored.solver.band_),
      lu_(factored.solver.lu_),
      real_symbol_(factored.solver.real_symbol_) {
  lay_out_and_plan();
}

template <class Real>
void BasicPeriodicBandedSolver<Real>::lay_out_and_plan() {
  const int w = 2 * band_ + 1;
  fre_.assign(std::size_t(rows_) * w * nk_, 0.0);
  fim_.assign(fre_.size(), 0.0);
  for (int k = 0; k < nk_; ++k)
    for (int j = 0; j < rows_; ++j)
      for (int o = 0; o < w; ++o) {
        const int jp = j + o - band_;
        if (jp < 0 || jp >= rows_) continue;
        cplx v = entry(k, j, jp);
        if (o == band_) v = 1.0 / v;
        fre_[(std::size_t(j) * w + o) * nk_ + k] = Real(v.real());
        fim_[(std::size_t(j) * w + o) * nk_ + k] = Real(v.imag());
      }
  // One batch of rows real transforms of length nx, planned once.
  using F = Fftw<Real>;
  std::lock_guard<std::mutex> guard(fftw_planner_lock());
  real_ = F::alloc(std::size_t(nx_) * rows_);
  spec_ = F::alloc(2 * std::size_t(nk_) * rows_);
  real2_ = F::alloc(std::size_t(nx_) * rows_);
  spec2_ = F::alloc(2 * std::size_t(nk_) * rows_);
  int n[] = {nx_};
  half_ = rows_ / 2;
  for (int h = 0; h < 2; ++h) {
    const int first = h == 0 ? 0 : half_, count = h == 0 ? half_ : rows_ - half_;
    if (count == 0) continue;
    Real* re = real_ + std::size_t(first) * nx_;
    Real* sp = spec_ + 2 * std::size_t(first) * nk_;
    forward_[h] = F::r2c(n, count, re, nx_, sp, nk_);
    backward_[h] = F::c2r(n, count, sp, nk_, re, nx_);
  }
}

template <class Real>
BasicPeriodicBandedSolver<Real>::~BasicPeriodicBandedSolver() {
  using F = Fftw<Real>;
  std::lock_guard<std::mutex> guard(fftw_planner_lock());
  for (Plan p : {forward_[0], forward_[1], backward_[0], backward_[1]})
    if (p) F::destroy(p);
  F::free(real_);
  F::free(spec_);
  F::free(real2_);
  F::free(spec2_);
}

template <class Real>
void BasicPeriodicBandedSolver<Real>::solve(const double* b, double* x) { solve_fields(1, &b, &x); }

template <class Real>
void BasicPeriodicBandedSolver<Real>::solve_pair(const double* b1, const double* b2, double* x1, double* x2) {
  const double* b[2] = {b1, b2};
  double* x[2] = {x1, x2};
  solve_fields(2, b, x);
}

template <class Real>
void BasicPeriodicBandedSolver<Real>::solve_pair_clearing(double* b1, double* b2, double* x1, double* x2) {
  const double* b[2] = {b1, b2};
  double* x[2] = {x1, x2};
  double* clear[2] = {b1, b2};
  solve_fields(2, b, x, clear);
}

template <class Real>
void BasicPeriodicBandedSolver<Real>::solve_fields(int fields, const double* const* b, double* const* x, double* const* clear) {
  using F = Fftw<Real>;
  constexpr bool single = std::is_same_v<Real, float>;
  const std::size_t size = std::size_t(nx_) * rows_;
  Real* real[2] = {real_, real2_};
  Real* spec[2] = {spec_, spec2_};
  const int w = 2 * band_ + 1;
  const Real scale = Real(1) / Real(nx_);
  // Values [first, last) of row half h.
  auto half = [&](int h) { return std::pair<std::size_t, std::size_t>(h == 0 ? 0 : std::size_t(half_) * nx_, h == 0 ? std::size_t(half_) * nx_ : size); };
  // Row half h of field f into the spectrum by the half's own plan, on the field's own arrays.
  auto forward = [&](int h, int f) {
    if (!forward_[h]) return;
    const auto [first, last] = half(h);
    // The plan reads b directly where b is aligned as the plan's own array (FFTW's r2c leaves its
    // input alone; same plan, same alignment: the same operations), else a copy of it (single
    // precision: always a copy, rounded).
    Real* in = real[f] + first;
    if constexpr (single) {
      for (std::size_t i = first; i < last; ++i) real[f][i] = float(b[f][i]);
    } else if (F::alignment_of(const_cast<double*>(b[f] + first)) == F::alignment_of(in)) {
      in = const_cast<double*>(b[f] + first);
    } else {
      std::memcpy(in, b[f] + first, sizeof(double) * (last - first));
    }
    const int first_row = h == 0 ? 0 : half_;
    F::r2c(forward_[h], in, spec[f] + 2 * std::size_t(first_row) * nk_);
    if (clear) std::memset(clear[f] + first, 0, sizeof(double) * (last - first));
  };
  auto backward = [&](int h, int f) {
    if (!backward_[h]) return;
    const int first_row = h == 0 ? 0 : half_;
    const auto [first, last] = half(h);
    // Straight into x where x is aligned as the plan's own array (the same operations, as for b
    // above), then scaled in place: one pass over the field fewer than through the plan's array.
    Real* out = real[f];
    if constexpr (!single)
      if (F::alignment_of(x[f] + first) == F::alignment_of(real[f] + first)) out = x[f];
    F::c2r(backward_[h], spec[f] + 2 * std::size_t(first_row) * nk_, out + first);
    for (std::size_t i = first; i < last; ++i) x[f][i] = out[i] * scale;
  };
  // The substitutions of fields [f0, f1) over the modes [k0, k1). Every mode's arithmetic is the
  // same whatever the range, so the split between threads does not change the result.
  auto substitute = [&](int f0, int f1, int k0, int k1) {
    // c_j −= f c_q for every mode, f the factor entry (j, q).
    auto subtract = [&](int j, int q) {
      const Real* fr = &fre_[(std::size_t(j) * w + (q - j + band_)) * nk_];
      const Real* fi = &fim_[(std::size_t(j) * w + (q - j + band_)) * nk_];
      if (real_symbol_) {  // f real: both parts of c_q times f (what the complex path computes with Im f = 0)
        for (int f = f0; f < f1; ++f) {
          Real* cj = spec[f] + 2 * std::size_t(j) * nk_;
          const Real* cq = spec[f] + 2 * std::size_t(q) * nk_;
          for (int k = k0; k < k1; ++k) {
            cj[2 * k] -= fr[k] * cq[2 * k];
            cj[2 * k + 1] -= fr[k] * cq[2 * k + 1];
          }
        }
        return;
      }
      for (int f = f0; f < f1; ++f) {
        Real* s = spec[f];
        for (int k = k0; k < k1; ++k) {
          const Real cr = s[2 * (std::size_t(q) * nk_ + k)], ci = s[2 * (std::size_t(q) * nk_ + k) + 1];
          s[2 * (std::size_t(j) * nk_ + k)] -= fr[k] * cr - fi[k] * ci;
          s[2 * (std::size_t(j) * nk_ + k) + 1] -= fr[k] * ci + fi[k] * cr;
        }
      }
    };
    // Forward substitution with the unit lower factor.
    for (int j = 1; j < rows_; ++j)
      for (int p = std::max(0, j - band_); p < j; ++p) subtract(j, p);
    // Back substitution with the upper factor: c_j = (c_j − Σ u_{j,q} c_q) / u_jj.
    for (int j = rows_ - 1; j >= 0; --j) {
      for (int q = j + 1; q <= std::min(rows_ - 1, j + band_); ++q) subtract(j, q);
      const Real* dr = &fre_[(std::size_t(j) * w + band_) * nk_];
      const Real* di = &fim_[(std::size_t(j) * w + band_) * nk_];
      if (real_symbol_) {
        for (int f = f0; f < f1; ++f) {
          Real* cj = spec[f] + 2 * std::size_t(j) * nk_;
          for (int k = k0; k < k1; ++k) {
            cj[2 * k] *= dr[k];
            cj[2 * k + 1] *= dr[k];
          }
        }
        continue;
      }
      for (int f = f0; f < f1; ++f) {
        Real* s = spec[f];
        for (int k = k0; k < k1; ++k) {
          const Real cr = s[2 * (std::size_t(j) * nk_ + k)], ci = s[2 * (std::size_t(j) * nk_ + k) + 1];
          s[2 * (std::size_t(j) * nk_ + k)] = dr[k] * cr - di[k] * ci;
          s[2 * (std::size_t(j) * nk_ + k) + 1] = dr[k] * ci + di[k] * cr;
        }
      }
    }
  };
  // Threads only pay on large grids (the wide channel's 320 x 159 and its coarse 160 x 81); small ones stay serial.
  const bool threaded = !omp_in_parallel() && size >= kParallelSize;
  if (threaded && fields == 2 && omp_get_max_threads() >= 2) {
    // Two fields on two or more threads: a thread solves one field whole (both halves' transforms,
    // every mode's substitutions), so that no field crosses between the cores and no barrier
    // waits inside the solve. Step 4's pair on the wide grid, in place, two threads: 159-177 us
    // against 213-259 us with the halves and modes shared, 304-325 us on one thread; the 50 cells' crowd step 6-8 % faster, 18 % in the machine's slow phase
    // (bench_channel --crowd-only, the two ways alternating in one run). The same operations per
    // value, so the same bits as one thread or solve().
#pragma omp parallel num_threads(2)
    {
      // (A team of one, if the runtime gives no second thread, solves both fields.)
      for (int f = omp_get_thread_num(); f < 2; f += omp_get_num_threads()) {
        for (int h = 0; h < 2; ++h) forward(h, f);
        substitute(f, f + 1, 0, nk_);
        for (int h = 0; h < 2; ++h) backward(h, f);
      }
    }
    return;
  }
#pragma omp parallel if (threaded)
  {
    const int threads = omp_get_num_threads(), t = omp_get_thread_num();
    // The spectrum is rows_ rows of nk_ modes: row j of mode k at spec[j * nk_ + k].
#pragma omp for schedule(static)
    for (int task = 0; task < 2 * fields; ++task) forward(task % 2, task / 2);
    // Each thread substitutes its own range of modes, [k0, k1), in every field.
    substitute(0, fields, t * nk_ / threads, (t + 1) * nk_ / threads);
#pragma omp barrier
#pragma omp for schedule(static)
    for (int task = 0; task < 2 * fields; ++task) backward(task % 2, task / 2);
  }
}

template class BasicPeriodicBandedSolver<double>;
template class BasicPeriodicBandedSolver<float>;

}  // namespace rbc
