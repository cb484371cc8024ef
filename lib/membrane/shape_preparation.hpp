#pragma once
// Shape preparation (the study's Remark 2.1).
//
// Start from N nodes on the circle of radius R0 and let the chain relax, with the target area
// s_e = s* π R0² (s* the swelling ratio), to a minimum of E_l + E_b + E_s. The study integrates
// m r̈ + γ ṙ = F; we minimise the same energy directly (GSL's vector BFGS, then Newton steps with
// the exact gradient and a finite-difference Hessian to converge tightly, as the accuracy claim
// needs: area within 0.001 % of s_e, perimeter within 0.005 % of 2πR0). A slight elongation along
// x1 of the initial circle (1 %) breaks the symmetry so that the long axis lies along x1. The
// minimiser works in units of R0 and k_l, so the shape does not depend on the unit reading.
//
// The most swollen cell (s* = 1, "the circle itself" in the study). A closed chain of N springs
// at rest length l0 = 2πR0/N encloses at most the area of the regular N-gon of side l0,
//   s_max = N l0² / (4 tan(π/N)) = π R0² · s*_max,   s*_max = (π/N) / tan(π/N)   (0.99943, N = 76)
// (the isoperimetric inequality for polygons), so s_e = π R0² cannot be met with the springs at
// rest, and no polygon is a rest state of (5)-(7) with that target. We take for s* ≥ s*_max the
// regular N-gon of side l0, with its own area as the target: every spring at rest (E_l = 0),
// E_s = 0, and E_b stationary (by symmetry), so the cell starts without force, like the prepared
// cells s* < s*_max. Its area is 0.057 % below π R0² (the polygon inscribed in the circle of
// radius R0, the study's "circle", has 0.114 % less, and springs 0.0285 % short of l0 that push it
// outward during the run). paper/method/02_membrane.md says why.
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
// Each (model, s*) is minimised once per process and kept (a run asks for the same shape in the
// scene's check, the run and the extrapolated scheme's half steps); shapes_minimised() counts the
// minimisations (tests).
PreparedShape prepare_shape(const MembraneModel& model, double swelling_ratio);
int shapes_minimised();

// s*_max = (π/N) / tan(π/N): the swelling ratio of the regular N-gon whose springs are at rest.
double max_swelling_ratio(int nodes);

// The prepared shape rotated by angle (rad) and moved to centroid c (m).
Points place_shape(const PreparedShape& shape, const Eigen::Vector2d& centroid, double angle);

}  // namespace rbc
