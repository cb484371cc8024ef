#pragma once
// A short-range repulsion that keeps membranes off the walls and off each other (not in the
// study), of the kind immersed-boundary codes for many red cells add (e.g. the cell–wall and
// cell–cell forces of Fedosov et al. and of HemoCell), and in the form of the disks' contact
// force (Glowinski, Pan, Hesla & Joseph 1999): with ρ its range and s its strength,
//
//   node i at distance d < ρ from a wall:        F_i += s (1 − d/ρ)² n      (n: away from the wall)
//   nodes i, j of different cells, |r_i − r_j| = d < ρ:
//                                                F_i += s (1 − d/ρ)² e,  F_j −= s (1 − d/ρ)² e
//                                                (e = (r_i − r_j)/d; x1 periodic of period L)
//
// F in N/m like the membrane's own node forces (spread by (10)); zero beyond ρ and smooth at ρ, so
// it acts only when a node comes within ρ (about a mesh cell) of a wall or of another cell, where
// the immersed boundary no longer resolves the plasma film between them. It is not in the study
// (whose model has no such force): a scene switches it on ([repulsion] strength > 0), and the
// experiments that need it measure its effect on their rows. Explicit in time (step 2); its
// stiffness 2s/ρ must stay small against the membrane's mobility times Δt (the scene's bound).
#include <vector>

#include "membrane/cell.hpp"

namespace rbc {

struct MembraneRepulsion {
  double range = 0;     // ρ, m
  double strength = 0;  // s, N/m (0: off)
  bool on() const { return range > 0 && strength > 0; }
};

struct RepulsionCount {
  long wall_nodes = 0;  // nodes within ρ of a wall
  long node_pairs = 0;  // pairs of nodes of different cells within ρ
};

// Adds the repulsion to F (F[k][i]: node i of cell k, N/m; sized like the cells' nodes) for the
// cells between the walls x2 = 0 and x2 = H, x1 periodic of period L.
RepulsionCount add_membrane_repulsion(const std::vector<Cell>& cells, double L, double H, const MembraneRepulsion& rep,
                                      std::vector<Points>& F);

}  // namespace rbc
