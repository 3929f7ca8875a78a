/// XDMF descriptions of cdpile files for ParaView (docs/analysis.md, "Seeing the grains").
///
/// ParaView has no H5MD reader. An XDMF file is a small XML text that tells it where the
/// arrays are inside HDF5 files, so it reads them in place. ParaView 5.11's File > Open picks
/// its Xdmf3 reader, which reads neither XDMF hyperslabs nor functions (a hyperslab geometry
/// crashed it with SIGSEGV: the array of a reference item has no type until read, and the
/// reader copies the geometry without reading it). So every array an XDMF names here is a
/// whole dataset: what the run holds, as virtual datasets (HDF5 1.10 VDS) in a small file
/// beside the XDMF, mapped onto the run's rows and never copied; what is derived, as real
/// datasets of that file (analysis::frame_fields, handed in by reading/views.hpp). Both the Xdmf3
/// reader and the legacy XDMF Reader load them.
///
///   pile or run, two XDMF files:
///     NAME.xdmf          grains, a temporal collection, one grid per frame (Time = the
///                        frame's time in s): one vertex per grain centre (z = 0) with radius,
///                        species, mass, velocity (a 3-vector, z = 0), angular_velocity,
///                        orientation, nu (below) and the frame's tilt_angle and step as field
///                        data. File > Open of it loads one point per grain.
///     STEM.network.xdmf  contacts: per frame one segment per contact row, between the
///                        centres of i and j (for a wall, from the centre of i to the contact
///                        point), with i, j, fn, ft, gap, status, normal, point, critical
///                        (1 if critical by the run's rule), mobilisation |f_t| / (mu f_n) and
///                        fn_rel = f_n / <f_n> (the mean over the frame's active contacts);
///                        gravity: an arrow above the pile along g = (sin theta, -cos theta),
///                        the box frame's gravity; walls: the floor and side walls as lines.
///   localnu product with a map: the nu field of the mapped frame on its grid (nu, above,
///   contacts, critical at each node).
/// The file beside (NAME.xdmf.hdf5: not .h5, so that globs of runs like run*.h5 do not take
/// it): /frames/K/... per frame; nu of a grain is the local state at its centre, critical /
/// contacts within `nu_radius` (in mean diameters; 6 D as localnu's map), NaN where no
/// contact is within reach; for a product, nu and above with NaN where the map has no value.
#pragma once

#include "cdpile/analysis/frame_fields.hpp"
#include "cdpile/io/schema.hpp"

#include <functional>
#include <ostream>
#include <string>

namespace cdpile::io::xdmf {

/// What a view derives from a run's frames, decided by the analysis layer and handed in
/// (reading/views.hpp): io writes the fields, it does not choose which contact is critical.
struct Derived {
  /// One frame's fields: nu of every grain; each contact row's critical flag, mobilisation
  /// and f_n / <f_n>. A cdpile::Error it throws is reported with the file and the frame.
  std::function<analysis::FrameFields(const Frame&)> fields;
  double diameter = 0;   ///< the grains' mean diameter [m]: the view's length scale
  double nu_radius = 0;  ///< [D] the radius of nu, for the sidecar's description
};

struct Summary {
  std::string kind;  ///< pile, run or localnu
  std::size_t frames = 0, grains = 0, contacts = 0;
  std::size_t nx = 0, ny = 0;  ///< the map's nodes (localnu)
  // For the state's view of a pile or run:
  double nu_max = 0;          ///< the largest nu of a grain over the frames (0: none)
  double fn_rel_high = 0;     ///< 99th percentile of f_n / <f_n> over the frames' contacts
  double diameter = 0;        ///< mean diameter [m]
  double width = 0, top = 0;  ///< the box's width and the walls' top [m]
  double tilt_last_deg = 0;   ///< the last frame's tilt angle [degree]
};

/// Writes the XDMF text of a pile's or run's grains into `xml`, of its network, gravity and
/// walls into `network_xml`, and every frame's arrays into `sidecar` (a new, empty HDF5 file):
/// the run's own as virtual datasets, `derived`'s fields as real ones.
/// `data_ref` and `sidecar_ref` are the two files' names as the XDMF refers to them (relative
/// to the XDMF's folder; the virtual datasets name the run by `data_ref` too).
Summary write_run(std::ostream& xml, std::ostream& network_xml, const h5::File& sidecar,
                  const RunReader& run, const std::string& data_ref, const std::string& sidecar_ref,
                  const Derived& derived);

/// The same for a localnu product (HDF5) with a map. Error if it has no map.
Summary write_localnu(std::ostream& xml, const h5::File& sidecar, const h5::File& product,
                      const std::string& data_ref, const std::string& sidecar_ref);

/// A ParaView Python state that opens the XDMF (named `xdmf_name`, beside it; `xdmf_path`
/// absolute, as a fallback; for a run also the network's, `network_name`) and shows what
/// `summary` describes: the grains as disks of their radius coloured by nu on the run's
/// range, the force network grey to black by f_n / <f_n>, the critical contacts in red,
/// gravity, the walls and the tilt angle as text; or the nu field of a product. File > Load State
/// in ParaView, `paraview --state=FILE`, or `pvpython FILE`.
std::string paraview_state(const Summary& summary, const std::string& xdmf_name,
                           const std::string& xdmf_path, const std::string& network_name = "",
                           const std::string& network_path = "");

/// Text escaped for an XML attribute or element.
std::string xml_escape(const std::string& s);

}  // namespace cdpile::io::xdmf
