#include "membrane/membrane_crossing.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "mesh/channel_mesh.hpp"

namespace rbc {

namespace {

struct Box {
  double x0, x1, y0, y1;
};

Box box_of(const Points& r) {
  Box b{r[0].x(), r[0].x(), r[0].y(), r[0].y()};
  for (const auto& p : r) {
    b.x0 = std::min(b.x0, p.x());
    b.x1 = std::max(b.x1, p.x());
    b.y0 = std::min(b.y0, p.y());
    b.y1 = std::max(b.y1, p.y());
  }
  return b;
}

// (q − p) × (s − p): > 0 when s is left of the directed line p → q.
double orient(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& s) {
  return (q.x() - p.x()) * (s.y() - p.y()) - (q.y() - p.y()) * (s.x() - p.x());
}

// The shift (a multiple of L) that brings box b nearest to box a in x1.
double nearest_shift(const Box& a, const Box& b, double L) {
  if (L <= 0) return 0;
  return shift_nearest(0.5 * (b.x0 + b.x1), L, 0.5 * (a.x0 + a.x1));
}

bool boxes_overlap(const Box& a, const Box& b, double shift) {
  return a.x0 <= b.x1 + shift && b.x0 + shift <= a.x1 && a.y0 <= b.y1 && b.y0 <= a.y1;
}

// Where segment p → q meets segment r → s, if they do: p, q on opposite sides of r → s (or on it)
// and r, s on opposite sides of p → q (or on it).
std::optional<Eigen::Vector2d> segments_cross(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r,
                                              const Eigen::Vector2d& s) {
  const double o1 = orient(p, q, r), o2 = orient(p, q, s), o3 = orient(r, s, p), o4 = orient(r, s, q);
  if ((o1 > 0 && o2 > 0) || (o1 < 0 && o2 < 0) || (o3 > 0 && o4 > 0) || (o3 < 0 && o4 < 0)) return std::nullopt;
  const double den = o3 - o4;  // p + t (q − p) with t = o3 / (o3 − o4) on r → s
  return den != 0 ? Eigen::Vector2d(p + (o3 / den) * (q - p)) : p;
}

}  // namespace

std::optional<MembraneCrossing> membranes_cross(const Points& a, const Points& b, double L) {
  if (a.size() < 2 || b.size() < 2) return std::nullopt;
  const Box ba = box_of(a), bb = box_of(b);
  const double shift = nearest_shift(ba, bb, L);
  if (!boxes_overlap(ba, bb, shift)) return std::nullopt;
  // Only segments that reach into the boxes' common part can cross: collect those of each polygon
  // (b in a's frame), then test them pairwise.
  const Box common{std::max(ba.x0, bb.x0 + shift), std::min(ba.x1, bb.x1 + shift), std::max(ba.y0, bb.y0), std::min(ba.y1, bb.y1)};
  auto reaching = [&](const Points& r, double dx) {
    std::vector<std::size_t> k;
    for (std::size_t i = 0, n = r.size(); i < n; ++i) {
      const Eigen::Vector2d& p = r[i];
      const Eigen::Vector2d& q = r[(i + 1) % n];
      if (std::max(p.x(), q.x()) + dx >= common.x0 && std::min(p.x(), q.x()) + dx <= common.x1 && std::max(p.y(), q.y()) >= common.y0 &&
          std::min(p.y(), q.y()) <= common.y1)
        k.push_back(i);
    }
    return k;
  };
  const std::vector<std::size_t> sa = reaching(a, 0.0), sb = reaching(b, shift);
  const Eigen::Vector2d e1(shift, 0.0);
  const std::size_t na = a.size(), nb = b.size();
  for (std::size_t i : sa) {
    const Eigen::Vector2d& p = a[i];
    const Eigen::Vector2d& q = a[(i + 1) % na];
    const double sx0 = std::min(p.x(), q.x()), sx1 = std::max(p.x(), q.x());
    const double sy0 = std::min(p.y(), q.y()), sy1 = std::max(p.y(), q.y());
    for (std::size_t j : sb) {
      const Eigen::Vector2d r = b[j] + e1, s = b[(j + 1) % nb] + e1;
      // Segment boxes first (cheap), then the orientation test.
      if (std::max(r.x(), s.x()) < sx0 || std::min(r.x(), s.x()) > sx1 || std::max(r.y(), s.y()) < sy0 ||
          std::min(r.y(), s.y()) > sy1)
        continue;
      if (const auto at = segments_cross(p, q, r, s)) return MembraneCrossing{0, 0, i, j, *at};
    }
  }
  return std::nullopt;
}

std::optional<MembraneCrossing> membrane_crosses_itself(const Points& a) {
  // Sweep along x1: the segments sorted by their left end, so that a segment's box can overlap
  // only those of the segments that start before it ends (a few, not all N: this runs for every
  // cell at every step). Of the pairs that cross, the first in the order (i, then j) is returned,
  // as testing every pair in that order would; the same test, segment i first.
  const std::size_t n = a.size();
  if (n < 4) return std::nullopt;
  struct Segment {
    double x0, x1, y0, y1;
    std::size_t i;
  };
  thread_local std::vector<Segment> seg;
  seg.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& p = a[i];
    const Eigen::Vector2d& q = a[(i + 1) % n];
    seg[i] = {std::min(p.x(), q.x()), std::max(p.x(), q.x()), std::min(p.y(), q.y()), std::max(p.y(), q.y()), i};
  }
  std::sort(seg.begin(), seg.end(), [](const Segment& u, const Segment& v) { return u.x0 < v.x0 || (u.x0 == v.x0 && u.i < v.i); });
  std::optional<MembraneCrossing> first;
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t m = k + 1; m < n && seg[m].x0 <= seg[k].x1; ++m) {
      if (seg[m].y1 < seg[k].y0 || seg[m].y0 > seg[k].y1) continue;
      const std::size_t i = std::min(seg[k].i, seg[m].i), j = std::max(seg[k].i, seg[m].i);
      if (j == i + 1 || (i == 0 && j == n - 1)) continue;  // neighbours share a node
      if (first && (i > first->segment_a || (i == first->segment_a && j > first->segment_b))) continue;
      if (const auto at = segments_cross(a[i], a[i + 1], a[j], a[(j + 1) % n])) first = MembraneCrossing{0, 0, i, j, *at};
    }
  return first;
}

