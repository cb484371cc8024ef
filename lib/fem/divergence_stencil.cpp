#include "fem/divergence_stencil.hpp"

#include <algorithm>

namespace rbc {

DivergenceStencil::DivergenceStencil(const ChannelMesh& mesh)
    : m_(mesh),
      fine_(mesh.velocity_nodes(), 0.0),
      tri_lower_(std::size_t(mesh.nx) * mesh.ny, 0.0),
      tri_upper_(std::size_t(mesh.nx) * mesh.ny, 0.0) {}

void DivergenceStencil::apply(const std::vector<double>& u1, const std::vector<double>& u2,
                              std::vector<double>& div) const {
  const int nx = m_.nx, ny = m_.ny;
  const double c = m_.h / 6.0;  // |T| (1/h) / 3 with |T| = h²/2
  // Triangle moments |T| (∇·u)_T / 3.
#pragma omp parallel for schedule(static)
  for (int j = 0; j < ny; ++j) {
    const double* a1 = &u1[std::size_t(j) * nx];
    const double* b1 = &u1[std::size_t(j + 1) * nx];
    const double* a2 = &u2[std::size_t(j) * nx];
    const double* b2 = &u2[std::size_t(j + 1) * nx];
    double* L = &tri_lower_[std::size_t(j) * nx];
    double* U = &tri_upper_[std::size_t(j) * nx];
    for (int i = 0; i < nx; ++i) {
      const int ip = (i + 1 == nx) ? 0 : i + 1;
      L[i] = c * (a1[ip] - a1[i] + b2[i] - a2[i]);
      U[i] = c * (b1[ip] - b1[i] + b2[ip] - a2[ip]);
    }
  }
  // Node moments d_n: the six triangles around node (i, j) (fewer on the walls).
#pragma omp parallel for schedule(static)
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int im = (i == 0) ? nx - 1 : i - 1;
      double d = 0;
      if (j < ny) d += tri_lower_[std::size_t(j) * nx + i] + tri_lower_[std::size_t(j) * nx + im] + tri_upper_[std::size_t(j) * nx + im];
      if (j > 0) d += tri_lower_[std::size_t(j - 1) * nx + i] + tri_upper_[std::size_t(j - 1) * nx + im] + tri_upper_[std::size_t(j - 1) * nx + i];
      fine_[std::size_t(j) * nx + i] = d;
    }
  // Restriction to T_2h: weight 1 at (2I, 2J), 1/2 at (±1, 0), (0, ±1), (−1, +1), (+1, −1).
  const int pnx = m_.pnx(), pny = m_.pny();
  div.resize(m_.pressure_nodes());
#pragma omp parallel for schedule(static)
  for (int J = 0; J < pny; ++J)
    for (int I = 0; I < pnx; ++I) {
      const int i = 2 * I, j = 2 * J, ip = (i + 1) % nx, im = (i + nx - 1) % nx;
      const double* row = &fine_[std::size_t(j) * nx];
      double s = row[i] + 0.5 * (row[ip] + row[im]);
      if (j > 0) s += 0.5 * (fine_[std::size_t(j - 1) * nx + i] + fine_[std::size_t(j - 1) * nx + ip]);
      if (j < ny) s += 0.5 * (fine_[std::size_t(j + 1) * nx + i] + fine_[std::size_t(j + 1) * nx + im]);
      div[std::size_t(J) * pnx + I] = s;
    }
}

void DivergenceStencil::apply_transpose(const std::vector<double>& p, std::vector<double>& g1,
                                        std::vector<double>& g2) const {
  const int nx = m_.nx, ny = m_.ny, pnx = m_.pnx();
  // Prolongation: q at every fine node by P1 interpolation on T_2h.
#pragma omp parallel for schedule(static)
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int I = i / 2, J = j / 2, Ip = (I + 1) % pnx;
      auto P = [&](int a, int b) { return p[std::size_t(b) * pnx + a]; };
      double q;
      if (i % 2 == 0 && j % 2 == 0) q = P(I, J);
      else if (j % 2 == 0) q = 0.5 * (P(I, J) + P(Ip, J));
      else if (i % 2 == 0) q = 0.5 * (P(I, J) + P(I, J + 1));
      else q = 0.5 * (P(Ip, J) + P(I, J + 1));  // midpoint of the coarse diagonal
      fine_[std::size_t(j) * nx + i] = q;
    }
  // Per triangle s_T = |T| (q_a + q_b + q_c)/3 / h = h (q_a + q_b + q_c)/6 (the 1/h of ∇φ folded in).
  const double c = m_.h / 6.0;
#pragma omp parallel for schedule(static)
  for (int j = 0; j < ny; ++j) {
    const double* a = &fine_[std::size_t(j) * nx];
    const double* b = &fine_[std::size_t(j + 1) * nx];
    for (int i = 0; i < nx; ++i) {
      const int ip = (i + 1 == nx) ? 0 : i + 1;
      tri_lower_[std::size_t(j) * nx + i] = c * (a[i] + a[ip] + b[i]);
      tri_upper_[std::size_t(j) * nx + i] = c * (a[ip] + b[ip] + b[i]);
    }
  }
  // (Bᵀp)_n = Σ_T s_T ∇φ_n|_T (in units of 1/h, already folded in):
  //   x1: −L(i,j) + L(i−1,j) + U(i−1,j−1) − U(i,j−1);   x2: −L(i,j) + L(i,j−1) − U(i−1,j) + U(i−1,j−1).
  g1.resize(m_.velocity_nodes());
  g2.resize(m_.velocity_nodes());
  for (auto* g : {&g1, &g2}) {  // wall rows: not unknowns; the interior is overwritten below
    std::fill(g->begin(), g->begin() + nx, 0.0);
    std::fill(g->end() - nx, g->end(), 0.0);
  }
#pragma omp parallel for schedule(static)
  for (int j = 1; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int im = (i == 0) ? nx - 1 : i - 1;
      const double La = tri_lower_[std::size_t(j) * nx + i], Lb = tri_lower_[std::size_t(j) * nx + im];
      const double Lc = tri_lower_[std::size_t(j - 1) * nx + i], Ub = tri_upper_[std::size_t(j) * nx + im];
      const double Ud = tri_upper_[std::size_t(j - 1) * nx + im], Uc = tri_upper_[std::size_t(j - 1) * nx + i];
      g1[std::size_t(j) * nx + i] = -La + Lb + Ud - Uc;
      g2[std::size_t(j) * nx + i] = -La + Lc - Ub + Ud;
    }
}

}  // namespace rbc
