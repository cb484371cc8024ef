#include "immersed_boundary/explicit_coupling.hpp"

#include <algorithm>

#include "immersed_boundary/immersed_boundary.hpp"

namespace rbc {

ExplicitMembraneStep::ExplicitMembraneStep(const ChannelMesh& mesh, const MembraneModel& model)
    : mesh_(mesh), model_(model), force_(mesh) {}

const VelocityField& ExplicitMembraneStep::step(std::vector<Cell>& cells, const VelocityField& u, double dt) {
  const int n = int(cells.size());
  // (13)-(14) Move the nodes with the interpolated velocity (each cell on its own: cells in parallel).
#pragma omp parallel if (n > 1)
  {
    Points U;
#pragma omp for schedule(static)
    for (int k = 0; k < n; ++k) {
      Cell& c = cells[k];
      interpolate_velocity(mesh_, u, c.nodes, U);
      for (std::size_t i = 0; i < c.nodes.size(); ++i) c.nodes[i] += dt * U[i];
    }
  }
  return spread(cells);
}

const VelocityField& ExplicitMembraneStep::spread(const std::vector<Cell>& cells, const std::vector<Points>* extra) {
  const int n = int(cells.size());
  std::fill(force_.u1.begin(), force_.u1.end(), 0.0);
  std::fill(force_.u2.begin(), force_.u2.end(), 0.0);
  stencils_.resize(cells.size());
  F_.resize(cells.size());
  // The scene's repulsion at the new positions (all cells moved first: it couples them).
  if (repulsion_.on()) {
    F_rep_.resize(cells.size());
    for (std::size_t k = 0; k < cells.size(); ++k) F_rep_[k].assign(cells[k].nodes.size(), Eigen::Vector2d::Zero());
    last_repulsion_ = add_membrane_repulsion(cells, length_, height_, repulsion_, F_rep_);
  }
  // (8) Forces at the new positions (cells in parallel) ...
#pragma omp parallel for schedule(static) if (n > 1)
  for (int k = 0; k < n; ++k) {
    const Cell& c = cells[k];
    membrane_energy(c.kb_scale == 1 ? model_ : model_of(model_, c.kb_scale), c.nodes, c.target_area, &F_[k]);
    if (repulsion_.on())
      for (std::size_t i = 0; i < F_[k].size(); ++i) F_[k][i] += F_rep_[k][i];
    if (extra)
      for (std::size_t i = 0; i < F_[k].size(); ++i) F_[k][i] += (*extra)[k][i];
    node_stencils(mesh_, c.nodes, stencils_[k]);
  }
  // ... (10) spread to the mesh, cell after cell (the sums in a fixed order whatever the threads).
  for (int k = 0; k < n; ++k) spread_forces(mesh_, stencils_[k], F_[k], force_);
  return force_;
}

}  // namespace rbc