namespace {
// The first crossing in the order (a, b), a ≤ b, of the membranes get(0 .. count − 1): a membrane
// with itself first, then with the later ones whose boxes overlap; in parallel (this runs every
// step), each a on its own.
template <class Get>
std::optional<MembraneCrossing> first_crossing(std::size_t count, Get get, double L) {
  std::vector<Box> boxes(count);
  for (std::size_t k = 0; k < count; ++k) boxes[k] = get(k).empty() ? Box{} : box_of(get(k));
  std::vector<std::optional<MembraneCrossing>> found(count);
  const long n = long(count);
#pragma omp parallel for schedule(dynamic, 4) if (n > 8)
  for (long a = 0; a < n; ++a) {
    if (get(a).size() < 2) continue;
    if (auto c = membrane_crosses_itself(get(a))) {
      c->cell_a = c->cell_b = std::size_t(a);
      found[a] = c;
      continue;
    }
    for (long b = a + 1; b < n; ++b) {
      if (get(b).size() < 2) continue;
      if (!boxes_overlap(boxes[a], boxes[b], nearest_shift(boxes[a], boxes[b], L))) continue;
      if (auto c = membranes_cross(get(a), get(b), L)) {
        c->cell_a = std::size_t(a);
        c->cell_b = std::size_t(b);
        found[a] = c;
        break;
      }
    }
  }
  for (auto& f : found)
    if (f) return f;
  return std::nullopt;
}
}  // namespace

std::optional<MembraneCrossing> find_membrane_crossing(const std::vector<Points>& membranes, double L) {
  return first_crossing(membranes.size(), [&](std::size_t k) -> const Points& { return membranes[k]; }, L);
}

std::optional<MembraneCrossing> find_membrane_crossing(const std::vector<Cell>& cells, double L) {
  return first_crossing(cells.size(), [&](std::size_t k) -> const Points& { return cells[k].nodes; }, L);
}

}  // namespace rbc
