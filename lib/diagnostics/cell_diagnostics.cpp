#include "diagnostics/cell_diagnostics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rbc {

namespace {
// Where the horizontal line x2 = y crosses the closed polygon: every crossing's x1.
std::vector<double> crossings_at_y(const Points& r, double y) {
  std::vector<double> xs;
  for (std::size_t i = 0, n = r.size(); i < n; ++i) {
    const auto& p = r[i];
    const auto& q = r[(i + 1) % n];
    if ((p.y() - y) * (q.y() - y) < 0 || (p.y() == y && q.y() != y)) {
      const double t = (y - p.y()) / (q.y() - p.y());
      xs.push_back(p.x() + t * (q.x() - p.x()));
    }
  }
  std::sort(xs.begin(), xs.end());
  return xs;
}
std::vector<double> crossings_at_x(const Points& r, double x) {
  Points s(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) s[i] = {r[i].y(), r[i].x()};
  return crossings_at_y(s, x);
}
}  // namespace

ShapeDescriptor describe_shape(const Points& r) {
  ShapeDescriptor d;
  const Eigen::Vector2d c = area_centroid(r);
  double xmin = std::numeric_limits<double>::max(), xmax = -xmin, ymin = xmin, ymax = -xmin;
  for (const auto& p : r) {
    xmin = std::min(xmin, p.x()); xmax = std::max(xmax, p.x());
    ymin = std::min(ymin, p.y()); ymax = std::max(ymax, p.y());
  }
  d.length = xmax - xmin;
  d.width = ymax - ymin;
  const auto xs = crossings_at_y(r, c.y());
  const auto ys = crossings_at_x(r, c.x());
  if (xs.size() >= 2) {
    d.rear_concavity = (xs.front() - xmin) / d.length;
    d.front_concavity = (xmax - xs.back()) / d.length;
  }
  if (ys.size() >= 2) d.side_concavity = ((ymax - ys.back()) + (ys.front() - ymin)) / (2 * d.width);
  d.fore_aft = (c.x() - 0.5 * (xmin + xmax)) / d.length;
  const double kr = d.rear_concavity, kf = d.front_concavity, ks = d.side_concavity, a = d.fore_aft;
  if (kr > 0.05 && kf < 0.02) d.kind = "parachute";
  else if (ks > 0.02 && kr < 0.02 && kf < 0.02) d.kind = "biconcave";
  else if (kr <= 0.05 && ks <= 0.05 && a < -0.01) d.kind = "bullet";
  else if (std::max({kr, kf, ks}) < 0.02 && std::abs(a) <= 0.01) d.kind = "round";
  else d.kind = "other";
  return d;
}

OwnFrameShape describe_shape_in_own_frame(const Points& r) {
  OwnFrameShape o;
  const Eigen::Vector2d c = area_centroid(r);
  // Second moments of the enclosed area about the centroid (Green's theorem over the polygon's
  // edges); dividing by the signed area makes them independent of the nodes' orientation.
  double a = 0, ixx = 0, iyy = 0, ixy = 0;  // ∫x², ∫y², ∫xy
  for (std::size_t i = 0, n = r.size(); i < n; ++i) {
    const Eigen::Vector2d p = r[i] - c, q = r[(i + 1) % n] - c;
    const double cross = p.x() * q.y() - q.x() * p.y();
    a += cross / 2;
    ixx += cross * (p.x() * p.x() + p.x() * q.x() + q.x() * q.x()) / 12;
    iyy += cross * (p.y() * p.y() + p.y() * q.y() + q.y() * q.y()) / 12;
    ixy += cross * (p.x() * q.y() + 2 * p.x() * p.y() + 2 * q.x() * q.y() + q.x() * p.y()) / 24;
  }
  ixx /= a;
  iyy /= a;
  ixy /= a;
  o.angle = 0.5 * std::atan2(2 * ixy, ixx - iyy);  // the direction of the largest second moment
  const double cs = std::cos(o.angle), sn = std::sin(o.angle);
  Points s(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) {
    const Eigen::Vector2d d = r[i] - c;
    s[i] = {cs * d.x() + sn * d.y(), -sn * d.x() + cs * d.y()};
  }
  const ShapeDescriptor d = describe_shape(s);
  const Eigen::Vector2d c2 = area_centroid(s);
  const auto ys = crossings_at_x(s, c2.x());
  double ymin = std::numeric_limits<double>::max(), ymax = -ymin;
  for (const auto& p : s) {
    ymin = std::min(ymin, p.y());
    ymax = std::max(ymax, p.y());
  }
  if (ys.size() >= 2) {
    o.top_dimple = (ymax - ys.back()) / d.width;
    o.bottom_dimple = (ys.front() - ymin) / d.width;
  }
  o.end_concavity = std::max(d.rear_concavity, d.front_concavity);
  o.biconcave = o.top_dimple > 0.02 && o.bottom_dimple > 0.02 && o.end_concavity < 0.02;
  return o;
}

CellState measure_cell(const Cell& c, double l0) {
  CellState s;
  s.centroid = area_centroid(c.nodes);
  s.area = enclosed_area(c.nodes);
  s.perimeter = perimeter(c.nodes);
  s.area_drift = s.area / c.prepared_area - 1.0;
  s.max_strain = max_strain(c.nodes, l0);
  s.shape = describe_shape(c.nodes);
  s.own_frame = describe_shape_in_own_frame(c.nodes);
  return s;
}

double hematocrit_percent(const std::vector<Cell>& cells, double fluid_area) {
  double a = 0;
  for (const Cell& c : cells) a += enclosed_area(c.nodes);
  return 100.0 * a / fluid_area;
}

WallGaps wall_gaps(const std::vector<Cell>& cells, double height) {
  WallGaps g{height, height};
  for (const Cell& c : cells)
    for (const auto& r : c.nodes) {
      g.lower = std::min(g.lower, r.y());
      g.upper = std::min(g.upper, height - r.y());
    }
  return g;
}

}  // namespace rbc
