#pragma once
// Flow quantities the study reports (Re = ρUH/μ: the study's Section 2).
//   mean velocity  U = (1/(L H)) ∫_Ω u1 dx   (lumped quadrature: trapezoid rule), m/s
//   Reynolds       Re = ρ U H / μ
//
// The study does not say whether U counts the fluid inside the cells. For that
// question we also measure the plasma alone, section by section (x1 = x_i, each mesh column):
//   Q_p(x_i) = ∫ u1 dy over the parts of (0, H) outside every membrane   (u1 linear between the
//              column's nodes, integrated exactly over the parts),
//   H_p(x_i) = H − Σ chords of the cells on that section (the open height),
// and report the section averages  U_p = <Q_p>/H  (the plasma's flux per unit height) and
// U_p,open = <Q_p / H_p>  (the plasma's mean velocity over its own height).
//
// A third reading of "the averaged velocity in the channel": the arithmetic mean of u1 over the
// velocity nodes, the two wall rows (u = 0) included,
//   U_n = (1/(N_x (M + 1))) Σ_{i, j=0..M} u1(x_i, y_j)      (M = H/h intervals across),
// which on the uniform mesh is (M/(M+1)) U exactly, since the trapezoid rule gives the wall rows
// weight 1/2 and they vanish; we compute it from the nodes, as a reader of the study would.
#include <vector>

#include "fluid/channel_flow.hpp"
#include "membrane/spring_membrane.hpp"

namespace rbc {

double mean_velocity(const ChannelMesh& mesh, const VelocityField& u);
struct MeanVelocities {
  double p1 = 0, nodal = 0;  // U and U_n, m/s
};
MeanVelocities mean_velocities(const ChannelMesh& mesh, const VelocityField& u);  // both in one pass
double reynolds_number(double mean_velocity, const FluidProperties& fluid, double height);
double max_speed(const VelocityField& u);  // max over nodes of |u|, m/s
bool all_finite(const VelocityField& u);

struct PlasmaVelocity {
  double flux_per_height = 0;  // <Q_p> / H, m/s
  double over_open_height = 0; // <Q_p / H_p>, m/s
};
// membranes: closed polygons, x1 unwrapped (any multiple of L), counter-clockwise or not.
PlasmaVelocity plasma_velocity(const ChannelMesh& mesh, const VelocityField& u, const std::vector<const Points*>& membranes);

}  // namespace rbc
