#pragma once
/// @file geometry.hpp
/// Pure helpers shared by the static picture (ucon-plot) and the playback page (ucon-view):
/// covariance ellipses, the paper's uncertainty sectors, colour maps and "nice" scale lengths.

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ucon {
namespace plot {

/// An ellipse: centre, semi-axes and orientation of the major axis.
struct Ellipse {
  double a = 0.0;      ///< semi-major axis [m]
  double b = 0.0;      ///< semi-minor axis [m]
  double angle = 0.0;  ///< angle of the major axis from +x [rad]
};

/// The `n_sigma` ellipse of a 2x2 covariance [m^2]: semi-axes n_sigma * sqrt(eigenvalues).
/// nullopt when the matrix is not finite, not symmetric (to 1e-9 relative) or not PSD.
std::optional<Ellipse> covarianceEllipse(const Eigen::Matrix2d& cov, double n_sigma);

/// Parameters of the uncertainty sector, paper Sec. IV-B (defaults are the paper's; the
/// planner's SectorParams/OptimizerParams use the same names and values).
struct SectorParams {
  double h = 0.02;              ///< velocity term of the radius [s]
  double k = 2.0;               ///< radial uncertainty multiplier [-]
  double kappa = 0.05;          ///< lateral gain of the central angle [-]
  double safe_distance = 0.4;   ///< s [m]
  double min_speed = 0.05;      ///< slower objects have no direction: drawn as a disk [m/s]
};

/// The sector of one object at the time of its state.
struct Sector {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< object position [m]
  double radius = 0.0;      ///< R_i [m]
  double heading = 0.0;     ///< direction of the velocity [rad]
  double half_angle = 0.0;  ///< θ_i / 2 [rad]; π for a disk (slow object)
};

/// Paper eq. (6)/(7) at the state's own time: R = |v| h + k sqrt(v̂ᵀ Σ v̂) + r/2 + s,
/// θ = 2 atan(κ sqrt(ûᵀ Σ û) / (|v| h)), with r the x-y diagonal of the box. Below
/// min_speed the direction is undefined: a disk of radius r/2 + s + k sqrt(tr Σ) (as the
/// planner does). A missing covariance counts as zero. nullopt for non-finite input.
std::optional<Sector> uncertaintySector(const Eigen::Vector2d& position, const Eigen::Vector2d& velocity,
                                        const Eigen::Matrix2d& cov_xy, bool has_cov, double box_diagonal,
                                        const SectorParams& params);

/// Axis-aligned bounds [m].
struct Bounds {
  double min_x = 0.0, min_y = 0.0, max_x = 0.0, max_y = 0.0;
  bool valid = false;
  void add(double x, double y);   ///< ignores non-finite points
  void pad(double fraction, double minimum);  ///< grows each side by fraction * size (at least minimum) [m]
  bool contains(double x, double y) const { return valid && x >= min_x && x <= max_x && y >= min_y && y <= max_y; }
  double width() const { return max_x - min_x; }
  double height() const { return max_y - min_y; }
};

/// The area a picture of a run shows: the robot's path, its plans and the static map, plus
/// moving objects within `margin` [m] of those (objects beyond are still drawn, clipped), so
/// that one spurious far-away track does not shrink the run to a dot. Without a robot path
/// or map, `objects` alone.
Bounds focusBounds(const Bounds& robot_and_map, const std::vector<Eigen::Vector2d>& objects, double margin);

/// RGB in [0, 1].
struct Rgb {
  double r = 0.0, g = 0.0, b = 0.0;
};

/// Viridis-like perceptual colour map; u is clamped to [0, 1] (NaN -> 0).
Rgb speedColour(double u);

/// A distinct colour per object id (stable over the run, 10 Tableau-like colours).
Rgb idColour(int64_t id);

/// "#rrggbb".
std::string toHex(const Rgb& c);

/// A round length (1, 2 or 5 times a power of ten) close to but not above `max_length`
/// (> 0); 0 for non-positive or non-finite input.
double niceLength(double max_length);


}  // namespace plot
}  // namespace ucon
