#include "mesh/channel_mesh.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rbc {

namespace {
// Number of cells n = extent / h, required to be an even integer (so that T_2h exists).
int even_cell_count(double extent, double h, const char* what) {
  const double n = extent / h;
  if (!(n <= 1e6)) {  // also keeps the count within int
    std::ostringstream s;
    s << "channel " << what << "/h = " << n << " cells; at most 1e6 per direction";
    throw std::invalid_argument(s.str());
  }
  const double rounded = std::round(n);
  if (std::abs(n - rounded) > 1e-9 * std::max(1.0, n)) {
    std::ostringstream s;
    s << "mesh size h = " << h << " m does not divide the channel " << what << " " << extent
      << " m (" << what << "/h = " << n << " is not an integer)";
    throw std::invalid_argument(s.str());
  }
  const int cells = int(rounded);
  if (cells < 4 || cells % 2 != 0) {
    std::ostringstream s;
    s << "channel " << what << "/h = " << cells
      << " cells; P1-iso-P2 needs an even number of at least 4 cells (the pressure mesh has size 2h)";
    throw std::invalid_argument(s.str());
  }
  return cells;
}
}  // namespace

ChannelMesh ChannelMesh::make(double length, double height, double h) {
  if (!(std::isfinite(length) && length > 0)) throw std::invalid_argument("channel length must be positive and finite");
  if (!(std::isfinite(height) && height > 0)) throw std::invalid_argument("channel height must be positive and finite");
  if (!(std::isfinite(h) && h > 0)) throw std::invalid_argument("mesh size must be positive and finite");
  ChannelMesh m;
  m.length = length;
  m.height = height;
  m.h = h;
  m.nx = even_cell_count(length, h, "length");
  m.ny = even_cell_count(height, h, "height");
  return m;
}

std::string ChannelMesh::describe() const {
  std::ostringstream s;
  s << nx << " x " << ny << " cells, h = " << h * 1e6 << " um";
  return s.str();
}

}  // namespace rbc
