#include "io/vtk.hpp"

#include <fstream>
#include <stdexcept>

namespace rbc {

void write_velocity_vtk(const std::string& path, const ChannelMesh& m, const VelocityField& u, double t) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path);
  f << "# vtk DataFile Version 3.0\nrbcflow velocity at t = " << t << " s\nASCII\nDATASET STRUCTURED_POINTS\n";
  f << "DIMENSIONS " << m.nx << " " << m.ny + 1 << " 1\nORIGIN 0 0 0\nSPACING " << m.h << " " << m.h << " 1\n";
  f << "POINT_DATA " << m.velocity_nodes() << "\nVECTORS velocity double\n";
  f.precision(9);
  for (std::size_t n = 0; n < m.velocity_nodes(); ++n) f << u.u1[n] << " " << u.u2[n] << " 0\n";
}

}  // namespace rbc
