#pragma once
// A scene in motion: the parts of the method the scene needs, advanced by the study's Lie scheme.
// A cell-free channel composes the fluid alone (no membrane code, no multiplier).
#include <string>

#include "fluid/channel_flow.hpp"
#include "scene/scene.hpp"

namespace rbc {

// A run that cannot go on (instability): the message names the cause and the time.
struct RunFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Simulation {
 public:
  explicit Simulation(const Scene& scene);

  // One step of the study's Lie scheme, tⁿ → tⁿ⁺¹.
  void step();
  // Stops the run (RunFailure) on non-finite values or a CFL number above the stability limit.
  void check_health() const;

  const ChannelFlow& flow() const { return flow_; }
  const Scene& scene() const { return scene_; }
  double time() const { return flow_.time(); }
  long steps() const { return flow_.steps(); }
  int last_cg_iterations() const { return last_projection_.iterations; }

 private:
  Scene scene_;
  ChannelFlow flow_;
  ProjectionReport last_projection_;
};

}  // namespace rbc
