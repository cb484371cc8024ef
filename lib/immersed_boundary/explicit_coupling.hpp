#pragma once
// Step 2 of the Lie scheme with the study's explicit coupling ("explicit" in scenes):
//
//   r_i^{n+1} = r_i^n + Δt U(r_i^n),   U interpolated from u^{n+1/3}            (13)-(14)
//   F_i^{n+1} = −∂E/∂r_i (r^{n+1})                                             (8)
//   f_B^{n+1} = Σ_i F_i^{n+1} D_h(x − r_i^{n+1})   → the force of step 4       (10)
//
// The spring forces are explicit, so Δt is bounded by the membrane stiffness (the limits:
// experiments/stability_map, and paper/method/03_immersed_boundary.md). A scene's membrane
// repulsion (membrane_repulsion.hpp; not in the study) adds to F^{n+1} once every cell has moved.
#include <vector>

#include "immersed_boundary/immersed_boundary.hpp"
#include "immersed_boundary/membrane_coupling.hpp"
#include "membrane/cell.hpp"
#include "membrane/membrane_repulsion.hpp"
#include "mesh/channel_mesh.hpp"

namespace rbc {

class ExplicitMembraneStep final : public MembraneCoupling {
 public:
  ExplicitMembraneStep(const ChannelMesh& mesh, const MembraneModel& model);
  // Moves every cell with u (= u^{n+1/3}) over dt and returns f_B at the new positions.
  const VelocityField& step(std::vector<Cell>& cells, const VelocityField& u, double dt) override;
  // f_B of the cells where they are (the second half of step): (8), the repulsion, plus extra
  // node forces (N/m) when given, one Points per cell; (10) spread.
  const VelocityField& spread(const std::vector<Cell>& cells, const std::vector<Points>* extra = nullptr);
  // The study's coupling adds nothing after step 4.
  const VelocityField* implicit_correction(const std::vector<Cell>&, const VelocityField&) override { return nullptr; }
  ExplicitMembraneStep& membrane_move() override { return *this; }
  const VelocityField& force() const { return force_; }
  // The repulsion between membranes and from the walls (off unless set), channel L x H.
  void set_repulsion(const MembraneRepulsion& r, double L, double H) {
    repulsion_ = r;
    length_ = L;
    height_ = H;
  }
  // How many nodes and node pairs it acted on in the last step.
  const RepulsionCount& last_repulsion() const { return last_repulsion_; }
  // The transfer stencils of each cell's nodes at their new positions (as the last step left them).
  const std::vector<std::vector<NodeStencil>>& stencils() const { return stencils_; }

 private:
  ChannelMesh mesh_;
  MembraneModel model_;
  VelocityField force_;
  std::vector<Points> F_;  // each cell's node forces (N/m)
  std::vector<std::vector<NodeStencil>> stencils_;
  MembraneRepulsion repulsion_;
  double length_ = 0, height_ = 0;
  std::vector<Points> F_rep_;
  RepulsionCount last_repulsion_;
};

}  // namespace rbc
