#include "scene/movie_frames.hpp"

#include <algorithm>

#include "scene/vtk_output.hpp"

namespace rbc {

namespace {

// Every line and polygon of poly as an outline of kind `kind`, the id from its cell data; once
// more one period over (±L) when it reaches past x1 = 0 or L.
void write_outlines(std::ostream& out, const VtkPolyData& poly, int kind, double length) {
  const std::vector<std::int32_t>& ids = poly.cell_data.front().i32;  // one per line, then per polygon
  std::size_t index = 0;
  auto put = [&](const std::vector<std::int64_t>& outline, bool closed) {
    const std::int32_t id = ids[index++];
    double lo = poly.xy[2 * outline.front()], hi = lo;
    for (std::int64_t p : outline) lo = std::min(lo, poly.xy[2 * p]), hi = std::max(hi, poly.xy[2 * p]);
    for (double shift : {0.0, length, -length}) {
      if ((shift > 0 && lo >= 0) || (shift < 0 && hi <= length)) continue;
      for (std::int64_t p : outline) out << (poly.xy[2 * p] + shift) << " " << poly.xy[2 * p + 1] << " " << kind << " " << id << "\n";
      if (closed) out << (poly.xy[2 * outline.front()] + shift) << " " << poly.xy[2 * outline.front() + 1] << " " << kind << " " << id << "\n";
      out << "\n";
    }
  };
  for (const auto& line : poly.lines) put(line, false);  // the membranes' and disks' lines close themselves
  for (const auto& polygon : poly.polys) put(polygon, true);
}

}  // namespace

void write_frames_header(std::ostream& out, const Scene& scene) {
  out << "# rbcflow movie frames, the channel's length and height (m): " << scene.length << " " << scene.height << "\n";
  out << "# x1 (m), x2 (m), kind (0 membrane, 1 disk, 2 obstacle), id; one index per frame\n";
}

void write_frame(std::ostream& out, const Simulation& sim) {
  const Scene& s = sim.scene();
  out << "# t = " << sim.time() << " s\n";
  if (!sim.cells().empty()) write_outlines(out, membranes_polydata(sim.cells(), sim.membrane(), s.length), 0, s.length);
  if (!sim.disks().empty()) write_outlines(out, disks_polydata(sim.disks(), s.length), 1, s.length);
  if (!s.obstacles.empty()) write_outlines(out, obstacles_polydata(s.obstacles), 2, s.length);
  out << "\n\n";
}

}  // namespace rbc
