#pragma once
// Shape preparation (the study's Remark 2.1; SPEC section 2).
//
// Start from N nodes on the circle of radius R0 and let the chain relax, with the target area
// s_e = s* π R0² (s* the swelling ratio), to a minimum of E_l + E_b + E_s. The study integrates
// m r̈ + γ ṙ = F; we minimise the same energy directly (GSL's vector BFGS, then Newton steps with
// the exact gradient and a finite-difference Hessian to converge tightly, as the accuracy claim
// needs: area within 0.001 % of s_e, perimeter within 0.005 % of 2πR0). A slight elongation along
// x1 of the initial circle (1 %) breaks the symmetry so that the long axis lies along x1. The
// minimiser works in units of R0 and k_l, so the shape does not depend on the unit reading.
// For s* = 1 the cell is the N-node circle itself.
#include "membrane/spring_membrane.hpp"

namespace rbc {

struct PreparedShape {
  Points nodes;             // counter-clockwise, centroid at the origin, long axis along x1, m
  double target_area = 0;   // s_e, m²
  double area_error = 0;    // (s − s_e)/s_e
  double perimeter_error = 0;  // (perimeter − 2πR0)/(2πR0)
  int iterations = 0;
};

// Throws std::invalid_argument for s* outside (0, 1] or std::runtime_error if the minimiser fails.
PreparedShape prepare_shape(const MembraneModel& model, double swelling_ratio);

// The prepared shape rotated by angle (rad) and moved to centroid c (m).
Points place_shape(const PreparedShape& shape, const Eigen::Vector2d& centroid, double angle);

}  // namespace rbc
