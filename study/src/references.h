#pragma once
/// @file references.h
/// @brief Independent reference solutions the simulator is measured against: published experimental
/// data (Martin & Moyce 1952 dam break) and analytic solutions (hydrostatic pressure, transient plane
/// Poiseuille flow after Morris, Fox & Zhu 1997, the decaying Taylor-Green vortex after Taylor & Green
/// 1937).

#include <string>
#include <vector>

namespace sphfx::study {

/// A tabulated curve y(x), x increasing, linearly interpolated.
class Table {
 public:
  Table() = default;
  Table(std::vector<double> x, std::vector<double> y);

  /// Reads a CSV of two numeric columns with a header line; '#' lines are comments.
  /// @throws IoError if unreadable; InputError (file and line) if malformed or x is not increasing.
  static Table readCsv(const std::string& path);

  /// y at x, linear between samples. @throws std::out_of_range outside [xMin, xMax].
  double at(double x) const;
  bool covers(double x) const { return !x_.empty() && x >= x_.front() && x <= x_.back(); }
  double xMin() const { return x_.front(); }
  double xMax() const { return x_.back(); }
  const std::vector<double>& x() const { return x_; }
  const std::vector<double>& y() const { return y_; }

 private:
  std::vector<double> x_, y_;
};

/// Martin & Moyce (1952), n^2 = 2: surge front Z = x/a against T = t sqrt(2g/a), and residual column
/// height H = eta/(2a) against tau = t sqrt(g/a). Files: dam_break_martin_moyce_n2{,_height}.csv.
struct MartinMoyce {
  Table front;
  Table height;
  /// Reads both tables from `directory` (normally referenceDirectory()).
  /// @throws IoError, InputError as Table::readCsv.
  static MartinMoyce load(const std::string& directory);
};

/// The shipped reference tables: `studies/reference` under dataDirectory() (sphfx/core/data_files.h).
/// @throws IoError when the data folder cannot be found.
std::string referenceDirectory();

/// Hydrostatic pressure rho0 g (H - y) at height y below a free surface at height H (0 above it).
double hydrostaticPressure(double restDensity, double gravity, double surfaceHeight, double y);

/// Transient plane Poiseuille flow between plates at y = 0 and y = L, started from rest at t = 0 by a
/// body force F along the plates (Morris, Fox & Zhu 1997, eq. 21):
///   v(y,t) = F/(2 nu) y (L - y) - sum_{n odd} 4 F L^2 / (nu pi^3 n^3) sin(n pi y / L) exp(-n^2 pi^2 nu t /
///   L^2)
/// summed until terms fall below 1e-12 of the steady maximum.
double poiseuilleVelocity(double y, double t, double plateDistance, double bodyForce, double viscosity);

/// Amplitude at time t of the 2D Taylor-Green vortex u = U sin(kx x) cos(kz z), w = -U (kx / kz)
/// cos(kx x) sin(kz z) with kx = 2 pi / Lx, kz = 2 pi / Lz, an exact solution of the incompressible
/// Navier-Stokes equations (the non-linear term is a pure gradient, balanced by the pressure; Taylor &
/// Green 1937): U(t) = U0 exp(-nu (kx^2 + kz^2) t), i.e. U0 exp(-8 pi^2 nu t / L^2) for Lx = Lz = L.
double taylorGreenAmplitude(double amplitude0, double t, double periodX, double periodZ, double viscosity);

}  // namespace sphfx::study
