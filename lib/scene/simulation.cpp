#include "scene/simulation.hpp"

#include <sstream>

#include "diagnostics/flow_diagnostics.hpp"

namespace rbc {

Simulation::Simulation(const Scene& scene) : scene_(scene), flow_(scene.flow_params()) {}

void Simulation::step() {
  last_projection_ = flow_.project();  // (1) quasi-Stokes projection → u^{n+1/3}, p^{n+1}
  /* (2) membrane: the scene has no cells */
  flow_.advect();                      // (3) wave-like advection → u^{n+2/3}
  flow_.diffuse();                     // (4) diffusion with the body force → u^{n+1}
}

void Simulation::check_health() const {
  const VelocityField& u = flow_.velocity();
  std::ostringstream s;
  if (!all_finite(u)) {
    s << "non-finite velocity at t = " << time() << " s (step " << steps() << ")";
    throw RunFailure(s.str());
  }
  const ChannelFlowParams& p = flow_.params();
  const double cfl = max_speed(u) * p.dt / (p.advection_substeps * p.mesh_size);
  if (cfl > 1.0) {
    s << "CFL: the advective CFL number " << cfl << " exceeds the wave-like step's stability limit 1 at t = "
      << time() << " s (step " << steps() << "); lower dt or raise [time] advection_substeps";
    throw RunFailure(s.str());
  }
}

}  // namespace rbc
