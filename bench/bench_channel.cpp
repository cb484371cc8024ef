// Benchmark (not a test): time per step of the cell-free channel and its ratio to FFT pairs of
// the same grid, measured in the same run (machines are noisy; ratios travel better).
//   build/bin/bench_channel [--threads N] [--steps N]
// The reference "FFT pair" is one forward plus one inverse FFTW real 2D transform of the
// nx × ny grid (FFTW_ESTIMATE, as our solvers plan); we also print the pair of batched 1D
// transforms along x1 over the ny + 1 rows, which is what the fast solvers actually use.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>

#include <fftw3.h>
#include <omp.h>

#include "fluid/channel_flow.hpp"

using clk = std::chrono::steady_clock;

static double seconds_per_call(const std::function<void()>& f, double min_seconds = 0.5) {
  for (int i = 0; i < 3; ++i) f();
  long n = 0;
  const auto t0 = clk::now();
  double el = 0;
  do { f(); ++n; el = std::chrono::duration<double>(clk::now() - t0).count(); } while (el < min_seconds);
  return el / n;
}

struct FftPairs { double pair2d, pair1d; };

static FftPairs fft_pairs(int nx, int ny) {
  double* r = fftw_alloc_real(std::size_t(nx) * (ny + 1));
  fftw_complex* c = fftw_alloc_complex(std::size_t(nx / 2 + 1) * (ny + 1));
  for (int k = 0; k < nx * (ny + 1); ++k) r[k] = std::sin(0.1 * k);
  fftw_plan f2 = fftw_plan_dft_r2c_2d(ny, nx, r, c, FFTW_ESTIMATE), b2 = fftw_plan_dft_c2r_2d(ny, nx, c, r, FFTW_ESTIMATE);
  int n[] = {nx};
  fftw_plan f1 = fftw_plan_many_dft_r2c(1, n, ny + 1, r, nullptr, 1, nx, c, nullptr, 1, nx / 2 + 1, FFTW_ESTIMATE);
  fftw_plan b1 = fftw_plan_many_dft_c2r(1, n, ny + 1, c, nullptr, 1, nx / 2 + 1, r, nullptr, 1, nx, FFTW_ESTIMATE);
  FftPairs p;
  p.pair2d = seconds_per_call([&] { fftw_execute(f2); fftw_execute(b2); });
  p.pair1d = seconds_per_call([&] { fftw_execute(f1); fftw_execute(b1); });
  for (auto* pl : {&f2, &b2, &f1, &b1}) fftw_destroy_plan(*pl);
  fftw_free(r);
  fftw_free(c);
  return p;
}

int main(int argc, char** argv) {
  int threads = 0;
  for (int a = 1; a + 1 < argc; ++a)
    if (std::string(argv[a]) == "--threads") threads = std::atoi(argv[a + 1]);
  if (threads > 0) omp_set_num_threads(threads);
  std::printf("rbcflow bench_channel: cell-free Lie step (threads = %d)\n", omp_get_max_threads());
  std::printf("%-28s %10s %10s %10s %10s %9s %9s %9s %9s\n", "grid", "step_us", "steps/s", "fft2d_us", "fft1d_us",
              "step/2d", "step/1d", "proj_us", "adv_us");
  struct Case { const char* name; double L, H, h, re; };
  for (const Case& c : {Case{"narrow 20x10um h=0.125um", 20e-6, 10e-6, 0.125e-6, 0.5556},
                        Case{"wide 100x50um h=0.3125um", 100e-6, 50e-6, 0.3125e-6, 2.778}}) {
    rbc::ChannelFlowParams p;
    p.length = c.L;
    p.height = c.H;
    p.mesh_size = c.h;
    p.dt = 1e-7;
    p.body_force = rbc::body_force_from_reynolds(c.re, p.fluid, p.height);
    rbc::ChannelFlow flow(p);
    flow.set_poiseuille();
    // A divergent perturbation, so that every step projects and advects a 2D field.
    const rbc::ChannelMesh& m = flow.mesh();
    for (int j = 1; j < m.ny; ++j)
      for (int i = 0; i < m.nx; ++i)
        flow.velocity().u2[m.v(i, j)] = 0.01 * std::sin(6.283 * i / m.nx) * std::sin(3.1416 * j / m.ny);
    const double step = seconds_per_call([&] { flow.step(); }, 2.0);
    const double proj = seconds_per_call([&] { flow.project(); }, 0.5);
    const double adv = seconds_per_call([&] { flow.advect(); }, 0.5);
    const FftPairs f = fft_pairs(m.nx, m.ny);
    char grid[64];
    std::snprintf(grid, sizeof grid, "%s (%dx%d)", c.name, m.nx, m.ny);
    std::printf("%-28s %10.1f %10.0f %10.1f %10.1f %9.2f %9.2f %9.1f %9.1f\n", grid, step * 1e6, 1.0 / step,
                f.pair2d * 1e6, f.pair1d * 1e6, step / f.pair2d, step / f.pair1d, proj * 1e6, adv * 1e6);
  }
  return 0;
}
