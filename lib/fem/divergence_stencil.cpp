#include "fem/divergence_stencil.hpp"

#include <algorithm>

namespace rbc {

DivergenceStencil::DivergenceStencil(const ChannelMesh& mesh)
    : m_(mesh),
      fine_(mesh.velocity_nodes(), 0.0),
      tri_lower_(std::size_t(mesh.nx) * mesh.ny, 0.0),
      tri_upper_(std::size_t(mesh.nx) * mesh.ny, 0.0) {}

// The loops below wrap in x1 only in their first or last column, which is written out apart, so
// that the inner loops have no modulo or branch (the compiler vectorises them); every value is
// the same expression, summed in the same order, as in the straightforward loop.
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
    auto moments = [&](int i, int ip) {
      L[i] = c * (a1[ip] - a1[i] + b2[i] - a2[i]);
      U[i] = c * (b1[ip] - b1[i] + b2[ip] - a2[ip]);
    };
    for (int i = 0; i + 1 < nx; ++i) moments(i, i + 1);
    moments(nx - 1, 0);
  }
  // Node moments d_n: the six triangles around node (i, j) (fewer on the walls).
#pragma omp parallel for schedule(static)
  for (int j = 0; j <= ny; ++j) {
    const double* L = &tri_lower_[std::size_t(j) * nx];  // row j (j < ny)
    const double* U = &tri_upper_[std::size_t(j) * nx];
    const double* Ld = j > 0 ? &tri_lower_[std::size_t(j - 1) * nx] : nullptr;  // row j − 1
    const double* Ud = j > 0 ? &tri_upper_[std::size_t(j - 1) * nx] : nullptr;
    double* out = &fine_[std::size_t(j) * nx];
    auto node = [&](int i, int im) {
      double d = 0;
      if (j < ny) d += L[i] + L[im] + U[im];
      if (j > 0) d += Ld[i] + Ud[im] + Ud[i];
      out[i] = d;
    };
    node(0, nx - 1);
    for (int i = 1; i < nx; ++i) node(i, i - 1);
  }
  // Restriction to T_2h: weight 1 at (2I, 2J), 1/2 at (±1, 0), (0, ±1), (−1, +1), (+1, −1).
  const int pnx = m_.pnx(), pny = m_.pny();
  div.resize(m_.pressure_nodes());
#pragma omp parallel for schedule(static)
  for (int J = 0; J < pny; ++J) {
    const int j = 2 * J;
    const double* row = &fine_[std::size_t(j) * nx];
    const double* below = j > 0 ? &fine_[std::size_t(j - 1) * nx] : nullptr;
    const double* above = j < ny ? &fine_[std::size_t(j + 1) * nx] : nullptr;
    double* out = &div[std::size_t(J) * pnx];
    auto restrict_at = [&](int I, int ip, int im) {
      const int i = 2 * I;
      double s = row[i] + 0.5 * (row[ip] + row[im]);
      if (below) s += 0.5 * (below[i] + below[ip]);
      if (above) s += 0.5 * (above[i] + above[im]);
      out[I] = s;
    };
    restrict_at(0, 1, nx - 1);  // nx is even: only I = 0 wraps (to the left)
    for (int I = 1; I < pnx; ++I) restrict_at(I, 2 * I + 1, 2 * I - 1);
  }
}

void DivergenceStencil::apply_transpose(const std::vector<double>& p, std::vector<double>& g1,
                                        std::vector<double>& g2) const {
  const int nx = m_.nx, ny = m_.ny, pnx = m_.pnx();
  // Prolongation: q at every fine node by P1 interpolation on T_2h. Even fine rows lie on coarse
  // row J, odd ones between J and J + 1; odd columns between I and I + 1 (I + 1 wraps at the end).
#pragma omp parallel for schedule(static)
  for (int j = 0; j <= ny; ++j) {
    const int J = j / 2;
    const double* P = &p[std::size_t(J) * pnx];
    const double* Pa = j % 2 ? &p[std::size_t(J + 1) * pnx] : nullptr;  // coarse row J + 1
    double* q = &fine_[std::size_t(j) * nx];
    if (!Pa) {
      for (int I = 0; I + 1 < pnx; ++I) {
        q[2 * I] = P[I];
        q[2 * I + 1] = 0.5 * (P[I] + P[I + 1]);
      }
      q[nx - 2] = P[pnx - 1];
      q[nx - 1] = 0.5 * (P[pnx - 1] + P[0]);
    } else {
      for (int I = 0; I + 1 < pnx; ++I) {
        q[2 * I] = 0.5 * (P[I] + Pa[I]);
        q[2 * I + 1] = 0.5 * (P[I + 1] + Pa[I]);  // midpoint of the coarse diagonal
      }
      q[nx - 2] = 0.5 * (P[pnx - 1] + Pa[pnx - 1]);
      q[nx - 1] = 0.5 * (P[0] + Pa[pnx - 1]);
    }
  }
  // Per triangle s_T = |T| (q_a + q_b + q_c)/3 / h = h (q_a + q_b + q_c)/6 (the 1/h of ∇φ folded in).
  const double c = m_.h / 6.0;
#pragma omp parallel for schedule(static)
  for (int j = 0; j < ny; ++j) {
    const double* a = &fine_[std::size_t(j) * nx];
    const double* b = &fine_[std::size_t(j + 1) * nx];
    double* L = &tri_lower_[std::size_t(j) * nx];
    double* U = &tri_upper_[std::size_t(j) * nx];
    for (int i = 0; i + 1 < nx; ++i) {
      L[i] = c * (a[i] + a[i + 1] + b[i]);
      U[i] = c * (a[i + 1] + b[i + 1] + b[i]);
    }
    L[nx - 1] = c * (a[nx - 1] + a[0] + b[nx - 1]);
    U[nx - 1] = c * (a[0] + b[0] + b[nx - 1]);
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
  for (int j = 1; j < ny; ++j) {
    const double* L = &tri_lower_[std::size_t(j) * nx];
    const double* U = &tri_upper_[std::size_t(j) * nx];
    const double* Ld = &tri_lower_[std::size_t(j - 1) * nx];
    const double* Ud = &tri_upper_[std::size_t(j - 1) * nx];
    double* o1 = &g1[std::size_t(j) * nx];
    double* o2 = &g2[std::size_t(j) * nx];
    auto gradient = [&](int i, int im) {
      o1[i] = -L[i] + L[im] + Ud[im] - Ud[i];
      o2[i] = -L[i] + Ld[i] - U[im] + Ud[im];
    };
    gradient(0, nx - 1);
    for (int i = 1; i < nx; ++i) gradient(i, i - 1);
  }
}

}  // namespace rbc
