#pragma once
// What a run writes for ParaView ([output] vtk = true; lib/io/vtk.hpp writes the files), in
// <out>/vtk/, every [output] vtk_every seconds of simulated time:
//
//   flow_NNNNN.vti       the fluid on the T_h nodes, the periodic column x1 = L repeated so the
//                        image spans the channel: "velocity [m/s]", "pressure [Pa]" (P1 on T_2h
//                        read at the T_h nodes), "vorticity [1/s]" ω = ∂u2/∂x1 − ∂u1/∂x2
//                        (centred differences, one-sided at the walls);
//   membranes_NNNNN.vtp  every cell as a closed polyline (x1 shifted by a whole period so that
//                        its centroid lies in [0, L)): "cell_id", "force [N/m]" (the spring force
//                        (8) on each node), "stretch" ((l − l0)/l0, mean of the node's two springs);
//   disks_NNNNN.vtp      every disk's outline (kDiskOutlinePoints points) and a radius towards its
//                        angle θ (to see it turn): "disk_id", "velocity [m/s]" (the rigid motion
//                        V + ω × (x − G) at the point), "angular_velocity [1/s]", "radius [m]";
//   obstacles.vtp        the obstacles as rectangles (once): "obstacle_id";
//   run.pvd              every file with its time (part 0 fluid, 1 membranes, 2 disks,
//                        3 obstacles): ParaView opens the run as one time series.
//
// Every dataset carries its time (field TimeValue, s). A resumed run keeps the files before its
// checkpoint and the collection's entries for them.
#include <filesystem>
#include <vector>

#include "io/vtk.hpp"
#include "scene/simulation.hpp"

namespace rbc {

inline constexpr int kDiskOutlinePoints = 64;

class VtkSeries {
 public:
  // dir: <out>/vtk (created); written: samples already written by the run being resumed (0: fresh).
  VtkSeries(const std::filesystem::path& dir, const Simulation& sim, int written);
  // Writes the next sample's files if its time has come (vtk_every), and the collection.
  void sample_due();
  int written() const { return written_; }

 private:
  void write();
  std::filesystem::path dir_;
  const Simulation& sim_;
  int written_ = 0;
  std::vector<PvdEntry> entries_;
};

// The datasets themselves (for tests): the fluid, the membranes, the disks, the obstacles.
// fluid_image: u and p (Pa, on the pressure nodes: the Simulation's pressure_with_membranes()).
VtkImage fluid_image(const ChannelFlow& flow, const std::vector<double>& pressure);
VtkPolyData membranes_polydata(const std::vector<Cell>& cells, const MembraneModel& model, double length);
VtkPolyData disks_polydata(const std::vector<Disk>& disks, double length);
VtkPolyData obstacles_polydata(const std::vector<Obstacle>& obstacles);

}  // namespace rbc
