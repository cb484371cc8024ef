#pragma once
// Two membranes crossing each other: the study's model has no force that keeps two
// cells apart except the fluid between them, and the immersed boundary lets a thin film of fluid
// (below a mesh cell) leak, so crowded cells can interpenetrate. A crossing is a geometric fact
// we test for directly: segment [r_i, r_{i+1}] of cell a and segment [s_j, s_{j+1}] of cell b
// (a ≠ b) intersect,
//
//   r_i + t (r_{i+1} − r_i) = s_j + u (s_{j+1} − s_j)   for some t, u in [0, 1],
//
// with x1 periodic of period L (each cell's nodes are unwrapped: a cell may sit anywhere in x1;
// b is compared with the image of it nearest to a). Broad phase: the cells' bounding boxes (with
// the periodic shift) must overlap; narrow phase: every pair of segments of the two polygons,
// by the signs of the cross products (orientation test). Two touching segments (a cross product
// exactly 0) count as crossing: the membranes met.
//
// A membrane that crosses itself (two segments of one cell that are not neighbours, i.e. share
// no node) is found the same way: a fold the springs' bending resistance should prevent, and a
// polygon whose area, chords and wall gaps no longer mean what they say.
#include <cstddef>
#include <optional>
#include <vector>

#include "membrane/cell.hpp"

namespace rbc {

struct MembraneCrossing {
  std::size_t cell_a = 0, cell_b = 0;      // a < b; a == b: the membrane crosses itself
  std::size_t segment_a = 0, segment_b = 0;  // segment i joins nodes i and i + 1 (mod N)
  Eigen::Vector2d point = Eigen::Vector2d::Zero();  // where they cross, m (cell a's frame in x1)
};

// The first crossing found (cells in order, then segments in order), or none. L: the channel's
// period in x1, m (0: not periodic).
std::optional<MembraneCrossing> find_membrane_crossing(const std::vector<Points>& membranes, double L);
std::optional<MembraneCrossing> find_membrane_crossing(const std::vector<Cell>& cells, double L);

// Whether a segment of closed polygon a crosses one of closed polygon b (b's nearest image in x1).
std::optional<MembraneCrossing> membranes_cross(const Points& a, const Points& b, double L);
// Whether two segments of closed polygon a that share no node cross (segment_a < segment_b).
std::optional<MembraneCrossing> membrane_crosses_itself(const Points& a);

}  // namespace rbc
