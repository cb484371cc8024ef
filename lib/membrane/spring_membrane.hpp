#pragma once
// The elastic spring membrane of a red blood cell (the study's Eqs. (5)-(8)).
//
// A cell is a closed chain of N nodes r_1..r_N; spring i joins node i to node i+1 (cyclic),
// l_i is its length, l0 = 2πR0/N the rest length (arc length of the initial circle), θ_i the
// angle between the two springs meeting at node i (θ = 0 for a straight chain), s the enclosed
// area (positive counter-clockwise) and s_e the target area. Energies per unit depth (J/m):
//
//   E_l = (k_l/2) Σ_i ((l_i − l0)/l0)²          stretching                         (5)
//   E_b = (k_b/2) Σ_i tan²(θ_i/2)               bending                            (6)
//   E_s = (k_s/2) ((s − s_e)/s_e)²              area penalty                       (7)
//   F_i = −∂(E_l + E_b + E_s)/∂r_i              nodal force (N/m)                  (8)
//
// With a = r_i − r_{i−1}, b = r_{i+1} − r_i:  tan(θ_i/2) = (a × b) / (|a||b| + a·b), which we
// differentiate exactly (no angle is ever formed, so there is no branch cut).
#include <string>
#include <vector>

#include <Eigen/Core>

namespace rbc {

using Points = std::vector<Eigen::Vector2d>;

// The study's constants "as given", and the two readings of them in a 2D code (paper/method/02_membrane.md):
//   "si"  — the numbers as energies per unit depth in SI (J/m);
//   "cgs" — the numbers converted to CGS (erg) and then used per unit depth in a CGS code
//           (erg/cm), i.e. 100 times stiffer than "si" once expressed in J/m.
struct MembraneConstants {
  double kl = 5e-8;    // k_l, stretching (study's value, "N m")
  double kb = 5e-10;   // k_b, bending
  double ks = 1e-5;    // k_s, area penalty
  std::string units = "si";
  double stiffness_scale() const;  // J/m per unit of the study's numbers: 1 (si) or 100 (cgs)
};

struct MembraneModel {
  int nodes = 76;        // N
  double radius = 2.8e-6;  // R0, m
  double kl = 0, kb = 0, ks = 0;  // J/m, after the unit reading
  bool area_penalty = true;       // E_s in the force (8)
  double rest_length() const;     // l0 = 2πR0/N, m
  static MembraneModel from(const MembraneConstants& c, int nodes, double radius, bool area_penalty = true);
  bool operator==(const MembraneModel&) const = default;
};

struct MembraneEnergy {
  double stretching = 0, bending = 0, area = 0;  // J/m
  double total() const { return stretching + bending + area; }
};

// Energies of a chain with target area s_e (m²); adds −∂E/∂r_i to forces (if non-null).
MembraneEnergy membrane_energy(const MembraneModel& m, const Points& r, double target_area, Points* forces);

double enclosed_area(const Points& r);   // s, m² (counter-clockwise positive)
double perimeter(const Points& r);       // Σ l_i, m
Eigen::Vector2d area_centroid(const Points& r);  // centroid of the enclosed region, m
double max_strain(const Points& r, double l0);   // max_i |l_i − l0| / l0

}  // namespace rbc
