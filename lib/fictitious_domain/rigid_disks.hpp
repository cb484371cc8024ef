#pragma once
// Freely moving, neutrally buoyant rigid disks by the fictitious domain (Glowinski,
// Pan, Hesla & Joseph, Int. J. Multiphase Flow 25 (1999) 755, the DLM/FD method the study builds
// on). The fluid fills each disk ω_k; step 4 holds it in rigid motion,
//
//   A u = b + Bᵀλ,     B u = R q,     Rᵀλ = 0,
//
// with q_k = (V1, V2, ω) the disk's velocity and spin, R q the rigid velocity V + ω e3 × (x − G) at
// the collocation points, and Rᵀλ the multiplier's net force and torque on each disk. For a
// neutrally buoyant disk (ρ_s = ρ) the disk's own inertia is that of the fluid filling it, and
// Newton's equations reduce to Rᵀλ = 0 (GPHJ 1999, eqs. with (1 − ρ/ρ_s) = 0); outside forces on
// the disk (contact) enter b as a force density over its area. Same A, b and B as for the fixed
// obstacles (dlm_obstacle_step.hpp), where q = 0 and the last equation is absent.
//
// Collocation points (GPHJ): the mesh nodes inside ω farther than h/2 from ∂ω, and points on ∂ω
// about s h apart (s = boundary_spacing, 1 by default: GPHJ's choice; coarser s test how the
// disks' motion converges in them), read and spread by bilinear interpolation. Closer than about
// h apart the points' bilinear stencils and the ring nodes over-determine the multiplier: S_R
// below is then singular (measured: a disk of radius 2.8 um at h = 0.3125 um from 0.8 h).
// The nodes split as for the obstacles: a deep node d (its four neighbours collocation nodes, in
// no boundary point's stencil) has (A u)_d = (ρh²/Δt) (R q)_d (the 5-point Laplacian of a rigid
// motion vanishes), so
//
//   λ_d = (ρh²/Δt) (R q)_d − b_d     in closed form,
//
// and the unknown multiplier lives on the ring (the other nodes and the boundary points). With
// S = B_R A⁻¹ B_Rᵀ (from the Green table, helmholtz_green.hpp), M = B_R A⁻¹ (ρh²/Δt) R_D the
// ring's response to the deep multipliers' rigid part, K = M − R_R, N = Σ_d R_dᵀ R_d and
// c = ρh²/Δt, each disk's system is solved exactly (capacitance) by
//
//   T q = F_D + Σ_comp R_Rᵀ S⁻¹ g,     T = c N − Σ_comp R_Rᵀ S⁻¹ K,     λ_R = −S⁻¹ (g + K q),
//
// g the ring's velocity defect and F_D = Σ_d R_dᵀ b_d. The disks couple only through A⁻¹, which
// decays over the screening length √(μΔt/ρ): each iteration solves every disk's system against
// the current field, then makes one fast solve pair for all the corrections (block Jacobi), and
// stops when max |u − R q| over all collocation points ≤ tolerance × max |u|. Disks apart by a
// few screening lengths need one iteration.
#include <array>
#include <vector>

#include <Eigen/Dense>

#include "fictitious_domain/helmholtz_green.hpp"
#include "fluid/diffusion.hpp"

namespace rbc {

struct Disk {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();  // G, m (x1 unwrapped)
  double radius = 0;                                  // m
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero(); // V, m/s
  double angular_velocity = 0;                        // ω, 1/s (counter-clockwise)
  double angle = 0;                                   // θ, rad (∫ ω dt)
};

// One disk's collocation points at its current position.
struct DiskPoints {
  struct Point {
    Eigen::Vector2d offset;       // x − G (x1 by the nearest periodic image), m
    std::array<int, 4> nodes{};   // interior-row indices (r nx + i) read and spread
    std::array<double, 4> weights{};
    int count = 1;                // 1: a mesh node; 4: a boundary point (bilinear)
  };
  std::vector<Point> ring;        // ring nodes, then boundary points
  std::vector<Point> deep;        // deep nodes (count 1)
  int interior_nodes = 0;         // ring nodes + deep nodes
};
// The number of points on the boundary of a disk of radius r (m) about spacing · h apart: an
// even count, at least 8 (an even count is symmetric under the half turn about G as well as the
// reflection about its x1-line: a disk at the centre of a shear flow feels no lift from them).
int boundary_point_count(double r, double h, double spacing);
// boundary_spacing: the points on ∂ω about boundary_spacing · h apart (boundary_point_count).
DiskPoints disk_points(const ChannelMesh& mesh, const Disk& disk, double boundary_spacing = 1.0);

class DiskConstraint : public Step4Constraint {
 public:
  // A: step 4's unconstrained Helmholtz solver; rho (kg/m³), dt (s): its diagonal's ρh²/Δt;
  // boundary_spacing (in h): disk_points'.
  static constexpr int kMaxIterations = 100;  // block-Jacobi iterations before a solve gives up
  DiskConstraint(const ChannelMesh& mesh, PeriodicBandedSolver& A, double rho, double dt, double tolerance,
                 int max_iterations = kMaxIterations, double boundary_spacing = 1.0);
  // The disks where step 4 will hold them (rebuilds their points and factors; at every step).
  void set_disks(const std::vector<Disk>& disks);
  void solve_pair(double* b1, double* b2) override;

  // q = (V1, V2, ω) of each disk in a field that is rigid on its points (least squares over the
  // points: exact for step 4's result and for any sum of such results, e.g. the semi-implicit
  // coupling's correction added to it).
  std::vector<Eigen::Vector3d> rigid_motion(const VelocityField& u) const;
  // q = (V1, V2, ω) of each disk from the last solve.
  const std::vector<Eigen::Vector3d>& motion() const { return q_; }
  const std::vector<DiskPoints>& points() const { return points_; }
  struct Report {
    int iterations = 0;   // block-Jacobi iterations of the last solve
    double residual = 0;  // max |u − R q| over the collocation points / max |u|
  };
  const Report& last() const { return last_; }
  const HelmholtzGreen& green() const { return green_; }

 private:
  struct Factors {
    Eigen::LLT<Eigen::MatrixXd> S;      // S_R (both components alike)
    Eigen::MatrixXd Q[2];               // R_R rows of each component (|R| × 3)
    Eigen::MatrixXd SinvK[2];           // S⁻¹ K per component
    Eigen::Matrix3d T;                  // the disk's 3 × 3 system
    Eigen::PartialPivLU<Eigen::Matrix3d> Tlu;
  };
  ChannelMesh m_;
  PeriodicBandedSolver& A_;
  HelmholtzGreen green_;
  double c_;  // ρh²/Δt, N s/m³ · m² (A's mass part)
  double tolerance_;
  int max_iterations_;
  double boundary_spacing_;  // h
  std::vector<Disk> disks_;
  std::vector<DiskPoints> points_;
  std::vector<Factors> factors_;
  std::vector<Eigen::Vector3d> q_;
  std::vector<double> rhs_[2];
  Report last_;
};

}  // namespace rbc
