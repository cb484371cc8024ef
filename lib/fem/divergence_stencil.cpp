#include "fem/divergence_stencil.hpp"

#include <algorithm>
#include <type_traits>

#include <omp.h>

namespace rbc {

DivergenceStencil::DivergenceStencil(const ChannelMesh& mesh) : m_(mesh) {}

namespace {
// A thread's rolling rows (n values), kept from call to call.
double* rows_buffer(std::size_t n) {
  thread_local std::vector<double> buffer;
  if (buffer.size() < n) buffer.resize(n);
  return buffer.data();
}
}  // namespace

// Each thread makes its own share of the output rows in one sweep, keeping only the few rows of
// the intermediate stages (triangle and node moments, the prolongated pressure) that its next
// output row needs; a row at the edge of two shares is made by both threads, by the same
// expression. The loops wrap in x1 only in their first or last column, which is written out
// apart, so that the inner loops have no modulo or branch (the compiler vectorises them); every
// value is the same expression, summed in the same order, as in the straightforward three passes
// over the whole mesh that this replaced (same bits). Wide grid (320 x 160),: B 107-128
// → 53-60 us on one thread, 57-64 → 34-35 us on two; Bᵀ 65-74 → 57-58 and 36-40 → 30-36 us.
void DivergenceStencil::apply(const std::vector<double>& u1, const std::vector<double>& u2,
                              std::vector<double>& div) const {
  const int nx = m_.nx, ny = m_.ny, pnx = m_.pnx(), pny = m_.pny();
  const double c = m_.h / 6.0;  // |T| (1/h) / 3 with |T| = h²/2
  div.resize(m_.pressure_nodes());
#pragma omp parallel
  {
    const int threads = omp_get_num_threads(), t = omp_get_thread_num();
    const int J0 = t * pny / threads, J1 = (t + 1) * pny / threads;  // this thread's coarse rows
    double* buf = rows_buffer(std::size_t(7) * nx);
    double* L[2] = {buf, buf + nx};           // triangle moments of rows r (at r % 2)
    double* U[2] = {buf + 2 * nx, buf + 3 * nx};
    double* F[3] = {buf + 4 * nx, buf + 5 * nx, buf + 6 * nx};  // node moments of rows j (at j % 3)
    // Triangle moments |T| (∇·u)_T / 3 of the triangles between rows r and r + 1.
    auto triangles = [&](int r) {
      const double* a1 = &u1[std::size_t(r) * nx];
      const double* b1 = &u1[std::size_t(r + 1) * nx];
      const double* a2 = &u2[std::size_t(r) * nx];
      const double* b2 = &u2[std::size_t(r + 1) * nx];
      double* Lr = L[r % 2];
      double* Ur = U[r % 2];
      const double k = c;  // a local copy: the captured reference kept the loop from vectorising
      auto moments = [=](int i, int ip) {
        Lr[i] = k * (a1[ip] - a1[i] + b2[i] - a2[i]);
        Ur[i] = k * (b1[ip] - b1[i] + b2[ip] - a2[ip]);
      };
      for (int i = 0; i + 1 < nx; ++i) moments(i, i + 1);
      moments(nx - 1, 0);
    };
    // Node moments d_n of row j: the six triangles around node (i, j) (fewer on the walls).
    auto nodes = [&](int j) {
      const double* Lj = j < ny ? L[j % 2] : nullptr;  // row j (j < ny)
      const double* Uj = j < ny ? U[j % 2] : nullptr;
      const double* Ld = j > 0 ? L[(j - 1) % 2] : nullptr;  // row j − 1
      const double* Ud = j > 0 ? U[(j - 1) % 2] : nullptr;
      double* out = F[j % 3];
      auto node = [&](int i, int im) {
        double d = 0;
        if (j < ny) d += Lj[i] + Lj[im] + Uj[im];
        if (j > 0) d += Ld[i] + Ud[im] + Ud[i];
        out[i] = d;
      };
      node(0, nx - 1);
      for (int i = 1; i < nx; ++i) node(i, i - 1);
    };
    // Restriction to T_2h: weight 1 at (2I, 2J), 1/2 at (±1, 0), (0, ±1), (−1, +1), (+1, −1).
    auto restriction = [&](int J) {
      const int j = 2 * J;
      const double* row = F[j % 3];
      const double* below = j > 0 ? F[(j - 1) % 3] : nullptr;
      const double* above = j < ny ? F[(j + 1) % 3] : nullptr;
      double* out = &div[std::size_t(J) * pnx];
      // The walls' rows lack a neighbour row; each case is its own loop (no branch inside).
      auto rows = [&](auto has_below, auto has_above) {
        auto restrict_at = [=](int I, int ip, int im) {
          const int i = 2 * I;
          double s = row[i] + 0.5 * (row[ip] + row[im]);
          if constexpr (decltype(has_below)::value) s += 0.5 * (below[i] + below[ip]);
          if constexpr (decltype(has_above)::value) s += 0.5 * (above[i] + above[im]);
          out[I] = s;
        };
        restrict_at(0, 1, nx - 1);  // nx is even: only I = 0 wraps (to the left)
        for (int I = 1; I < pnx; ++I) restrict_at(I, 2 * I + 1, 2 * I - 1);
      };
      using yes = std::true_type;
      using no = std::false_type;
      if (below && above) rows(yes{}, yes{});
      else if (below) rows(yes{}, no{});
      else if (above) rows(no{}, yes{});
      else rows(no{}, no{});
    };
    if (J0 < J1) {
      // Fine rows 2 J0 − 1 … 2 (J1 − 1) + 1 (within the mesh); coarse row J is complete with its
      // fine row 2J + 1 (the top row, J = ny/2, with fine row ny).
      const int first = std::max(0, 2 * J0 - 1), last = std::min(ny, 2 * (J1 - 1) + 1);
      if (first > 0) triangles(first - 1);
      for (int j = first; j <= last; ++j) {
        if (j < ny) triangles(j);
        nodes(j);
        if (j % 2 == 1 && (j - 1) / 2 >= J0) restriction((j - 1) / 2);
        else if (j == ny) restriction(ny / 2);
      }
    }
  }
}

template <class Store>
void DivergenceStencil::transpose_rows(const std::vector<double>& p, Store store) const {
  const int nx = m_.nx, ny = m_.ny, pnx = m_.pnx();
  const double c = m_.h / 6.0;
#pragma omp parallel
  {
    const int threads = omp_get_num_threads(), t = omp_get_thread_num();
    const int r0 = 1 + t * (ny - 1) / threads, r1 = 1 + (t + 1) * (ny - 1) / threads;  // this thread's rows
    double* buf = rows_buffer(std::size_t(7) * nx);
    double* Q[3] = {buf, buf + nx, buf + 2 * nx};  // prolongated p of rows j (at j % 3)
    double* L[2] = {buf + 3 * nx, buf + 4 * nx};   // per-triangle sums of rows r (at r % 2)
    double* U[2] = {buf + 5 * nx, buf + 6 * nx};
    // Prolongation: q at every fine node of row j by P1 interpolation on T_2h. Even fine rows lie
    // on coarse row J, odd ones between J and J + 1; odd columns between I and I + 1 (I + 1 wraps
    // at the end).
    auto prolongate = [&](int j) {
      const int J = j / 2;
      const double* P = &p[std::size_t(J) * pnx];
      const double* Pa = j % 2 ? &p[std::size_t(J + 1) * pnx] : nullptr;  // coarse row J + 1
      double* q = Q[j % 3];
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
    };
    // Per triangle between rows r and r + 1: s_T = |T| (q_a + q_b + q_c)/3 / h = h (q_a + q_b + q_c)/6
    // (the 1/h of ∇φ folded in).
    auto triangles = [&](int r) {
      const double* a = Q[r % 3];
      const double* b = Q[(r + 1) % 3];
      double* Lr = L[r % 2];
      double* Ur = U[r % 2];
      for (int i = 0; i + 1 < nx; ++i) {
        Lr[i] = c * (a[i] + a[i + 1] + b[i]);
        Ur[i] = c * (a[i + 1] + b[i + 1] + b[i]);
      }
      Lr[nx - 1] = c * (a[nx - 1] + a[0] + b[nx - 1]);
      Ur[nx - 1] = c * (a[0] + b[0] + b[nx - 1]);
    };
    // (Bᵀp)_n = Σ_T s_T ∇φ_n|_T (in units of 1/h, already folded in):
    //   x1: −L(i,j) + L(i−1,j) + U(i−1,j−1) − U(i,j−1);   x2: −L(i,j) + L(i,j−1) − U(i−1,j) + U(i−1,j−1).
    auto gradient_row = [&](int j) {
      const double* Lj = L[j % 2];
      const double* Uj = U[j % 2];
      const double* Ld = L[(j - 1) % 2];
      const double* Ud = U[(j - 1) % 2];
      store(j, [&](int i, int im, double& a, double& b) {
        a = -Lj[i] + Lj[im] + Ud[im] - Ud[i];
        b = -Lj[i] + Ld[i] - Uj[im] + Ud[im];
      });
    };
    if (r0 < r1) {
      prolongate(r0 - 1);
      prolongate(r0);
      triangles(r0 - 1);
      for (int j = r0; j < r1; ++j) {
        prolongate(j + 1);
        triangles(j);
        gradient_row(j);
      }
    }
  }
}

void DivergenceStencil::apply_transpose(const std::vector<double>& p, std::vector<double>& g1,
                                        std::vector<double>& g2) const {
  const int nx = m_.nx;
  g1.resize(m_.velocity_nodes());
  g2.resize(m_.velocity_nodes());
  for (auto* g : {&g1, &g2}) {  // wall rows: not unknowns; the interior is overwritten below
    std::fill(g->begin(), g->begin() + nx, 0.0);
    std::fill(g->end() - nx, g->end(), 0.0);
  }
  transpose_rows(p, [&](int j, auto gradient) {
    double* o1 = &g1[std::size_t(j) * nx];
    double* o2 = &g2[std::size_t(j) * nx];
    gradient(0, nx - 1, o1[0], o2[0]);
    for (int i = 1; i < nx; ++i) gradient(i, i - 1, o1[i], o2[i]);
  });
}

void DivergenceStencil::add_transpose(const std::vector<double>& p, double c, const std::vector<double>& u1,
                                      const std::vector<double>& u2, std::vector<double>& out1, std::vector<double>& out2) const {
  const int nx = m_.nx;
  const std::size_t top = std::size_t(m_.ny) * nx;
  out1.resize(m_.velocity_nodes());
  out2.resize(m_.velocity_nodes());
  if (&out1 != &u1)  // wall rows: u (Bᵀ p is zero there)
    for (std::size_t k : {std::size_t(0), top})
      for (int i = 0; i < nx; ++i) {
        out1[k + i] = u1[k + i];
        out2[k + i] = u2[k + i];
      }
  transpose_rows(p, [&](int j, auto gradient) {
    const double* a1 = &u1[std::size_t(j) * nx];
    const double* a2 = &u2[std::size_t(j) * nx];
    double* o1 = &out1[std::size_t(j) * nx];
    double* o2 = &out2[std::size_t(j) * nx];
    auto at = [&](int i, int im) {
      double g1, g2;
      gradient(i, im, g1, g2);
      o1[i] = a1[i] + c * g1;
      o2[i] = a2[i] + c * g2;
    };
    at(0, nx - 1);
    for (int i = 1; i < nx; ++i) at(i, i - 1);
  });
}

void DivergenceStencil::transpose_at(const std::vector<double>& p, int i, int j, double& g1, double& g2) const {
  // transpose_rows' three stages at the one node: the prolongated pressure q of the fine nodes
  // around it (columns i − 1, i, i + 1 of rows j − 1, j, j + 1), the sums of the six triangles
  // that meet there, their weighted gradients.
  const int nx = m_.nx, pnx = m_.pnx();
  const double c = m_.h / 6.0;
  auto q = [&](int k, int r) {  // prolongate(r) at column k
    const int J = r / 2, I = k / 2, In = I + 1 < pnx ? I + 1 : 0;
    const double* P = &p[std::size_t(J) * pnx];
    if (r % 2 == 0) return k % 2 == 0 ? P[I] : 0.5 * (P[I] + P[In]);
    const double* Pa = &p[std::size_t(J + 1) * pnx];  // coarse row J + 1
    return k % 2 == 0 ? 0.5 * (P[I] + Pa[I]) : 0.5 * (P[In] + Pa[I]);
  };
  const int im = i > 0 ? i - 1 : nx - 1, ip = i + 1 < nx ? i + 1 : 0;
  const double d_i = q(i, j - 1), d_ip = q(ip, j - 1);               // row j − 1
  const double a_im = q(im, j), a_i = q(i, j), a_ip = q(ip, j);     // row j
  const double b_im = q(im, j + 1), b_i = q(i, j + 1);              // row j + 1
  // triangles(r): L(k) = c (a[k] + a[k+1] + b[k]), U(k) = c (a[k+1] + b[k+1] + b[k]) of rows r, r + 1.
  const double Lj = c * (a_i + a_ip + b_i), Ljm = c * (a_im + a_i + b_im), Ujm = c * (a_i + b_i + b_im);
  const double Ld = c * (d_i + d_ip + a_i), Udm = c * (d_i + a_i + a_im), Ud = c * (d_ip + a_ip + a_i);
  g1 = -Lj + Ljm + Udm - Ud;  // gradient_row
  g2 = -Lj + Ld - Ujm + Udm;
}

}  // namespace rbc
