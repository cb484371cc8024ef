#pragma once
// What we measure on a cell (the quantities of the study's Section 3).
//
//   centroid     area-weighted centroid of the enclosed region (x1 unwrapped), m
//   area drift   s / s_prepared − 1
//   hematocrit   Σ cell areas / fluid area (L H minus obstacles), %
//   wall gaps    the cell-free layer at an instant (the study's Section 3.1.3): the gap between each wall
//                and the membrane node of any cell closest to it, min_k,i r_ki·e2 (lower wall
//                x2 = 0) and H − max_k,i r_ki·e2 (upper wall x2 = H), m
//
// Shape descriptor, in the frame of the flow (x1 downstream), with D the cell's x1-extent:
//   rear concavity   κ_r = (x_rear(y_c) − x_min) / D   — how far the rear midpoint (where the
//                    line x2 = y_c through the centroid meets the rear membrane) lies ahead of
//                    the rearmost node; > 0 for a parachute, ≈ 0 for a bullet or a circle
//   front concavity  κ_f = (x_max − x_front(y_c)) / D — the same at the front
//   side concavity   κ_s = ((y_max − y_top(x_c)) + (y_bot(x_c) − y_min)) / (2 H_c), H_c the
//                    x2-extent — dimples on the top and bottom, > 0 for a biconcave disc
//   fore-aft offset  a = (x_c − (x_min + x_max)/2) / D — < 0 when the area sits toward the rear
//                    (a bullet: flat rear, round front)
// Classification (thresholds fixed here, before any comparison with the study):
//   parachute   κ_r > 0.05 and κ_f < 0.02
//   biconcave   κ_s > 0.02 and κ_r < 0.02 and κ_f < 0.02
//   bullet      κ_r ≤ 0.05, κ_s ≤ 0.05 and a < −0.01
//   round       none of the above with max(κ) < 0.02 and |a| ≤ 0.01
//   other       otherwise
#include <string>

#include "membrane/cell.hpp"
#include "mesh/channel_mesh.hpp"

namespace rbc {

struct ShapeDescriptor {
  double rear_concavity = 0, front_concavity = 0, side_concavity = 0, fore_aft = 0;
  double length = 0, width = 0;  // x1- and x2-extents, m
  std::string kind;              // parachute, biconcave, bullet, round, other
};

// The same outline in the cell's own frame, whatever way it lies in the flow (a tilted biconcave
// cell has concave "ends" in the flow's frame and is "other" there): rotated about its centroid so
// that the long principal axis of the enclosed area's second moments lies along x1. With W the
// extent across that axis and the crossings of the line through the centroid across it:
//   top and bottom dimples  δ_t = (y_max − y_top(x_c)) / W,  δ_b = (y_bot(x_c) − y_min) / W
//   end concavity           κ_e = the larger of the rear and front concavities along the axis
//   biconcave               δ_t > 0.02 and δ_b > 0.02 and κ_e < 0.02 (both faces dimpled, both
//                           ends convex; the thresholds of the flow-frame descriptor above). A
//                           parachute (one face indented) or an ellipse is not biconcave.
struct OwnFrameShape {
  double angle = 0;  // of the long axis to x1, rad, in (−π/2, π/2]
  double top_dimple = 0, bottom_dimple = 0, end_concavity = 0;
  bool biconcave = false;
};

struct CellState {
  Eigen::Vector2d centroid;
  double area = 0, perimeter = 0, area_drift = 0, max_strain = 0;
  ShapeDescriptor shape;
  OwnFrameShape own_frame;
};

ShapeDescriptor describe_shape(const Points& r);
OwnFrameShape describe_shape_in_own_frame(const Points& r);
CellState measure_cell(const Cell& c, double rest_length);
double hematocrit_percent(const std::vector<Cell>& cells, double fluid_area);
struct WallGaps {
  double lower = 0, upper = 0;  // m; the channel height H each if there are no cells
};
WallGaps wall_gaps(const std::vector<Cell>& cells, double height);

}  // namespace rbc
