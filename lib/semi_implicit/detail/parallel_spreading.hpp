#pragma once
// How the semi-implicit coupling's products spread the cells' node forces in parallel
// (SemiImplicitMembraneStep::apply_full), apart from the method: the sums Σ_c S_c (K v)_c into
// step 4's two right-hand sides, each mesh node summing its cells in an order that does not
// depend on the thread count, so that every run keeps its bits.
//
// Where the cells are short against the channel (a wide channel), the channel is cut into
// kSlabs equal slabs along x1 and each cell goes to the slab of its mean x1: slabs two apart
// never touch the same nodes, so the even slabs spread at once into the same arrays, then the
// odd ones. Otherwise (narrow channels) each thread spreads a fixed share of the cells into its
// own arrays, added in thread order.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <omp.h>

#include "membrane/cell.hpp"
#include "mesh/channel_mesh.hpp"

namespace rbc::detail {

class ParallelSpreading {
 public:
  static constexpr int kSlabs = 4;  // even: two phases

  // Chooses the schedule for the cells where they are now (called once a step): slabs when no cell
  // reaches further than half a slab from its mean x1 (its stencils and a mesh cell of margin
  // included), else the per-thread arrays.
  void assign(const ChannelMesh& mesh, const std::vector<Cell>& cells) {
    const int ncells = int(cells.size());
    slab_cells_.clear();
    if (ncells < 2) return;
    const double slab = mesh.length / kSlabs;
    double reach = 0;
    std::vector<double> mean(ncells);
    for (int c = 0; c < ncells; ++c) {
      double sum = 0;
      for (const auto& r : cells[c].nodes) sum += r.x();
      mean[c] = sum / double(cells[c].nodes.size());
      for (const auto& r : cells[c].nodes) reach = std::max(reach, std::abs(r.x() - mean[c]));
    }
    if (2 * (reach + 3 * mesh.h) < slab) {
      slab_cells_.resize(kSlabs);
      for (int c = 0; c < ncells; ++c) {
        const double x = image_in_period(mean[c], mesh.length);
        slab_cells_[std::min(kSlabs - 1, int(x / slab))].push_back(c);
      }
    }
  }

  // spread(c, f1, f2) adds cell c's forces into the arrays f1, f2 (each `size` values); this adds
  // every cell's into f1, f2.
  template <class Spread>
  void run(int ncells, std::size_t size, double* f1, double* f2, const Spread& spread) {
    if (!slab_cells_.empty()) {
      for (int phase = 0; phase < 2; ++phase) {
#pragma omp parallel for schedule(static, 1)
        for (int s = phase; s < int(slab_cells_.size()); s += 2)
          for (int c : slab_cells_[s]) spread(c, f1, f2);
      }
      return;
    }
    // A fixed share per thread: the sum is the same from run to run for a given thread count. The
    // shares are of the team the runtime gives (OMP_DYNAMIC, OMP_THREAD_LIMIT or a nested region
    // may give fewer threads than asked for): every cell is spread, and only the arrays the team
    // filled are added.
    const int threads = std::max(1, std::min(omp_get_max_threads(), ncells));
    if (int(thread_rhs_.size()) != threads - 1) thread_rhs_.assign(threads - 1, std::vector<double>(2 * size));
    int team = 1;
#pragma omp parallel num_threads(threads)
    {
      const int t = omp_get_thread_num(), n = omp_get_num_threads();
      if (t == 0) team = n;
      double* g1 = t == 0 ? f1 : thread_rhs_[t - 1].data();
      double* g2 = t == 0 ? f2 : thread_rhs_[t - 1].data() + size;
      if (t > 0) std::fill(thread_rhs_[t - 1].begin(), thread_rhs_[t - 1].end(), 0.0);
      for (int c = t * ncells / n; c < (t + 1) * ncells / n; ++c) spread(c, g1, g2);
    }
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(size); ++k)
      for (int t = 1; t < team; ++t) {
        f1[k] += thread_rhs_[t - 1][k];
        f2[k] += thread_rhs_[t - 1][size + k];
      }
  }

 private:
  std::vector<std::vector<int>> slab_cells_;      // the cells of each slab (empty: per-thread arrays)
  std::vector<std::vector<double>> thread_rhs_;  // threads 1.. of the per-thread arrays (both components)
};

}  // namespace rbc::detail
