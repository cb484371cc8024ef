#pragma once
// Reading back the numeric CSV files a run writes (series.csv, profile.csv): one column by its
// header name. Throws std::runtime_error naming the file and column.
#include <string>
#include <vector>

namespace rbc {
std::vector<double> csv_column(const std::string& path, const std::string& name);
}
