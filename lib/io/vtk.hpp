#pragma once
// ParaView (legacy VTK) files of the velocity on T_h: STRUCTURED_POINTS, one point per node.
#include <string>

#include "mesh/channel_mesh.hpp"

namespace rbc {
void write_velocity_vtk(const std::string& path, const ChannelMesh& mesh, const VelocityField& u, double t);
}
