#pragma once
// Immersed-boundary transfer between membrane nodes and the velocity mesh (the study's Eqs. (10)-(14)):
//
//   spread       f_B(x) = Σ_i F_i D_h(x − r_i)               (10)   F_i in N/m → f_B in N/m³
//   interpolate  U(r_i) = Σ_x h² u(x) D_h(x − r_i)           (13)
//   move         r_i^{n+1} = r_i^n + Δt U(r_i^n)             (14)
//
// Periodic in x1 (node positions are kept unwrapped; the stencil wraps). Walls: the 4 × 4 stencil
// is truncated to the mesh nodes that exist (rows 0..ny); wall nodes carry the prescribed wall
// velocity in the interpolation, and force spread onto them is dropped (the wall velocity is
// prescribed, so no force can act there). Spreading and interpolation use the same weights at the
// same positions, so with zero wall velocity they are adjoint in the lumped inner product:
// Σ_n h² (S F)_n · u_n = Σ_i F_i · (J u)_i.
#include <limits>
#include <utility>
#include <vector>

#include "mesh/channel_mesh.hpp"
#include "membrane/spring_membrane.hpp"

namespace rbc {

// The 4 × 4 stencil of one node: first column and row, and the weights φ in each
// direction. Computing it is most of the cost of a transfer; a solver that spreads and
// interpolates many times at fixed positions computes the stencils once (node_stencils).
struct NodeStencil {
  int i0, j0;  // i0 wrapped into [0, nx) (nx is even, so its parity is the unwrapped one's)
  double wx[4], wy[4];
};
void node_stencils(const ChannelMesh& mesh, const Points& r, std::vector<NodeStencil>& stencils);

// Spreading (10) is one loop over the stencils (immersed_boundary.cpp), in two layouts:
// adds the spread f_B of forces F at positions r (or at their stencils) to field (interior nodes only) ...
void spread_forces(const ChannelMesh& mesh, const Points& r, const Points& F, VelocityField& field);
void spread_forces(const ChannelMesh& mesh, const std::vector<NodeStencil>& r, const Points& F, VelocityField& field);
// ... or adds h² f_B (F in N/m, (x, y) of node i at F[2i], F[2i + 1]) to two arrays over the
// interior rows j = 1..ny-1 only (x1 fastest; the layout of step 4's right-hand sides): f1 gets
// the x1 component, f2 the x2 one.
void spread_forces_interior(const ChannelMesh& mesh, const std::vector<NodeStencil>& r, const double* F, double* f1, double* f2);
// Interpolation (13), U(r_i) for every node, is one sum over the stencils too (immersed_boundary.cpp),
// here from a field over the mesh, in StencilFootprint::interpolate from values at the footprint.
void interpolate_velocity(const ChannelMesh& mesh, const VelocityField& u, const Points& r, Points& U);
void interpolate_velocity(const ChannelMesh& mesh, const VelocityField& u, const std::vector<NodeStencil>& r, Points& U);

// The mesh nodes under a set of cells' stencils, each once: J u needs u there only, so a field
// that costs a sweep over the mesh (the projected velocity P w of the semi-implicit coupling) can
// be made at these nodes instead when they are few. Rows beyond the walls are left out, as
// interpolate_velocity leaves them out.
class StencilFootprint {
 public:
  // false (and the footprint unusable) as soon as it would hold more than max_nodes nodes: a
  // caller that takes it only when small stops there rather than walk every cell's stencils.
  bool build(const ChannelMesh& mesh, const std::vector<std::vector<NodeStencil>>& stencils,
             std::size_t max_nodes = std::numeric_limits<std::size_t>::max());
  const std::vector<std::pair<int, int>>& nodes() const { return nodes_; }  // (i, j)
  // J u at cell c's nodes from u's values at nodes() (v1[s], v2[s] at nodes()[s]): interpolate_velocity's
  // sums, in its order (same bits as J of a field holding those values).
  void interpolate(int c, const std::vector<NodeStencil>& stencils, const double* v1, const double* v2, Points& U) const;

 private:
  std::vector<int> slot_of_;                 // mesh node → its place in nodes_ (−1 elsewhere)
  std::vector<std::pair<int, int>> nodes_;
  std::vector<std::vector<int>> slots_;      // per cell: 16 per node, row by row (−1 beyond the walls)
};

}  // namespace rbc
