#pragma once
// Movie frames ([output] frames = n): the run's shapes at n + 1 times, frame k at the first step
// with t ≥ k end/n − Δt/2, appended to <out>/frames.dat for experiments/common/movie.gp.
//
// The file, for gnuplot (one index per frame):
//   # rbcflow movie frames, the channel's length and height (m): <L> <H>   (once, at the top)
//   # t = <t> s
//   x1 (m)   x2 (m)   kind  id     one closed outline per block, blocks apart by a blank line;
//                                  kind 0 a membrane, 1 a disk (its outline, then its radius at θ),
//                                  2 an obstacle; id the cell's, disk's or obstacle's index
//   (two blank lines end the frame)
// The outlines are those of the ParaView files (scene/vtk_output.hpp: a cell's x1 shifted by whole
// periods so that its centroid lies in [0, L)); an outline reaching past x1 = 0 or L is written a
// second time one period over, so that a picture of [0, L] shows the periodic channel whole.
#include <ostream>

#include "scene/simulation.hpp"

namespace rbc {

// The line at the top of frames.dat (the channel's size).
void write_frames_header(std::ostream& out, const Scene& scene);
// One frame: the simulation's membranes, disks and obstacles at its time.
void write_frame(std::ostream& out, const Simulation& sim);

}  // namespace rbc
