#include "references.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "sphfx/core/data_files.h"
#include "sphfx/core/error.h"

namespace sphfx::study {

Table::Table(std::vector<double> x, std::vector<double> y) : x_(std::move(x)), y_(std::move(y)) {
  if (x_.size() != y_.size() || x_.empty()) throw InputError("table: x and y differ in length or are empty");
  for (size_t i = 1; i < x_.size(); ++i)
    if (!(x_[i] > x_[i - 1])) throw InputError("table: x is not increasing");
}

Table Table::readCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open");
  std::vector<double> x, y;
  std::string line;
  bool header = true;
  for (int lineNumber = 1; std::getline(in, line); ++lineNumber) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {  // the first non-comment line names the columns
      header = false;
      continue;
    }
    std::istringstream cells(line);
    double a = 0, b = 0;
    char comma = 0;
    if (!(cells >> a >> comma >> b) || comma != ',')
      throw InputError(
          fmt::format("{}:{}: expected two comma-separated numbers, got \"{}\"", path, lineNumber, line));
    if (!x.empty() && !(a > x.back()))
      throw InputError(fmt::format("{}:{}: the first column must increase", path, lineNumber));
    x.push_back(a);
    y.push_back(b);
  }
  if (x.size() < 2) throw InputError(path + ": expected at least two data rows");
  return Table(std::move(x), std::move(y));
}

double Table::at(double v) const {
  if (!covers(v))
    throw std::out_of_range(fmt::format("table: {} outside [{}, {}]", v, x_.front(), x_.back()));
  const auto it = std::upper_bound(x_.begin(), x_.end(), v);
  if (it == x_.end()) return y_.back();
  const size_t i = size_t(it - x_.begin());
  const double w = (v - x_[i - 1]) / (x_[i] - x_[i - 1]);
  return y_[i - 1] + w * (y_[i] - y_[i - 1]);
}

MartinMoyce MartinMoyce::load(const std::string& directory) {
  return {Table::readCsv(directory + "/dam_break_martin_moyce_n2.csv"),
          Table::readCsv(directory + "/dam_break_martin_moyce_n2_height.csv")};
}

std::string referenceDirectory() {
  return dataDirectory() + "/studies/reference";
}

double hydrostaticPressure(double restDensity, double gravity, double surfaceHeight, double y) {
  return y >= surfaceHeight ? 0.0 : restDensity * gravity * (surfaceHeight - y);
}

double taylorGreenAmplitude(double U0, double t, double lx, double lz, double nu) {
  const double kx = 2 * M_PI / lx, kz = 2 * M_PI / lz;
  return U0 * std::exp(-nu * (kx * kx + kz * kz) * t);
}

double poiseuilleVelocity(double y, double t, double L, double F, double nu) {
  const double steady = F / (2 * nu) * y * (L - y);
  const double scale = F * L * L / (8 * nu);  // the steady maximum, at y = L/2
  double sum = 0;
  for (int n = 1; n < 100001; n += 2) {
    const double term = 4 * F * L * L / (nu * M_PI * M_PI * M_PI * n * n * n) * std::sin(n * M_PI * y / L) *
                        std::exp(-double(n) * n * M_PI * M_PI * nu * t / (L * L));
    sum += term;
    // Terms fall at least as 1/n^3: stop once the remaining tail is negligible.
    if (std::fabs(4 * F * L * L / (nu * M_PI * M_PI * M_PI * n * n * n)) < 1e-12 * scale) break;
    if (t > 0 && std::exp(-double(n) * n * M_PI * M_PI * nu * t / (L * L)) < 1e-16) break;
  }
  return steady - sum;
}

}  // namespace sphfx::study
