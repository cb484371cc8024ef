#include "scene/vtk_output.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <string>

#include "fem/p1_operators.hpp"

namespace rbc {

namespace fs = std::filesystem;

VtkImage fluid_image(const ChannelFlow& flow, const std::vector<double>& p) {
  const ChannelMesh& m = flow.mesh();
  const VelocityField& u = flow.velocity();
  VtkImage im;
  im.nx = m.nx + 1;  // the column x1 = L repeats x1 = 0 (periodic)
  im.ny = m.ny + 1;
  im.dx = im.dy = m.h;
  const std::size_t points = std::size_t(im.nx) * im.ny;
  VtkArray vel{"velocity [m/s]", 3, std::vector<double>(3 * points, 0.0), {}};
  VtkArray pre{"pressure [Pa]", 1, std::vector<double>(points, 0.0), {}};
  VtkArray vor{"vorticity [1/s]", 1, std::vector<double>(points, 0.0), {}};
  // P1 on T_2h at a T_h node (fem/p1_operators.hpp).
  std::vector<std::pair<std::size_t, double>> w;
  auto pressure_at = [&](int i, int j) {
    coarse_weights_at(m, i, j, w);
    double v = 0;
    for (auto [Q, c] : w) v += c * p[Q];
    return v;
  };
  for (int j = 0; j <= m.ny; ++j)
    for (int i = 0; i <= m.nx; ++i) {
      const std::size_t k = std::size_t(j) * im.nx + i, n = m.v(i, j);
      vel.f64[3 * k] = u.u1[n];
      vel.f64[3 * k + 1] = u.u2[n];
      pre.f64[k] = pressure_at(i % m.nx, j);
      const double du2dx = (u.u2[m.v(i + 1, j)] - u.u2[m.v(i - 1, j)]) / (2 * m.h);
      const double du1dy = j == 0      ? (u.u1[m.v(i, 1)] - u.u1[m.v(i, 0)]) / m.h
                           : j == m.ny ? (u.u1[m.v(i, m.ny)] - u.u1[m.v(i, m.ny - 1)]) / m.h
                                       : (u.u1[m.v(i, j + 1)] - u.u1[m.v(i, j - 1)]) / (2 * m.h);
      vor.f64[k] = du2dx - du1dy;
    }
  im.point_data = {std::move(vel), std::move(pre), std::move(vor)};
  return im;
}

VtkPolyData membranes_polydata(const std::vector<Cell>& cells, const MembraneModel& model, double length) {
  VtkPolyData poly;
  VtkArray id{"cell_id", 1, {}, {}}, force{"force [N/m]", 3, {}, {}}, stretch{"stretch", 1, {}, {}};
  VtkArray line_id{"cell_id", 1, {}, {}};
  const double l0 = model.rest_length();
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const Points& r = cells[c].nodes;
    Points f;
    membrane_energy(model_of(model, cells[c].kb_scale), r, cells[c].target_area, &f);
    const double shift = shift_into_period(area_centroid(r).x(), length);  // whole periods: the centroid in [0, L)
    const std::int64_t first = std::int64_t(poly.xy.size() / 2);
    std::vector<std::int64_t> line;
    const std::size_t n = r.size();
    for (std::size_t k = 0; k < n; ++k) {
      poly.xy.push_back(r[k].x() + shift);
      poly.xy.push_back(r[k].y());
      id.i32.push_back(std::int32_t(c));
      force.f64.insert(force.f64.end(), {f[k].x(), f[k].y(), 0.0});
      const double before = (r[k] - r[(k + n - 1) % n]).norm(), after = (r[(k + 1) % n] - r[k]).norm();
      stretch.f64.push_back(0.5 * (before + after) / l0 - 1.0);
      line.push_back(first + std::int64_t(k));
    }
    line.push_back(first);  // closed
    poly.lines.push_back(std::move(line));
    line_id.i32.push_back(std::int32_t(c));
  }
  poly.point_data = {std::move(id), std::move(force), std::move(stretch)};
  poly.cell_data = {std::move(line_id)};
  return poly;
}

