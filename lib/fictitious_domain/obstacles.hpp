#pragma once
// Fixed obstacles of the fictitious-domain method (the study's eqs. (15)-(21)):
// axis-aligned rectangles ω = [a, b] × [c, d] inside the channel, through which the fluid mesh
// runs on (the fictitious domain) and on which step 4 enforces u = 0 by a multiplier.
//
// Collocation points, as the study places them: the velocity-mesh nodes inside ω farther than h/2
// from ∂ω, plus points on ∂ω (not on the channel walls) about h apart. We ask the rectangle's edges
// to lie on mesh lines (a scene whose edges do not is refused, naming the nearest mesh lines), so
// that the points on ∂ω, taken h apart from a corner, are mesh nodes too: the collocation points
// are then exactly the nodes of the closed rectangle off the walls, C, and B (the constraint
// ⟨l, u⟩ = 0 of the study) reads u at those nodes.
//
// C splits into its ring R (nodes with a 5-point neighbour outside C; the wall rows count as
// inside, their values are data) and its deep part D. At a node of D the velocity and its four
// neighbours all vanish, so step 4's equation there, (A u)_d = b_d + λ_d, gives λ_d = −b_d at
// once; the unknown multiplier lives on R (see dlm_obstacle_step.hpp).
#include <string>
#include <vector>

#include "mesh/channel_mesh.hpp"

namespace rbc {

struct Obstacle {
  double x[2] = {0, 0};  // [a, b], m
  double y[2] = {0, 0};  // [c, d], m
  // The wall the scene says the block stands on: "bottom", "top" or "" (none said; not checked).
  std::string wall;
};

// The nearest mesh line to a coordinate (m) and whether the coordinate lies on it (to 1e-6 h).
double nearest_mesh_line(double coordinate, double h);
bool on_mesh_line(double coordinate, double h);

class ObstacleGeometry {
 public:
  // Obstacles already validated (inside the channel, edges on mesh lines, not overlapping).
  ObstacleGeometry(const ChannelMesh& mesh, std::vector<Obstacle> obstacles);

  const ChannelMesh& mesh() const { return m_; }
  const std::vector<Obstacle>& obstacles() const { return obstacles_; }
  // Collocation nodes as interior-row indices (j − 1) nx + i (the layout of step 4's solver).
  const std::vector<int>& nodes() const { return nodes_; }
  const std::vector<int>& ring() const { return ring_; }
  const std::vector<int>& deep() const { return deep_; }
  bool covers(int i, int j) const { return j >= 1 && j < m_.ny && mask_[std::size_t(j - 1) * m_.nx + m_.wrap(i)]; }
  // Is the point (m; x1 taken modulo L) inside an obstacle (closed rectangle)?
  bool contains(double x, double y) const;
  // H minus the heights of the obstacles whose x-range holds x (closed), m: a section's open height.
  double open_height(double x) const;
  double blocked_area() const;  // m², the obstacles' total area (the fluid area is L H minus it)

 private:
  ChannelMesh m_;
  std::vector<Obstacle> obstacles_;
  std::vector<char> mask_;  // interior rows: 1 on C
  std::vector<int> nodes_, ring_, deep_;
};

// Mean velocity of the narrow part (sections whose open height is below H) and of the wide part
// (open height H): on each section x1 = x_i the flux Q_i = ∫ u1 dx2 (trapezoid over the column's
// nodes, exact for P1) over the open height, averaged over the part's sections, m/s. And the
// nodal reading (flow_diagnostics.hpp): the mean of u1 over the nodes of the part's sections in the
// open passage, its two bounding rows (u = 0: a block's free face or a wall) included.
struct PartVelocities {
  double wide = 0, narrow = 0;  // m/s
  double wide_nodal = 0, narrow_nodal = 0;  // m/s, the arithmetic mean of u1 over the part's nodes in the open passage (its walls' rows included)
  double wide_flux = 0, narrow_flux = 0;  // m²/s, the mean flux through a section of each part
  double wide_height = 0, narrow_height = 0;  // m (the parts' open heights)
  int wide_sections = 0, narrow_sections = 0;
};
PartVelocities part_velocities(const ObstacleGeometry& g, const VelocityField& u);
// Flux per section Q_i (m²/s), i = 0..nx−1.
std::vector<double> section_fluxes(const ChannelMesh& mesh, const VelocityField& u);

}  // namespace rbc
