#pragma once
// One red blood cell: its membrane nodes and the areas it is measured against.
#include "membrane/shape_preparation.hpp"

namespace rbc {

struct Cell {
  Points nodes;               // r_i, m; x1 unwrapped (a cell that crosses x1 = L keeps going)
  double swelling_ratio = 1;  // s*
  double target_area = 0;     // s_e = s* π R0², m²
  double prepared_area = 0;   // area of the prepared shape, m² (reference of the area drift)
  double prepared_perimeter = 0;
  double kb_scale = 1;        // this cell's k_b over the model's (the study's stiffer cells, Sec. 3.1.2)
};

// The membrane model of one cell: the scene's, with the cell's own bending stiffness.
inline MembraneModel model_of(const MembraneModel& m, double kb_scale) {
  MembraneModel c = m;
  c.kb *= kb_scale;
  return c;
}

inline Cell make_cell(const PreparedShape& shape, double swelling_ratio, const Eigen::Vector2d& centroid, double angle,
                      double kb_scale = 1) {
  Cell c;
  c.kb_scale = kb_scale;
  c.nodes = place_shape(shape, centroid, angle);
  c.swelling_ratio = swelling_ratio;
  c.target_area = shape.target_area;
  c.prepared_area = enclosed_area(c.nodes);
  c.prepared_perimeter = perimeter(c.nodes);
  return c;
}

}  // namespace rbc
