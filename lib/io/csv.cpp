#include "io/csv.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rbc {

std::vector<double> csv_column(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::string line, cell;
  std::getline(in, line);
  std::stringstream hs(line);
  int col = -1;
  for (int k = 0; std::getline(hs, cell, ','); ++k)
    if (cell == name) col = k;
  if (col < 0) throw std::runtime_error(path + ": no column '" + name + "'");
  std::vector<double> v;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    for (int k = 0; std::getline(ss, cell, ','); ++k)
      if (k == col) { v.push_back(std::stod(cell)); break; }
  }
  return v;
}

}  // namespace rbc
