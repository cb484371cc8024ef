#include "semi_implicit/step_mobility.hpp"

#include <algorithm>
#include <cmath>

#include <gsl/gsl_integration.h>
#include <omp.h>

#include "immersed_boundary/immersed_boundary.hpp"
#include "semi_implicit/detail/phase_average_kernel.hpp"
#include "immersed_boundary/peskin_delta.hpp"

namespace rbc {

StepMobility::StepMobility(const ChannelMesh& mesh, ImplicitDiffusion& diffusion, QuasiStokesProjection& projection,
                           double rho, double dt)
    : m_(mesh), diffusion_(diffusion), projection_(projection), rho_(rho), dt_(dt), rows_(mesh.ny - 1), table_(rows_) {}

void StepMobility::tabulate_source_row(int js) {
  if (table_[js]) return;
  const int nx = m_.nx;
  const std::size_t plane = std::size_t(nx) * rows_;
  // Filled before it is kept (a solve that throws leaves the row untabulated); every value written
  // below, so not cleared first.
  std::unique_ptr<double[]> row(new double[plane * 8]);
  VelocityField u[2] = {VelocityField(m_), VelocityField(m_)};
  std::vector<double> p(m_.pressure_nodes(), 0.0), b(plane);
  for (int parity = 0; parity < 2; ++parity) {
    // A⁻¹ of a unit value at node (parity, js + 1): the same for either component β.
    std::fill(b.begin(), b.end(), 0.0);
    b[std::size_t(js) * nx + parity] = 1.0;
    diffusion_.solve_interior(b.data());
    for (int beta = 0; beta < 2; ++beta) {
      // P A⁻¹ applied to a unit value in component β at that node.
      std::fill(u[beta].u1.begin(), u[beta].u1.end(), 0.0);
      std::fill(u[beta].u2.begin(), u[beta].u2.end(), 0.0);
      std::copy(b.begin(), b.end(), (beta == 0 ? u[beta].u1 : u[beta].u2).begin() + nx);
      std::fill(p.begin(), p.end(), 0.0);
      // P as a fixed linear map (with the Schur preconditioner one fast solve, else CG from p = 0).
      projection_.project(u[beta], u[beta], p, rho_, dt_, ProjectionForm::exact);
    }
    // T_αβ for this parity, the four values of an entry written together (stored by column
    // offset i − parity).
    for (int j = 0; j < rows_; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::size_t n = std::size_t(j + 1) * nx + i;
        double* t = &row[offset(j, wrap_index(i - parity, nx)) + 4 * parity];
        t[0] = u[0].u1[n];  // α = 0, β = 0
        t[1] = u[1].u1[n];  // α = 0, β = 1
        t[2] = u[0].u2[n];  // α = 1, β = 0
        t[3] = u[1].u2[n];  // α = 1, β = 1
      }
  }
  table_[js] = std::move(row);
}

int StepMobility::rows_tabulated() const {
  return int(std::count_if(table_.begin(), table_.end(), [](const std::unique_ptr<double[]>& t) { return t != nullptr; }));
}

std::size_t StepMobility::table_bytes() const { return std::size_t(rows_tabulated()) * 8 * m_.nx * rows_ * sizeof(double); }

double peskin_autocorrelation(double z) {
  // φ(τ) φ(τ + z) is smooth between the points where τ or τ + z is an integer: Gauss–Legendre
  // (8 points) on each such piece of the common support [−2, 2 − |z|] is exact to round-off.
  z = std::abs(z);
  if (z >= 4.0) return 0.0;
  static const gsl_integration_glfixed_table* rule = gsl_integration_glfixed_table_alloc(8);
  std::vector<double> cuts = {-2.0, 2.0 - z};
  for (int i = -1; i <= 1; ++i) {
    if (i > -2.0 && i < 2.0 - z) cuts.push_back(i);
    if (i - z > -2.0 && i - z < 2.0 - z) cuts.push_back(i - z);
  }
  std::sort(cuts.begin(), cuts.end());
  double sum = 0.0;
  for (std::size_t c = 0; c + 1 < cuts.size(); ++c)
    for (std::size_t i = 0; i < 8; ++i) {
      double t, w;
      gsl_integration_glfixed_point(cuts[c], cuts[c + 1], i, &t, &w, rule);
      sum += w * peskin_phi(t) * peskin_phi(t + z);
    }
  return sum;
}

void StepMobility::averaged_kernel(int j, int js, double z, double out[4]) const {
  // H(j, j', z) = Σ_d c(d − z) T̄(d, j, j'), |d − z| < 4.
  for (int v = 0; v < 4; ++v) out[v] = 0.0;
  for (int d = int(std::ceil(z - 4.0)); d <= int(std::floor(z + 4.0)); ++d) {
    const double c = 0.5 * peskin_autocorrelation(d - z);
    const double* g = entry(j, js, wrap_index(d, m_.nx));
    for (int v = 0; v < 4; ++v) out[v] += c * (g[v] + g[4 + v]);
  }
}

std::size_t StepMobility::phase_average_bytes(const ChannelMesh& mesh, double extent) {
  const int reach = int(std::ceil(extent / mesh.h)) + 4;  // + the stencils' reach
  const std::size_t J = std::min(mesh.ny - 2, reach), Z = std::min(mesh.nx / 2, reach);
  return std::size_t(mesh.ny - 1) * (2 * J + 1) * (2 * Z * kPhaseSamples + 1) * 4 * sizeof(float);
}

void StepMobility::prepare_phase_average(double extent) {
  if (extent == extent_) return;
  for (int js = 0; js < rows_; ++js) tabulate_source_row(js);
  const int reach = int(std::ceil(extent / m_.h)) + 4, m = kPhaseSamples, nx = m_.nx;
  J_ = std::min(rows_ - 1, reach);
  Z_ = std::min(nx / 2, reach);
  const int W = 2 * J_ + 1, S = 2 * Z_ * m + 1;
  // c at the multiples of 1/m (every d − z that a sample z meets).
  std::vector<double> c(8 * m + 1);
  for (int k = -4 * m; k <= 4 * m; ++k) c[k + 4 * m] = 0.5 * peskin_autocorrelation(double(k) / m);
  H_.assign(std::size_t(rows_) * W * S * 4, 0.0f);
#pragma omp parallel for schedule(dynamic)
  for (int j = 0; j < rows_; ++j)
    for (int js = std::max(0, j - J_); js <= std::min(rows_ - 1, j + J_); ++js) {
      for (int s = 0; s < S; ++s) {
        float* out = &H_[((std::size_t(j) * S + s) * W + (js - j + J_)) * 4];
        // z = (s − Z m)/m; d − z = (d m − s + Z m)/m = k/m with |k| < 4m.
        const int zm = s - Z_ * m;
        double acc[4] = {0, 0, 0, 0};
        for (int d = (zm - 4 * m) / m - 1; d <= (zm + 4 * m) / m + 1; ++d) {
          const int k = d * m - zm;
          if (k <= -4 * m || k >= 4 * m) continue;
          const double* g = entry(j, js, wrap_index(d, nx));
          for (int v = 0; v < 4; ++v) acc[v] += c[k + 4 * m] * (g[v] + g[4 + v]);
        }
        for (int v = 0; v < 4; ++v) out[v] = float(acc[v]);
      }
    }
  extent_ = extent;
}

void StepMobility::phase_averaged_matrix(const Points& r, Eigen::MatrixXd& M) const {
  constexpr int kPrefetchAhead = 4;  // sources
  const int n = int(r.size()), nx = m_.nx, m = kPhaseSamples, W = 2 * J_ + 1, S = 2 * Z_ * m + 1;
  std::vector<int> row(n);  // interior row of each node's first stencil row
  std::vector<double> wy(std::size_t(n) * 4), x(n);
  for (int k = 0; k < n; ++k) {
    row[k] = peskin_weights(r[k].y() / m_.h, &wy[4 * std::size_t(k)]) - 1;
    x[k] = r[k].x() / m_.h;
  }
  M.resize(2 * n, 2 * n);
#pragma omp parallel if (!omp_in_parallel())
  {
    std::vector<double> acc(std::size_t(n) * 4);  // row pair k of M: (l, 2α + β)
    std::vector<int> sample(n);
    std::vector<double> frac(n), zs(n);
    std::vector<char> near(n);  // pair within the table's reach in x1
#pragma omp for schedule(static)
    for (int k = 0; k < n; ++k) {
      for (int l = 0; l < n; ++l) {
        double z = x[k] - x[l];
        z = nearest_image(z, nx);  // the nearest periodic image
        const double u = (z + Z_) * m;
        zs[l] = z;
        near[l] = std::abs(z) <= Z_;
        sample[l] = std::clamp(int(u), 0, S - 2);
        frac[l] = u - sample[l];
      }
      std::fill(acc.begin(), acc.end(), 0.0);
      // Response row by row (j fixed in the inner loops: they stay in one slab of H).
      for (int p = 0; p < 4; ++p) {
        const int j = row[k] + p;
        if (j < 0 || j >= rows_) continue;
        const double wk = wy[4 * std::size_t(k) + p];
        const float* slab = &H_[std::size_t(j) * W * S * 4];
        for (int l = 0; l < n; ++l) {
          // The slab's lines a few sources ahead, asked for now: the sources go round the
          // membrane, so where they read H jumps about, which the hardware cannot guess.
          if (const int la = l + kPrefetchAhead; la < n) {
            const int da = row[la] - j + J_;
            if (near[la] && da >= 0 && da + 3 < W) {
              const float* p0 = slab + (std::size_t(sample[la]) * W + da) * 4;
              __builtin_prefetch(p0);
              __builtin_prefetch(p0 + 15);
              __builtin_prefetch(p0 + std::size_t(W) * 4);
              __builtin_prefetch(p0 + std::size_t(W) * 4 + 15);
            }
          }
          double* a = &acc[4 * std::size_t(l)];
          const int d = row[l] - j + J_;  // offset slot of the source's first row
          if (near[l] && d >= 0 && d + 3 < W && row[l] >= 0 && row[l] + 3 < rows_) {
            // The common case: the source's four rows are consecutive slots of H at the two
            // samples around z, sixteen contiguous values each.
            const float* h0 = slab + (std::size_t(sample[l]) * W + d) * 4;
            detail::add_interpolated_pair(h0, h0 + std::size_t(W) * 4, wk, frac[l], &wy[4 * std::size_t(l)], a);
            continue;
          }
          for (int q = 0; q < 4; ++q) {
            const int js = row[l] + q;
            if (js < 0 || js >= rows_) continue;
            const double w = wk * wy[4 * std::size_t(l) + q];
            if (near[l] && std::abs(js - j) <= J_) {
              const float* h = slab + (std::size_t(sample[l]) * W + (js - j + J_)) * 4;
              const double f = frac[l];
              for (int v = 0; v < 4; ++v) a[v] += w * (h[v] + f * (h[4 * W + v] - h[v]));
            } else {  // beyond the table: the kernel from T (slow, rare)
              double g[4];
              averaged_kernel(j, js, zs[l], g);
              for (int v = 0; v < 4; ++v) a[v] += w * g[v];
            }
          }
        }
      }
      for (int l = 0; l < n; ++l) {
        M(2 * k, 2 * l) = acc[4 * l];
        M(2 * k, 2 * l + 1) = acc[4 * l + 1];
        M(2 * k + 1, 2 * l) = acc[4 * l + 2];
        M(2 * k + 1, 2 * l + 1) = acc[4 * l + 3];
      }
    }
  }
}

void StepMobility::matrix(const Points& r, Eigen::MatrixXd& M) {
  // Two stages. (a) The response of every source node l at the footprint (the mesh nodes under
  // any node's stencil): R_l(x) = Σ_{q, qx} φ_l T(x − source); (b) M_kl = Σ_{x ∈ stencil k} φ_k(x) R_l(x).
  // 64 multiply-adds per (l, footprint node) and per pair, instead of 16 × 7 × 8 per pair.
  const int n = int(r.size()), nx = m_.nx;
  std::vector<NodeStencil> st;
  node_stencils(m_, r, st);
  for (const NodeStencil& b : st)
    for (int q = 0; q < 4; ++q)
      if (const int js = b.j0 + q - 1; js >= 0 && js < rows_) tabulate_source_row(js);
  // The footprint: interior mesh nodes (column mod nx, interior row) under some stencil; slot
  // of each stencil point (−1 for rows on or beyond the walls).
  std::vector<int> slot(std::size_t(n) * 16, -1);
  std::vector<std::pair<int, int>> points;  // (column, interior row)
  std::vector<int> index(std::size_t(nx) * rows_, -1);
  for (int k = 0; k < n; ++k)
    for (int p = 0; p < 4; ++p) {
      const int j = st[k].j0 + p - 1;
      if (j < 0 || j >= rows_) continue;
      for (int px = 0; px < 4; ++px) {
        const int i = st[k].i0 + px < nx ? st[k].i0 + px : st[k].i0 + px - nx;
        int& id = index[std::size_t(j) * nx + i];
        if (id < 0) { id = int(points.size()); points.push_back({i, j}); }
        slot[std::size_t(k) * 16 + p * 4 + px] = id;
      }
    }
  const int F = int(points.size());
  std::vector<double> R(std::size_t(F) * n * 4);  // R_l(x) at [(x n + l) 4 + v]
#pragma omp parallel for schedule(static) if (!omp_in_parallel())
  for (int l = 0; l < n; ++l) {
    const NodeStencil& b = st[l];
    double w[16];  // φ_l's weights, wy[q] wx[qx]
    for (int q = 0; q < 4; ++q)
      for (int qx = 0; qx < 4; ++qx) w[q * 4 + qx] = b.wy[q] * b.wx[qx];
    for (int x = 0; x < F; ++x) {
      const auto [i, j] = points[x];
      int d0 = i - b.i0;  // column offset to the first source column, mod nx
      d0 += d0 < 0 ? nx : 0;
      double acc[4] = {0, 0, 0, 0};
      for (int q = 0; q < 4; ++q) {
        const int js = b.j0 + q - 1;
        if (js < 0 || js >= rows_) continue;
        const double* plane = entry(j, js, 0);
        for (int qx = 0; qx < 4; ++qx) {
          int di = d0 - qx;  // i − (i0 + qx) mod nx
          di += di < 0 ? nx : 0;
          const double* g = plane + std::size_t(di) * 8 + 4 * ((b.i0 + qx) & 1);
          const double wq = w[q * 4 + qx];
          for (int v = 0; v < 4; ++v) acc[v] += wq * g[v];
        }
      }
      for (int v = 0; v < 4; ++v) R[(std::size_t(x) * n + l) * 4 + v] = acc[v];
    }
  }
  M.resize(2 * n, 2 * n);
#pragma omp parallel if (!omp_in_parallel())
  {
  std::vector<double> sum(std::size_t(n) * 4);  // row pair k of M, (l, v) with v = 2α + β
#pragma omp for schedule(static)
  for (int k = 0; k < n; ++k) {
    const NodeStencil& a = st[k];
    std::fill(sum.begin(), sum.end(), 0.0);
    for (int p = 0; p < 4; ++p)
      for (int px = 0; px < 4; ++px) {
        const int x = slot[std::size_t(k) * 16 + p * 4 + px];
        if (x < 0) continue;
        const double w = a.wy[p] * a.wx[px];
        const double* Rx = &R[std::size_t(x) * n * 4];  // R at footprint point x for every l
        for (int lv = 0; lv < 4 * n; ++lv) sum[lv] += w * Rx[lv];
      }
    for (int l = 0; l < n; ++l) {
      M(2 * k, 2 * l) = sum[4 * l];
      M(2 * k, 2 * l + 1) = sum[4 * l + 1];
      M(2 * k + 1, 2 * l) = sum[4 * l + 2];
      M(2 * k + 1, 2 * l + 1) = sum[4 * l + 3];
    }
  }
  }
}

}  // namespace rbc
