#include "fictitious_domain/obstacles.hpp"

#include <cmath>

namespace rbc {

double nearest_mesh_line(double coordinate, double h) { return std::round(coordinate / h) * h; }
bool on_mesh_line(double coordinate, double h) { return std::abs(coordinate - nearest_mesh_line(coordinate, h)) <= 1e-6 * h; }

ObstacleGeometry::ObstacleGeometry(const ChannelMesh& mesh, std::vector<Obstacle> obstacles)
    : m_(mesh), obstacles_(std::move(obstacles)), mask_(std::size_t(mesh.nx) * (mesh.ny - 1), 0) {
  const int nx = m_.nx, rows = m_.ny - 1;
  for (const Obstacle& o : obstacles_) {
    const int i0 = int(std::lround(o.x[0] / m_.h)), i1 = int(std::lround(o.x[1] / m_.h));
    const int j0 = std::max(1, int(std::lround(o.y[0] / m_.h))), j1 = std::min(m_.ny - 1, int(std::lround(o.y[1] / m_.h)));
    const int columns = std::min(i1 - i0 + 1, nx);  // a block over the whole length covers every column once
    for (int j = j0; j <= j1; ++j)
      for (int c = 0; c < columns; ++c) mask_[std::size_t(j - 1) * nx + m_.wrap(i0 + c)] = 1;
  }
  for (int r = 0; r < rows; ++r)
    for (int i = 0; i < nx; ++i) {
      const int k = r * nx + i;
      if (!mask_[std::size_t(k)]) continue;
      nodes_.push_back(k);
      // Neighbours on interior rows only: wall rows hold data, not unknowns.
      bool deep = mask_[std::size_t(r * nx + m_.wrap(i - 1))] && mask_[std::size_t(r * nx + m_.wrap(i + 1))];
      if (r > 0) deep = deep && mask_[std::size_t((r - 1) * nx + i)];
      if (r + 1 < rows) deep = deep && mask_[std::size_t((r + 1) * nx + i)];
      (deep ? deep_ : ring_).push_back(k);
    }
}

namespace {

// Does the periodic image of x (channel length L) lie in the obstacle's x-range [a, b + slack]?
bool in_x_range(const Obstacle& o, double x, double L, double slack) {
  if (o.x[1] - o.x[0] >= L) return true;
  const double s = image_in_period(x, L, o.x[0]);  // the image of x in [a, a + L)
  return s <= o.x[1] + slack;
}

}  // namespace

bool ObstacleGeometry::contains(double x, double y) const {
  for (const Obstacle& o : obstacles_)
    if (y >= o.y[0] && y <= o.y[1] && in_x_range(o, x, m_.length, 0.0)) return true;
  return false;
}

double ObstacleGeometry::open_height(double x) const {
  double open = m_.height;
  for (const Obstacle& o : obstacles_)
    if (in_x_range(o, x, m_.length, 1e-9 * m_.h)) open -= o.y[1] - o.y[0];
  return open;
}

double ObstacleGeometry::blocked_area() const {
  double a = 0;
  for (const Obstacle& o : obstacles_) a += (o.x[1] - o.x[0]) * (o.y[1] - o.y[0]);
  return a;
}

std::vector<double> section_fluxes(const ChannelMesh& mesh, const VelocityField& u) {
  std::vector<double> q(std::size_t(mesh.nx), 0.0);
  for (int i = 0; i < mesh.nx; ++i) {
    // Trapezoid over the column's nodes: exact for u1 linear between them.
    double s = 0.5 * (u.u1[mesh.v(i, 0)] + u.u1[mesh.v(i, mesh.ny)]);
    for (int j = 1; j < mesh.ny; ++j) s += u.u1[mesh.v(i, j)];
    q[std::size_t(i)] = s * mesh.h;
  }
  return q;
}

PartVelocities part_velocities(const ObstacleGeometry& g, const VelocityField& u) {
  const ChannelMesh& m = g.mesh();
  const std::vector<double> q = section_fluxes(m, u);
  PartVelocities p;
  // A node of a section is outside the passage when it lies in an obstacle's closed x-range and in
  // its y-range off the face that meets the fluid (a block on a wall keeps its free face's row and
  // drops the wall row beneath it), so each narrow section counts the passage and its two
  // bounding rows, as each wide section counts H and the two wall rows.
  auto outside_passage = [&](double x, double y) {
    const double e = 1e-6 * m.h;
    for (const Obstacle& o : g.obstacles()) {
      if (!in_x_range(o, x, m.length, 1e-9 * m.h)) continue;  // the sections open_height counts as the block's
      const bool free_below = o.y[0] > e, free_above = o.y[1] < m.height - e;
      if (y > o.y[0] + e && y < o.y[1] - e) return true;
      if (std::abs(y - o.y[0]) <= e && !free_below) return true;
      if (std::abs(y - o.y[1]) <= e && !free_above) return true;
    }
    return false;
  };
  long wide_nodes = 0, narrow_nodes = 0;
  for (int i = 0; i < m.nx; ++i) {
    const double open = g.open_height(m.x(i));
    const bool narrow = open < m.height - 1e-9 * m.h;
    (narrow ? p.narrow : p.wide) += q[std::size_t(i)] / open;
    (narrow ? p.narrow_flux : p.wide_flux) += q[std::size_t(i)];
    (narrow ? p.narrow_sections : p.wide_sections) += 1;
    (narrow ? p.narrow_height : p.wide_height) = open;
    for (int j = 0; j <= m.ny; ++j)
      if (!outside_passage(m.x(i), j * m.h)) {
        (narrow ? p.narrow_nodal : p.wide_nodal) += u.u1[m.v(i, j)];
        ++(narrow ? narrow_nodes : wide_nodes);
      }
  }
  p.narrow_nodal = narrow_nodes ? p.narrow_nodal / double(narrow_nodes) : NAN;  // a part without nodes measures nothing
  p.wide_nodal = wide_nodes ? p.wide_nodal / double(wide_nodes) : NAN;
  if (p.narrow_sections) {
    p.narrow /= p.narrow_sections;
    p.narrow_flux /= p.narrow_sections;
  }
  if (p.wide_sections) {
    p.wide /= p.wide_sections;
    p.wide_flux /= p.wide_sections;
  }
  return p;
}

}  // namespace rbc
