#include "membrane/membrane_repulsion.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace rbc {

RepulsionCount add_membrane_repulsion(const std::vector<Cell>& cells, double L, double H, const MembraneRepulsion& rep,
                                      std::vector<Points>& F) {
  RepulsionCount count;
  if (!rep.on()) return count;
  const double rho = rep.range, s = rep.strength;
  auto push = [&](double d) { return s * (1 - d / rho) * (1 - d / rho); };
  // The walls.
  for (std::size_t k = 0; k < cells.size(); ++k)
    for (std::size_t i = 0; i < cells[k].nodes.size(); ++i) {
      const double y = cells[k].nodes[i].y();
      if (y < rho) { F[k][i].y() += push(std::max(y, 0.0)); ++count.wall_nodes; }
      if (H - y < rho) { F[k][i].y() -= push(std::max(H - y, 0.0)); ++count.wall_nodes; }
    }
  if (cells.size() < 2) return count;
  // Between cells: every node in a bin of side ≥ ρ (x1 wrapped into [0, L)), each node against
  // the nodes of other cells in its bin and the 8 around it (bins wrap in x1), each pair once.
  // (Fewer than 3 bins along x1: one, so that no neighbour bin is visited twice through the wrap.)
  const int bx = int(std::floor(L / rho)) >= 3 ? int(std::floor(L / rho)) : 1, by = std::max(1, int(std::floor(H / rho))) + 2;
  const double wx = L / bx, wy = H / (by - 2);  // ≥ ρ each
  struct Ref { int cell, node; double x, y; };
  std::unordered_map<long, std::vector<Ref>> bins;
  auto bin_of = [&](int ix, int iy) { return long(iy) * bx + ((ix % bx) + bx) % bx; };
  for (std::size_t k = 0; k < cells.size(); ++k)
    for (std::size_t i = 0; i < cells[k].nodes.size(); ++i) {
      const auto& r = cells[k].nodes[i];
      const double x = r.x() - L * std::floor(r.x() / L);
      const int ix = std::min(bx - 1, int(x / wx)), iy = std::clamp(int(std::floor(r.y() / wy)) + 1, 0, by - 1);
      bins[bin_of(ix, iy)].push_back({int(k), int(i), x, r.y()});
    }
  for (const auto& [key, here] : bins) {
    const int ix = int(key % bx), iy = int(key / bx);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (iy + dy < 0 || iy + dy >= by) continue;
        const long other = bin_of(ix + dx, iy + dy);
        if (other < key || (bx == 1 && dx != 0)) continue;  // each pair of bins once
        const auto it = bins.find(other);
        if (it == bins.end()) continue;
        for (const Ref& a : here)
          for (const Ref& b : it->second) {
            if (a.cell == b.cell) continue;
            if (other == key && a.cell > b.cell) continue;  // each pair once within a bin
            double ex = a.x - b.x;
            ex -= L * std::round(ex / L);
            const double ey = a.y - b.y, d = std::hypot(ex, ey);
            if (d >= rho || d == 0) continue;
            const double f = push(d);
            F[a.cell][a.node] += f * Eigen::Vector2d(ex, ey) / d;
            F[b.cell][b.node] -= f * Eigen::Vector2d(ex, ey) / d;
            ++count.node_pairs;
          }
      }
  }
  return count;
}

}  // namespace rbc