VtkPolyData disks_polydata(const std::vector<Disk>& disks, double length) {
  VtkPolyData poly;
  VtkArray id{"disk_id", 1, {}, {}}, vel{"velocity [m/s]", 3, {}, {}}, spin{"angular_velocity [1/s]", 1, {}, {}},
      radius{"radius [m]", 1, {}, {}}, line_id{"disk_id", 1, {}, {}};
  for (std::size_t d = 0; d < disks.size(); ++d) {
    const Disk& disk = disks[d];
    const Eigen::Vector2d g(image_in_period(disk.center.x(), length), disk.center.y());
    auto add_point = [&](const Eigen::Vector2d& x) {
      const Eigen::Vector2d arm = x - g;
      poly.xy.push_back(x.x());
      poly.xy.push_back(x.y());
      id.i32.push_back(std::int32_t(d));
      vel.f64.insert(vel.f64.end(), {disk.velocity.x() - disk.angular_velocity * arm.y(), disk.velocity.y() + disk.angular_velocity * arm.x(), 0.0});
      spin.f64.push_back(disk.angular_velocity);
      radius.f64.push_back(disk.radius);
      return std::int64_t(poly.xy.size() / 2 - 1);
    };
    std::vector<std::int64_t> outline;
    for (int k = 0; k < kDiskOutlinePoints; ++k) {
      const double a = disk.angle + 2 * std::numbers::pi * k / kDiskOutlinePoints;
      outline.push_back(add_point(g + disk.radius * Eigen::Vector2d(std::cos(a), std::sin(a))));
    }
    const std::int64_t rim = outline.front();
    outline.push_back(rim);
    poly.lines.push_back(std::move(outline));
    poly.lines.push_back({add_point(g), rim});  // the radius at angle θ: the disk's turn
    line_id.i32.insert(line_id.i32.end(), {std::int32_t(d), std::int32_t(d)});
  }
  poly.point_data = {std::move(id), std::move(vel), std::move(spin), std::move(radius)};
  poly.cell_data = {std::move(line_id)};
  return poly;
}

VtkPolyData obstacles_polydata(const std::vector<Obstacle>& obstacles) {
  VtkPolyData poly;
  VtkArray id{"obstacle_id", 1, {}, {}};
  for (std::size_t o = 0; o < obstacles.size(); ++o) {
    const Obstacle& b = obstacles[o];
    const std::int64_t first = std::int64_t(poly.xy.size() / 2);
    poly.xy.insert(poly.xy.end(), {b.x[0], b.y[0], b.x[1], b.y[0], b.x[1], b.y[1], b.x[0], b.y[1]});
    poly.polys.push_back({first, first + 1, first + 2, first + 3});
    id.i32.push_back(std::int32_t(o));
  }
  poly.cell_data = {std::move(id)};
  return poly;
}

VtkSeries::VtkSeries(const fs::path& dir, const Simulation& sim, int written) : dir_(dir), sim_(sim), written_(written) {
  fs::create_directories(dir_);
  if (written_ == 0) return;
  // Resumed: the collection's entries of the files written before the checkpoint (sample k is
  // written at the first sample at or after k vtk_every − dt/2, before (k + 1) vtk_every − dt/2).
  const Scene& s = sim.scene();
  const double before = written_ * s.vtk_interval() - 0.5 * s.dt;
  std::ifstream f(dir_ / "run.pvd");
  std::string line;
  while (std::getline(f, line)) {
    double t = 0;
    int part = 0;
    char file[256] = {0};
    if (std::sscanf(line.c_str(), "<DataSet timestep=\"%lf\" group=\"\" part=\"%d\" file=\"%255[^\"]\"", &t, &part, file) != 3) continue;
    if (t < before) entries_.push_back({t, part, file});
  }
}

void VtkSeries::sample_due() {
  const Scene& s = sim_.scene();
  if (!s.vtk || sim_.time() < written_ * s.vtk_interval() - 0.5 * s.dt) return;
  write();
}

void VtkSeries::write() {
  const Scene& s = sim_.scene();
  const double t = sim_.time();
  char index[16];
  std::snprintf(index, sizeof index, "_%05d", written_);
  // Part k's file of this sample, entered in the collection.
  auto put = [&](int part, const std::string& file) {
    entries_.push_back({t, part, file});
    return (dir_ / file).string();
  };
  write_vti(put(0, "flow" + std::string(index) + ".vti"), fluid_image(sim_.flow(), sim_.pressure_with_membranes()), t);
  if (!sim_.cells().empty())
    write_vtp(put(1, "membranes" + std::string(index) + ".vtp"), membranes_polydata(sim_.cells(), sim_.membrane(), s.length), t);
  if (!sim_.disks().empty()) write_vtp(put(2, "disks" + std::string(index) + ".vtp"), disks_polydata(sim_.disks(), s.length), t);
  if (!s.obstacles.empty()) {  // they do not move: one file, named at every time
    const std::string path = put(3, "obstacles.vtp");
    if (written_ == 0) write_vtp(path, obstacles_polydata(s.obstacles), 0.0);
  }
  ++written_;
  write_pvd((dir_ / "run.pvd").string(), entries_);
}

}  // namespace rbc
