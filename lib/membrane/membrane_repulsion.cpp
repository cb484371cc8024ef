#include "membrane/membrane_repulsion.hpp"

#include <algorithm>
#include <cmath>

#include "mesh/channel_mesh.hpp"

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
  // Between cells: every node in a bin of side ≥ ρ (x1 wrapped into [0, L)); each node gathers the
  // push of the nodes of other cells in its bin and the 8 around it (bins wrap in x1). Gathering
  // (each pair seen from both ends, e and −e) rather than scattering lets the nodes go in parallel
  // and sums each node's pushes in one fixed order (bins, then cells and nodes), whatever the
  // threads. (Fewer than 3 bins along x1: one, so that no neighbour bin is visited twice through
  // the wrap.) The bins are a counting sort of the nodes: no allocation per bin.
  const int bx = int(std::floor(L / rho)) >= 3 ? int(std::floor(L / rho)) : 1, by = std::max(1, int(std::floor(H / rho))) + 2;
  const double wx = L / bx, wy = H / (by - 2);  // ≥ ρ each
  struct Ref { int cell, node; double x, y; };
  std::vector<int> first_node(cells.size() + 1, 0);  // node index of each cell's first node
  for (std::size_t k = 0; k < cells.size(); ++k) first_node[k + 1] = first_node[k] + int(cells[k].nodes.size());
  const int total = first_node.back();
  std::vector<int> bin(total), start(std::size_t(bx) * by + 1, 0);
  std::vector<Ref> refs(total);
  for (std::size_t k = 0; k < cells.size(); ++k)
    for (std::size_t i = 0; i < cells[k].nodes.size(); ++i) {
      const auto& r = cells[k].nodes[i];
      const double x = image_in_period(r.x(), L);
      const int ix = std::min(bx - 1, int(x / wx)), iy = std::clamp(int(std::floor(r.y() / wy)) + 1, 0, by - 1);
      const int id = first_node[k] + int(i);
      bin[id] = iy * bx + ix;
      refs[id] = {int(k), int(i), x, r.y()};
      ++start[bin[id] + 1];
    }
  for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
  std::vector<Ref> sorted(total);  // by bin, in cell and node order within a bin
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int id = 0; id < total; ++id) sorted[fill[bin[id]]++] = refs[id];
  }
  long pairs = 0;
#pragma omp parallel for schedule(static) reduction(+ : pairs)
  for (int id = 0; id < total; ++id) {
    const Ref& a = refs[id];
    const int ix = bin[id] % bx, iy = bin[id] / bx;
    Eigen::Vector2d push_sum = Eigen::Vector2d::Zero();
    for (int dy = -1; dy <= 1; ++dy) {
      if (iy + dy < 0 || iy + dy >= by) continue;
      for (int dx = bx == 1 ? 0 : -1; dx <= (bx == 1 ? 0 : 1); ++dx) {
        const int other = (iy + dy) * bx + wrap_index(ix + dx, bx);
        for (int m = start[other]; m < start[other + 1]; ++m) {
          const Ref& b = sorted[m];
          if (a.cell == b.cell) continue;
          double ex = a.x - b.x;
          ex = nearest_image(ex, L);
          const double ey = a.y - b.y, d = std::hypot(ex, ey);
          if (d >= rho || d == 0) continue;
          push_sum += push(d) * Eigen::Vector2d(ex, ey) / d;
          pairs += a.cell < b.cell;  // each pair once
        }
      }
    }
    F[a.cell][a.node] += push_sum;
  }
  count.node_pairs = pairs;
  return count;
}

}  // namespace rbc
