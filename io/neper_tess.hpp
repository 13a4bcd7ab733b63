#pragma once
/// \file
/// Imported polycrystals: Neper's tessellation files (.tess, format 3.x, 3D) and plain grain
/// files (one grain a line: centroid, volume, Bunge angles). Every grain is an exact convex
/// polyhedron and the grains' exact volumes sum exactly to the domain's:
/// - a .tess is rebuilt as the Laguerre cells of its seeds (power |x - s|^2 - w^2, w the
///   file's seed weight) clipped by its planar domain, then each rebuilt cell is checked
///   against the file's own vertices (its rounded coordinates are not exactly coplanar, so
///   they are not used as the shape);
/// - a grain file's centroids become Laguerre seeds whose weights are fitted so the cells
///   take the given volumes (geometry::fitted_laguerre), in a given box.
/// Orientations become quaternions rotating crystal coordinates into specimen coordinates.

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/exact_polyhedron.hpp"

namespace cleave::io {

/// A tessellation file that cannot be read: what() reads "FILE:LINE: problem" (LINE 0 when
/// the problem is the whole file).
class TessellationFileError : public std::runtime_error {
 public:
  TessellationFileError(std::string file, int line, const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  int line_;
};

/// An imported tessellation, in metres.
struct ImportedTessellation {
  std::vector<geometry::ExactPolyhedron> cells;  ///< in file order, specimen coordinates
  std::vector<Eigen::Vector3d> seeds;            ///< the Laguerre points, metres
  std::vector<double> weights;                   ///< power weights (m^2)
  std::vector<int> ids;                          ///< the file's cell ids
  std::vector<Eigen::Quaterniond> orientations;  ///< crystal -> specimen; empty: none given
  std::string crystal_symmetry;                  ///< Neper's *crysym, empty if absent
  geometry::ExactScalar domain_volume;           ///< of the domain the cells tile, exactly
};

/// How far a rebuilt .tess cell's vertices may lie from the file's own (and back), relative
/// to the domain's bounding-box diagonal: Neper writes 12 decimals.
inline constexpr double kTessVertexTolerance = 1e-6;

/// Reads a Neper .tess (format 3.x, dimension 3, planar domain faces, not regularised, not
/// periodic). File lengths x `scale` = metres. Reads **cell (*id, *seed, *ori, *crysym;
/// others skipped), **vertex, **edge, **face, **polyhedron, **domain (*vertex, *face).
/// Throws TessellationFileError naming the file and line.
ImportedTessellation read_neper_tess(const std::filesystem::path& file, double scale = 1.0);
/// The same from text; `name` stands for the file in messages.
ImportedTessellation parse_neper_tess(const std::string& text, const std::string& name,
                                      double scale = 1.0);

/// Reads a plain grain file: one grain a line, `x y z volume phi1 Phi phi2` (centroid and
/// volume in file lengths, x `scale` = metres; Bunge angles in degrees, the standard passive
/// convention); blank lines and text after '#' ignored. The cells tile the box [0, size]
/// (metres): seeds at the centroids, weights fitted to the volumes, which must sum to the
/// box's volume within 1% (they are then scaled to it exactly). Throws
/// TessellationFileError naming the file and line.
ImportedTessellation read_grain_file(const std::filesystem::path& file, double scale,
                                     const Eigen::Vector3d& size);
ImportedTessellation parse_grain_file(const std::string& text, const std::string& name,
                                      double scale, const Eigen::Vector3d& size);

/// Bunge Euler angles (degrees) in the passive convention, g = Rz(phi2) Rx(Phi) Rz(phi1)
/// mapping specimen to crystal coordinates (Rz(a) = [[c, s, 0], [-s, c, 0], [0, 0, 1]],
/// Rx(a) = [[1, 0, 0], [0, c, s], [0, -s, c]]), as the rotation crystal -> specimen, g^T.
Eigen::Quaterniond quaternion_from_bunge_degrees(double phi1, double Phi, double phi2);

/// A Neper orientation: `descriptor` is "rodrigues", "euler-bunge", "rotmat", "axis-angle" or
/// "quaternion", optionally with ":active" (Neper's default) or ":passive"; `params` its
/// values (angles in degrees, rotmat row by row, axis-angle as axis then angle, quaternion
/// scalar first). Neper's formulas give a matrix g(params) (its orilib: the passive matrix
/// of the rotation the parameters describe); "passive" means g maps specimen to crystal
/// coordinates, "active" that g maps crystal to specimen (Neper inverts the rotation between
/// the two). Returns crystal -> specimen. Throws std::invalid_argument for an unknown
/// descriptor or convention, or the wrong number of parameters.
Eigen::Quaterniond neper_orientation(const std::string& descriptor,
                                     const std::vector<double>& params);
/// The number of parameters of a descriptor (the convention suffix ignored); 0 if unknown.
int neper_descriptor_size(const std::string& descriptor);

}  // namespace cleave::io
