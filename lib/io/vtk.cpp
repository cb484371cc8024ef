#include "io/vtk.hpp"

#include <bit>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rbc {

static_assert(std::endian::native == std::endian::little, "the VTK files say byte_order=\"LittleEndian\"");

namespace {

// The appended section: blocks of (UInt64 byte count, bytes), each DataArray pointing at its
// block's offset from the first byte after the '_' that opens the section.
class Appended {
 public:
  // The DataArray element of one array (its data goes into the section).
  std::string array(const VtkArray& a) {
    if (a.components < 1) throw std::invalid_argument("VTK array " + a.name + ": components must be at least 1");
    const std::size_t n = a.f64.empty() ? a.i32.size() : a.f64.size();
    if (n % std::size_t(a.components) != 0)
      throw std::invalid_argument("VTK array " + a.name + ": " + std::to_string(n) + " values are not whole tuples of " +
                                  std::to_string(a.components));
    std::ostringstream e;
    e << "<DataArray type=\"" << (a.f64.empty() ? "Int32" : "Float64") << "\" Name=\"" << a.name << "\" NumberOfComponents=\""
      << a.components << "\" NumberOfTuples=\"" << n / std::size_t(a.components) << "\" format=\"appended\" offset=\"" << bytes_.size()
      << "\"/>\n";
    if (a.f64.empty())
      block(a.i32.data(), a.i32.size() * sizeof(std::int32_t));
    else
      block(a.f64.data(), a.f64.size() * sizeof(double));
    return e.str();
  }
  std::string int64(const std::string& name, const std::vector<std::int64_t>& v) {
    std::ostringstream e;
    e << "<DataArray type=\"Int64\" Name=\"" << name << "\" format=\"appended\" offset=\"" << bytes_.size() << "\"/>\n";
    block(v.data(), v.size() * sizeof(std::int64_t));
    return e.str();
  }
  const std::string& bytes() const { return bytes_; }

 private:
  void block(const void* data, std::size_t size) {
    const std::uint64_t header = size;
    bytes_.append(reinterpret_cast<const char*>(&header), sizeof header);
    bytes_.append(static_cast<const char*>(data), size);
  }
  std::string bytes_;
};

std::string time_field(Appended& app, double time) {
  VtkArray t{"TimeValue", 1, {time}, {}};
  return "<FieldData>\n" + app.array(t) + "</FieldData>\n";
}

void check_tuples(const std::string& path, const std::vector<VtkArray>& arrays, std::size_t expected, const char* what) {
  for (const VtkArray& a : arrays)
    if (a.tuples() != expected)
      throw std::invalid_argument(path + ": array " + a.name + " has " + std::to_string(a.tuples()) + " tuples for " +
                                  std::to_string(expected) + " " + what);
}

void write_file(const std::string& path, const std::string& type, const std::string& body, const Appended& app) {
  std::ofstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot write " + path);
  f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"" << type
    << "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
    << body << "<AppendedData encoding=\"raw\">\n_";
  f.write(app.bytes().data(), std::streamsize(app.bytes().size()));
  f << "\n</AppendedData>\n</VTKFile>\n";
  if (!f) throw std::runtime_error("cannot write " + path);
}

std::string data_section(const char* tag, Appended& app, const std::vector<VtkArray>& arrays) {
  std::string s = std::string("<") + tag + ">\n";
  for (const VtkArray& a : arrays) s += app.array(a);
  return s + "</" + tag + ">\n";
}

}  // namespace

void write_vti(const std::string& path, const VtkImage& im, double time) {
  if (im.nx < 1 || im.ny < 1) throw std::invalid_argument(path + ": an image needs at least one point each way");
  check_tuples(path, im.point_data, std::size_t(im.nx) * std::size_t(im.ny), "points");
  Appended app;
  std::ostringstream b;
  b.precision(17);
  const std::string extent = "0 " + std::to_string(im.nx - 1) + " 0 " + std::to_string(im.ny - 1) + " 0 0";
  b << "<ImageData WholeExtent=\"" << extent << "\" Origin=\"" << im.x0 << " " << im.y0 << " 0\" Spacing=\"" << im.dx << " " << im.dy
    << " " << im.dx << "\">\n";
  b << time_field(app, time);
  b << "<Piece Extent=\"" << extent << "\">\n" << data_section("PointData", app, im.point_data) << "<CellData>\n</CellData>\n</Piece>\n</ImageData>\n";
  write_file(path, "ImageData", b.str(), app);
}

void write_vtp(const std::string& path, const VtkPolyData& p, double time) {
  if (p.xy.size() % 2 != 0) throw std::invalid_argument(path + ": points need two coordinates each");
  const std::size_t points = p.xy.size() / 2;
  check_tuples(path, p.point_data, points, "points");
  check_tuples(path, p.cell_data, p.lines.size() + p.polys.size(), "lines and polygons");
  Appended app;
  std::ostringstream b;
  b << "<PolyData>\n" << time_field(app, time);
  b << "<Piece NumberOfPoints=\"" << points << "\" NumberOfVerts=\"0\" NumberOfLines=\"" << p.lines.size()
    << "\" NumberOfStrips=\"0\" NumberOfPolys=\"" << p.polys.size() << "\">\n";
  b << data_section("PointData", app, p.point_data) << data_section("CellData", app, p.cell_data);
  VtkArray xyz{"Points", 3, std::vector<double>(3 * points, 0.0), {}};
  for (std::size_t k = 0; k < points; ++k) {
    xyz.f64[3 * k] = p.xy[2 * k];
    xyz.f64[3 * k + 1] = p.xy[2 * k + 1];
  }
  b << "<Points>\n" << app.array(xyz) << "</Points>\n";
  auto cells = [&](const char* tag, const std::vector<std::vector<std::int64_t>>& list) {
    std::vector<std::int64_t> connectivity, offsets;
    for (const auto& c : list) {
      for (std::int64_t id : c) {
        if (id < 0 || std::size_t(id) >= points) throw std::invalid_argument(path + ": a cell refers to point " + std::to_string(id));
        connectivity.push_back(id);
      }
      offsets.push_back(std::int64_t(connectivity.size()));
    }
    b << "<" << tag << ">\n" << app.int64("connectivity", connectivity) << app.int64("offsets", offsets) << "</" << tag << ">\n";
  };
  cells("Lines", p.lines);
  cells("Polys", p.polys);
  b << "</Piece>\n</PolyData>\n";
  write_file(path, "PolyData", b.str(), app);
}

void write_pvd(const std::string& path, const std::vector<PvdEntry>& entries) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    if (!f) throw std::runtime_error("cannot write " + tmp);
    f.precision(17);
    f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n";
    for (const PvdEntry& e : entries)
      f << "<DataSet timestep=\"" << e.time << "\" group=\"\" part=\"" << e.part << "\" file=\"" << e.file << "\"/>\n";
    f << "</Collection>\n</VTKFile>\n";
    if (!f) throw std::runtime_error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace rbc
