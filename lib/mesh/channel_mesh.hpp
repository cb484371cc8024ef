#pragma once
// The uniform triangulation of the channel Ω = (0, L) × (0, H) (the study's Section 2.4).
//
// T_h: the square grid of size h, nx = L/h cells along x1 (periodic) and ny = H/h across,
// each square [i, i+1] × [j, j+1] cut by the diagonal from (i+1, j) to (i, j+1):
//   lower triangle (i, j), (i+1, j), (i, j+1);  upper triangle (i+1, j), (i+1, j+1), (i, j+1).
// Velocity is P1 on T_h: nodes (i h, j h), i = 0..nx-1 (periodic), j = 0..ny (j = 0, ny on walls).
// T_2h is the same construction with size 2h; it is the coarse mesh that T_h refines by
// midpoints ("P1-iso-P2"). Pressure is P1 on T_2h: nodes (2 I h, 2 J h), I = 0..nx/2-1, J = 0..ny/2.
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace rbc {

// The channel is periodic in x1 with period L: x and x + kL (k an integer) are the same point.
// The whole periods that bring x nearest to c, and the image of x there, in [c − L/2, c + L/2]:
//   s = −L round((x − c)/L),   x + s;
// with c = 0 the image is the shortest form of an offset x between two points.
inline double shift_nearest(double x, double L, double c = 0.0) { return -L * std::round((x - c) / L); }
inline double nearest_image(double x, double L, double c = 0.0) { return x + shift_nearest(x, L, c); }
// The whole periods that bring x into [a, a + L), and the image of x there:
//   s = −L floor((x − a)/L),   x + s.
inline double shift_into_period(double x, double L, double a = 0.0) { return -L * std::floor((x - a) / L); }
inline double image_in_period(double x, double L, double a = 0.0) { return x + shift_into_period(x, L, a); }
// The same for a node index i of a period of n nodes: i mod n in [0, n).
inline int wrap_index(int i, int n) { return ((i % n) + n) % n; }

struct ChannelMesh {
  double length = 0;  // L, m (period in x1)
  double height = 0;  // H, m
  double h = 0;       // mesh size of T_h, m
  int nx = 0;         // cells (= velocity nodes) along x1
  int ny = 0;         // cells across; velocity rows j = 0..ny

  // Builds the mesh; throws std::invalid_argument naming the quantity when h does not divide
  // L or H into an even number of cells (T_2h must exist) or when a size is not positive.
  static ChannelMesh make(double length, double height, double h);

  // Velocity nodes: row-major, x1 fastest, wall rows included.
  int velocity_rows() const { return ny + 1; }
  std::size_t velocity_nodes() const { return std::size_t(nx) * std::size_t(ny + 1); }
  std::size_t v(int i, int j) const { return std::size_t(j) * nx + std::size_t(wrap(i)); }
  int wrap(int i) const { return wrap_index(i, nx); }
  double x(int i) const { return i * h; }
  double y(int j) const { return j * h; }

  // Pressure nodes on T_2h.
  int pnx() const { return nx / 2; }
  int pny() const { return ny / 2 + 1; }
  std::size_t pressure_nodes() const { return std::size_t(pnx()) * std::size_t(pny()); }
  std::size_t p(int I, int J) const { return std::size_t(J) * pnx() + std::size_t(wrap_index(I, pnx())); }

  std::string describe() const;  // "160 x 80 cells, h = 0.125 um"
};

// A velocity field on T_h (both components, wall rows included), SI units (m/s).
struct VelocityField {
  std::vector<double> u1, u2;
  VelocityField() = default;
  explicit VelocityField(const ChannelMesh& m) : u1(m.velocity_nodes(), 0.0), u2(m.velocity_nodes(), 0.0) {}
};

}  // namespace rbc
