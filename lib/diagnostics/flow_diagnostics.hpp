#pragma once
// Flow quantities the study reports (SPEC section 1).
//   mean velocity  U = (1/(L H)) ∫_Ω u1 dx   (lumped quadrature: trapezoid rule), m/s
//   Reynolds       Re = ρ U H / μ
#include "fluid/channel_flow.hpp"

namespace rbc {

double mean_velocity(const ChannelMesh& mesh, const VelocityField& u);
double reynolds_number(double mean_velocity, const FluidProperties& fluid, double height);
double max_speed(const VelocityField& u);  // max over nodes of |u|, m/s
bool all_finite(const VelocityField& u);

}  // namespace rbc
