#pragma once
// One step of the study's Lie scheme written out on the library's operators: the literate reference
// (Shi, Pan & Glowinski, IJNMF 68 (2012), DOI 10.1002/fld.2455, Section 2). reference_step.cpp reads
// top to bottom like the study's Section 2; tests/test_reference_step.cpp checks that it takes the
// same step as Simulation::step (lib/scene/simulation.cpp) to round-off. Scalar and serial: for
// reading, not for runs.
//
// It covers a channel with cells and the explicit coupling, in either pressure form ([time]
// projection); it refuses obstacles, disks, the semi-implicit coupling and the membrane repulsion.
#include <vector>

#include "fast_solvers/periodic_banded_solver.hpp"
#include "fem/divergence_stencil.hpp"
#include "fluid/wave_like_advection.hpp"
#include "membrane/cell.hpp"
#include "mesh/channel_mesh.hpp"
#include "scene/scene.hpp"

namespace rbc {

// The discrete operators of the study's Section 2.4 on the scene's mesh, built once (reference_step.cpp
// says what each is). Not copyable: the solvers hold FFTW plans and the Schur operator refers to B.
struct ReferenceOperators {
  explicit ReferenceOperators(const Scene& scene);  // throws std::invalid_argument for a scene it does not cover
  ChannelMesh mesh;                     // T_h (velocity) and T_2h (pressure)
  DivergenceStencil B;                  // (B u)_Q = ∫ q_Q ∇·u_h, and Bᵀ
  std::vector<double> pressure_weight;  // lumped weights of T_2h (the pressure's mean)
  PeriodicBandedSolver schur;           // S⁻¹, S = B M⁻¹ Bᵀ (pressure, T_2h)
  PeriodicBandedSolver helmholtz;       // A⁻¹, A = (ρ/Δt) M + μ K (one velocity component, interior rows)
  WaveLikeAdvection advection;          // step 3's wave-like substeps
  MembraneModel membrane;               // E_l, E_b, E_s (5)-(7) with the scene's constants
};

// The state the next step needs.
struct ReferenceState {
  VelocityField u;          // uⁿ, m/s, on T_h (wall rows: the wall velocity)
  std::vector<double> p;    // pⁿ, Pa, on T_2h, mean-zero
  std::vector<Cell> cells;  // rⁿ, m
  double t = 0;             // tⁿ, s
  long steps = 0;           // n
};

// The start of every run in the study: fluid at rest (the walls at their velocity), p = 0, each cell
// its prepared shape (the study's Remark 2.1) where the scene places it.
ReferenceState reference_start(const Scene& scene, const ReferenceOperators& ops);
// One step tⁿ → tⁿ⁺¹ of the Lie scheme: steps 1-4, eqs. (19), (13)-(14), (8), (10), (20), (21).
void reference_step(ReferenceState& state, const Scene& scene, ReferenceOperators& ops);

}  // namespace rbc
