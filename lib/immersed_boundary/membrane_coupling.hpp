#pragma once
// The membranes' part of one Lie step, whichever coupling a scene chose ([time] coupling):
//
//   step 2:         r^{n+1} = rⁿ + Δt U(rⁿ),  f_B^{n+1} = Σ_i F_i(r^{n+1}) D_h(x − r_i^{n+1})   (step)
//   after step 4:   the change of u^{n+1} the coupling adds                   (implicit_correction)
//
// The study's explicit coupling (explicit_coupling.hpp) adds nothing after step 4; the
// semi-implicit one (semi_implicit/semi_implicit_coupling.hpp; not in the study) moves and spreads
// the same way, then adds step 4's response to its implicit spring force. Simulation::step calls
// the two through this interface and does not ask which one it has.
#include <vector>

#include "io/checkpoint.hpp"
#include "membrane/cell.hpp"
#include "mesh/channel_mesh.hpp"

namespace rbc {

class ExplicitMembraneStep;

class MembraneCoupling {
 public:
  virtual ~MembraneCoupling() = default;
  // Step 2: moves every cell with u (= u^{n+1/3}) over dt; returns f_B^{n+1} for step 4 (N/m³).
  virtual const VelocityField& step(std::vector<Cell>& cells, const VelocityField& u, double dt) = 0;
  // After step 4, u = u^{n+1} of the explicit force: the velocity change (m/s) that completes
  // u^{n+1}, or null where the coupling adds none.
  virtual const VelocityField* implicit_correction(const std::vector<Cell>& cells, const VelocityField& u) = 0;
  // Step 2's mover: the study's explicit step itself, which the semi-implicit coupling moves and
  // spreads with too (so the scene's membrane repulsion is set, and counted, on it for either).
  virtual ExplicitMembraneStep& membrane_move() = 0;
  // Step 4 has a multiplier (obstacles, disks): the fluid is no longer invariant under shifts in x1.
  virtual void set_fluid_not_x1_invariant() {}
  // Iterations of the coupling's last solve (0: none).
  virtual int last_iterations() const { return 0; }
  // Checkpoints: what the coupling carries from step to step besides the cells (nothing by default).
  virtual void save(CheckpointWriter&) const {}
  virtual void load(CheckpointReader&, const std::vector<Cell>&) {}
};

}  // namespace rbc
