/// XDMF descriptions of cdpile files for ParaView (docs/analysis.md, "Seeing the grains").
///
/// ParaView has no H5MD reader. An XDMF file is a small XML text that tells it where the
/// arrays are inside the HDF5 file, so it reads them in place, without a copy. The layout
/// written here is for ParaView's legacy "XDMF Reader" (XDMF 2): each frame's grains are a
/// hyperslab of /particles/grains/position/value; ParaView's newer Xdmf3 readers crash on
/// hyperslabs (ParaView 5.11), so they are not the target.
///
///   pile or run: three grids
///     grains    a temporal collection, one grid per frame (Time = the frame's time in s):
///               points at the grain centres (z = 0) with radius, species, mass, velocity
///               (a 3-vector, z = 0), angular_velocity, orientation, nu (below) and the
///               frame's tilt_angle and step as field data;
///     contacts  a temporal collection: points at the contact points with i, j, fn, ft,
///               gap, status, normal (3-vector), critical (1 if critical by the run's rule)
///               and mobilisation |f_t| / (mu f_n);
///     walls     the floor and side walls as lines.
///   localnu product with a map: the nu field of the mapped frame on its grid (nu, above,
///   contacts, critical at each node).
/// What the run file does not hold, computed once, goes into a small HDF5 file beside the
/// XDMF (NAME.xdmf.hdf5: not .h5, so that globs of runs like run*.h5 do not take it): per contact
/// `critical` and `mobilisation`; per grain and frame `nu`, the local state at the grain's centre,
/// critical / contacts within `nu_radius` (in mean diameters; 6 D as localnu's map), NaN where no
/// contact is within reach; for a product, nu and above with NaN where the map has no value.
#pragma once

#include "cdpile/analysis/critical.hpp"
#include "cdpile/io/schema.hpp"

#include <optional>
#include <ostream>
#include <string>

namespace cdpile::io::xdmf {

struct Options {
  double nu_radius = 6.0;     ///< [D] radius of the grains' local state nu
  std::optional<double> eps;  ///< critical tolerance (default: the run's critical_eps, else 1e-3)
  std::optional<double> mu, mu_wall;  ///< friction (default: the run's mu_grain, mu_wall)
  bool walls = false;                 ///< nu counts wall contacts too (critical's --walls)
};

struct Summary {
  std::string kind;  ///< pile, run or localnu
  std::size_t frames = 0, grains = 0, contacts = 0;
  std::size_t nx = 0, ny = 0;  ///< the map's nodes (localnu)
};

/// Writes the XDMF text of a pile or run into `xml` and the derived arrays into `sidecar`
/// (a new, empty HDF5 file). `data_ref` and `sidecar_ref` are the two files' names as the
/// XDMF refers to them (relative to the XDMF's folder).
Summary write_run(std::ostream& xml, const h5::File& sidecar, const RunReader& run,
                  const std::string& data_ref, const std::string& sidecar_ref,
                  const Options& opt = {});

/// The same for a localnu product (HDF5) with a map. Error if it has no map.
Summary write_localnu(std::ostream& xml, const h5::File& sidecar, const h5::File& product,
                      const std::string& data_ref, const std::string& sidecar_ref);

/// A ParaView Python state that opens the XDMF (named `xdmf_name`, beside it; `xdmf_path`
/// absolute, as a fallback) and shows what `summary` describes: the grains as disks of
/// their radius coloured by nu, the walls, the contacts (hidden, ready to show); or the nu
/// field of a product. File > Load State in ParaView, `paraview --state=FILE`, or
/// `pvpython FILE`.
std::string paraview_state(const Summary& summary, const std::string& xdmf_name,
                           const std::string& xdmf_path);

/// Text escaped for an XML attribute or element.
std::string xml_escape(const std::string& s);

}  // namespace cdpile::io::xdmf
