#pragma once
// ParaView files: VTK XML (https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html),
// binary, appended raw, little-endian, with UInt64 block headers — what VTK's own readers take.
//
//   .vti  ImageData: a uniform grid of points with point arrays (the fluid);
//   .vtp  PolyData: points joined by lines (closed polylines repeat their first point) and
//         polygons, with point and cell arrays (membranes, disks, obstacles);
//   .pvd  a ParaView collection: every sample's files with its time (timestep) and part, so
//         ParaView opens a run as one time series.
//
// Every dataset also carries its time as the field array TimeValue (s). Arrays are Float64 or
// Int32; their names carry their unit, e.g. "velocity [m/s]". Vectors are 3-component (z = 0).
// These writers know nothing of the physics: lib/scene/vtk_output.hpp decides what is written.
#include <cstdint>
#include <string>
#include <vector>

namespace rbc {

struct VtkArray {
  std::string name;
  int components = 1;
  std::vector<double> f64;         // Float64 values (tuple after tuple), or
  std::vector<std::int32_t> i32;   // Int32 values (f64 empty)
  std::size_t tuples() const { return (f64.empty() ? i32.size() : f64.size()) / std::size_t(components); }
};

// A uniform grid of nx × ny points at (x0 + i dx, y0 + j dy), point k = j nx + i.
struct VtkImage {
  int nx = 0, ny = 0;
  double x0 = 0, y0 = 0, dx = 0, dy = 0;
  std::vector<VtkArray> point_data;
};

// Points (x, y) joined by lines (each a list of point indices) and polygons.
struct VtkPolyData {
  std::vector<double> xy;                     // x0, y0, x1, y1, …
  std::vector<std::vector<std::int64_t>> lines, polys;
  std::vector<VtkArray> point_data;
  std::vector<VtkArray> cell_data;            // one tuple per line, then per polygon
};

// Each throws std::runtime_error naming the file when it cannot be written, and
// std::invalid_argument when an array's size does not match its points or cells.
void write_vti(const std::string& path, const VtkImage& image, double time);
void write_vtp(const std::string& path, const VtkPolyData& poly, double time);

// One file of a collection: its time (s), its part (0, 1, … for the datasets of one sample)
// and its path relative to the .pvd.
struct PvdEntry {
  double time = 0;
  int part = 0;
  std::string file;
};
// Writes the collection whole (through a temporary file renamed over the old one, so a reader
// or a stopped run never sees half a file).
void write_pvd(const std::string& path, const std::vector<PvdEntry>& entries);

}  // namespace rbc
