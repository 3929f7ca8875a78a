#include "cdpile/io/xdmf.hpp"

#include "cdpile/analysis/local_state.hpp"
#include "cdpile/error.hpp"
#include "cdpile/io/products.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace cdpile::io::xdmf {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

std::string num(double v) { return format_number(v); }

/// Where an array lives, as an XDMF data item refers to it.
struct Array {
  std::string ref;   ///< FILE:/path
  std::string dims;  ///< "F N 2"
  std::string type;  ///< NumberType="Float" Precision="8"
};

Array array(const std::string& file, const std::string& path, const std::string& dims,
            const char* number, int precision) {
  return {
      xml_escape(file) + ":" + path, dims,
      std::string("NumberType=\"") + number + "\" Precision=\"" + std::to_string(precision) + "\""};
}

std::string item(const Array& a) {
  return "<DataItem Dimensions=\"" + a.dims + "\" " + a.type + " Format=\"HDF\">" + a.ref +
         "</DataItem>";
}

/// A hyperslab of `a`: start, count per dimension (stride 1), giving `result_dims`.
std::string slab(const Array& a, const std::vector<std::size_t>& start,
                 const std::vector<std::size_t>& count, const std::string& result_dims) {
  std::string sel;
  for (auto s : start) sel += std::to_string(s) + " ";
  for (std::size_t k = 0; k < start.size(); ++k) sel += "1 ";
  for (std::size_t k = 0; k < count.size(); ++k)
    sel += std::to_string(count[k]) + (k + 1 < count.size() ? " " : "");
  return "<DataItem ItemType=\"HyperSlab\" Dimensions=\"" + result_dims +
         "\" Type=\"HyperSlab\">"
         "<DataItem Dimensions=\"3 " +
         std::to_string(start.size()) + "\" Format=\"XML\">" + sel + "</DataItem>" + item(a) +
         "</DataItem>";
}

std::string attribute(const std::string& name, const char* type, const char* center,
                      const std::string& data) {
  return "   <Attribute Name=\"" + name + "\" AttributeType=\"" + type + "\" Center=\"" + center +
         "\">" + data + "</Attribute>\n";
}

/// A 3-vector (x, y, 0) from the two components of an [.., 2] array, by XDMF's JOIN.
std::string vector3(const std::string& x, const std::string& y, std::size_t n) {
  return "<DataItem ItemType=\"Function\" Function=\"JOIN($0, $1, 0 * $0)\" Dimensions=\"" +
         std::to_string(n) + " 3\">" + x + y + "</DataItem>";
}

std::string header() {
  return "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf "
         "Version=\"2.0\">\n <Domain>\n";
}

}  // namespace

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

Summary write_run(std::ostream& xml, const h5::File& sidecar, const RunReader& run,
                  const std::string& data_ref, const std::string& sidecar_ref, const Options& opt) {
  const std::string& file = run.name();
  const std::size_t F = run.frame_count(), N = run.grain_count();
  if (F == 0) throw Error(file, "/particles/grains/position", "no frame to show");
  const RunHeader& h = run.header();
  auto param = [&](const char* key) -> std::optional<double> {
    if (h.parameters.find(key) == h.parameters.end()) return std::nullopt;
    return as_real(h.parameters, key, file);
  };
  analysis::Friction mu;
  mu.grain = opt.mu ? *opt.mu : param("mu_grain").value_or(0.5);
  mu.wall = opt.mu_wall ? *opt.mu_wall : opt.mu ? *opt.mu : param("mu_wall").value_or(mu.grain);
  analysis::CriticalRule rule;
  rule.eps = opt.eps ? *opt.eps : param("critical_eps").value_or(analysis::default_eps);
  rule.include_walls = opt.walls;
  analysis::validate(rule, mu);
  const double diameter = analysis::mean_diameter(run.grain_properties());
  const std::vector<double> radii{opt.nu_radius * diameter};

  // Derived arrays: every frame read once.
  std::vector<std::size_t> offset(F), count(F);
  std::vector<double> nu(F * N, nan), mob;
  std::vector<std::uint8_t> critical;
  for (std::size_t k = 0; k < F; ++k) {
    const Frame fr = run.frame(k);
    const Contacts& c = fr.contacts;
    offset[k] = critical.size();
    count[k] = c.size();
    for (std::size_t q = 0; q < c.size(); ++q) {
      const double m = c.j[q] < 0 ? mu.wall : mu.grain;
      critical.push_back(analysis::is_critical(c.fn[q], c.ft[q], m, rule.eps) ? 1 : 0);
      mob.push_back(c.fn[q] > 0 ? std::abs(c.ft[q]) / (m * c.fn[q]) : nan);
    }
    analysis::ContactSet set;
    try {
      set = analysis::select_contacts(c, fr.grains.species, mu, rule);
    } catch (const Error& e) {
      throw Error(file, "/contacts", "frame " + std::to_string(k) + ": " + e.what());
    }
    if (set.size() == 0) continue;
    const analysis::NeighbourIndex index(set.point);
    const analysis::LocalStates s =
        analysis::local_states_at(index, set.critical, fr.grains.position, radii);
    for (std::size_t g = 0; g < N; ++g)
      if (auto v = s.nu(g, 0)) nu[k * N + g] = *v;
  }
  const std::size_t K = critical.size();
  h5::write(sidecar, "/grains/nu", nu.data(), {F, N}, {1, 4});
  h5::write(sidecar, "/contacts/critical", critical.data(), {K},
            {std::max<hsize_t>(1, std::min<hsize_t>(K, 16384)), 4});
  h5::write(sidecar, "/contacts/mobilisation", mob.data(), {K},
            {std::max<hsize_t>(1, std::min<hsize_t>(K, 16384)), 4});
  h5::set_attr(sidecar, "/grains/nu", "meaning",
               "critical / contacts (by the run's rule) within " + num(opt.nu_radius) +
                   " mean diameters of the grain's centre; NaN where none");
  h5::set_attr(sidecar, "/", "source", data_ref);

  const std::string sF = std::to_string(F), sN = std::to_string(N), sK = std::to_string(K);
  const std::string gp = "/particles/grains";
  const Array pos = array(data_ref, gp + "/position/value", sF + " " + sN + " 2", "Float", 8);
  const Array vel = array(data_ref, gp + "/velocity/value", sF + " " + sN + " 2", "Float", 8);
  const Array orient = array(data_ref, gp + "/orientation/value", sF + " " + sN, "Float", 8);
  const Array omega = array(data_ref, gp + "/angular_velocity/value", sF + " " + sN, "Float", 8);
  const Array nu_a = array(sidecar_ref, "/grains/nu", sF + " " + sN, "Float", 8);
  const Array tilt = array(data_ref, "/contacts/tilt_angle", sF, "Float", 8);
  const Array step = array(data_ref, "/contacts/step", sF, "Int", 8);
  const std::vector<double> times = [&] {
    std::vector<double> t(F);
    for (std::size_t k = 0; k < F; ++k) t[k] = run.frame_time(k);
    return t;
  }();

  xml << header();
  xml << "  <!-- " << xml_escape(file) << ": " << N << " grains, " << F << " frames, " << K
      << " contact rows; written by to-xdmf for ParaView's XDMF Reader (legacy XDMF 2) -->\n";
  xml << "  <Grid Name=\"grains\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < F; ++k) {
    xml << "  <Grid Name=\"grains_" << k << "\" GridType=\"Uniform\">\n   <Time Value=\""
        << num(times[k]) << "\"/>\n"
        << "   <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << N
        << "\" NodesPerElement=\"1\"/>\n"
        << "   <Geometry GeometryType=\"XY\">" << slab(pos, {k, 0, 0}, {1, N, 2}, sN + " 2")
        << "</Geometry>\n";
    xml << attribute("radius", "Scalar", "Node",
                     item(array(data_ref, gp + "/radius", sN, "Float", 8)));
    xml << attribute("species", "Scalar", "Node",
                     item(array(data_ref, gp + "/species", sN, "UChar", 1)));
    xml << attribute("mass", "Scalar", "Node", item(array(data_ref, gp + "/mass", sN, "Float", 8)));
    xml << attribute("velocity", "Vector", "Node",
                     vector3(slab(vel, {k, 0, 0}, {1, N, 1}, sN + " 1"),
                             slab(vel, {k, 0, 1}, {1, N, 1}, sN + " 1"), N));
    xml << attribute("angular_velocity", "Scalar", "Node", slab(omega, {k, 0}, {1, N}, sN));
    xml << attribute("orientation", "Scalar", "Node", slab(orient, {k, 0}, {1, N}, sN));
    xml << attribute("nu", "Scalar", "Node", slab(nu_a, {k, 0}, {1, N}, sN));
    xml << attribute("tilt_angle", "Scalar", "Grid", slab(tilt, {k}, {1}, "1"));
    xml << attribute("step", "Scalar", "Grid", slab(step, {k}, {1}, "1"));
    xml << "  </Grid>\n";
  }
  xml << "  </Grid>\n";

  const std::string cg = "/contacts";
  const Array point = array(data_ref, cg + "/point", sK + " 2", "Float", 8);
  const Array normal = array(data_ref, cg + "/normal", sK + " 2", "Float", 8);
  xml << "  <Grid Name=\"contacts\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < F; ++k) {
    const std::size_t o = offset[k], c = count[k];
    const std::string sc = std::to_string(c);
    auto one = [&](const char* name, const std::string& ref, const char* type, int precision) {
      return slab(array(ref, name[0] == '/' ? name : cg + "/" + name, sK, type, precision), {o},
                  {c}, sc);
    };
    xml << "  <Grid Name=\"contacts_" << k << "\" GridType=\"Uniform\">\n   <Time Value=\""
        << num(times[k]) << "\"/>\n"
        << "   <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << c
        << "\" NodesPerElement=\"1\"/>\n"
        << "   <Geometry GeometryType=\"XY\">" << slab(point, {o, 0}, {c, 2}, sc + " 2")
        << "</Geometry>\n";
    xml << attribute("i", "Scalar", "Node", one("i", data_ref, "Int", 4));
    xml << attribute("j", "Scalar", "Node", one("j", data_ref, "Int", 4));
    xml << attribute("fn", "Scalar", "Node", one("fn", data_ref, "Float", 8));
    xml << attribute("ft", "Scalar", "Node", one("ft", data_ref, "Float", 8));
    xml << attribute("gap", "Scalar", "Node", one("gap", data_ref, "Float", 8));
    xml << attribute("status", "Scalar", "Node", one("status", data_ref, "Char", 1));
    xml << attribute("critical", "Scalar", "Node", one("critical", sidecar_ref, "UChar", 1));
    xml << attribute("mobilisation", "Scalar", "Node",
                     one("mobilisation", sidecar_ref, "Float", 8));
    xml << attribute("normal", "Vector", "Node",
                     vector3(slab(normal, {o, 0}, {c, 1}, sc + " 1"),
                             slab(normal, {o, 1}, {c, 1}, sc + " 1"), c));
    xml << attribute("tilt_angle", "Scalar", "Grid", slab(tilt, {k}, {1}, "1"));
    xml << "  </Grid>\n";
  }
  xml << "  </Grid>\n";

  // The walls: left wall down, the floor, right wall up (the box frame; gravity turns).
  double top = h.box.height;
  {
    const Frame last = run.frame(F - 1);
    for (std::size_t g = 0; g < N; ++g)
      top = std::max(top, last.grains.position[g].y() + last.grains.radius[g]);
  }
  const double w = h.box.width;
  xml << "  <Grid Name=\"walls\" GridType=\"Uniform\">\n"
      << "   <Topology TopologyType=\"Polyline\" NumberOfElements=\"1\" NodesPerElement=\"4\">"
         "<DataItem Dimensions=\"1 4\" NumberType=\"Int\" Format=\"XML\">0 1 2 "
         "3</DataItem></Topology>\n"
      << "   <Geometry GeometryType=\"XY\"><DataItem Dimensions=\"4 2\" NumberType=\"Float\" "
         "Precision=\"8\" "
         "Format=\"XML\">0 "
      << num(top) << " 0 0 " << num(w) << " 0 " << num(w) << " " << num(top)
      << "</DataItem></Geometry>\n  </Grid>\n";
  xml << " </Domain>\n</Xdmf>\n";
  return {h.kind, F, N, K, 0, 0};
}

Summary write_localnu(std::ostream& xml, const h5::File& sidecar, const h5::File& product,
                      const std::string& data_ref, const std::string& sidecar_ref) {
  const ProductFile pf = read_product_hdf5(product);
  const analysis::Product& p = pf.product;
  if (p.kind != "localnu")
    throw Error(product.name(), "/",
                "is a '" + p.kind + "' product; to-xdmf shows piles, runs and localnu maps");
  const analysis::Table* map = p.find("map");
  if (!map)
    throw Error(product.name(), "/tables",
                "no map table (localnu writes one for the mapped frame)");
  const auto nx = p.result("map_nx"), ny = p.result("map_ny");
  if (!nx || !ny || *nx < 1 || *ny < 1)
    throw Error(product.name(), "/results", "no map_nx, map_ny");
  const auto NX = static_cast<std::size_t>(*nx), NY = static_cast<std::size_t>(*ny);
  if (map->rows() != NX * NY)
    throw Error(product.name(), "/tables/map",
                std::to_string(map->rows()) + " rows for a " + std::to_string(NX) + " x " +
                    std::to_string(NY) + " grid");
  const auto& x = map->column("x");
  const auto& y = map->column("y");
  const double x0 = x.num[0], y0 = y.num[0];
  const double dx = NX > 1 ? x.num[1] - x.num[0] : NY > 1 ? y.num[NX] - y.num[0] : 1.0;
  // The map's columns as [ny][nx] grids (missing values NaN), in the small file beside.
  const std::string dims = "1 " + std::to_string(NY) + " " + std::to_string(NX);
  for (const char* name : {"nu", "above", "contacts", "critical"}) {
    std::vector<double> v(NX * NY);
    for (std::size_t r = 0; r < NX * NY; ++r) v[r] = map->column(name).get(r).value_or(nan);
    h5::write(sidecar, std::string("/map/") + name, v.data(), {1, NY, NX});
  }
  h5::set_attr(sidecar, "/", "source", data_ref);
  auto field = [&](const char* name) {
    return "<DataItem Dimensions=\"" + dims +
           "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" + xml_escape(sidecar_ref) +
           ":/map/" + name + "</DataItem>";
  };
  xml << header();
  xml << "  <!-- " << xml_escape(product.name()) << ": the nu field of localnu's mapped frame, "
      << NX << " x " << NY
      << " nodes; written by to-xdmf for ParaView's XDMF Reader (legacy XDMF 2) -->\n";
  xml << "  <Grid Name=\"nu_field\" GridType=\"Uniform\">\n"
      << "   <Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"" << dims << "\"/>\n"
      << "   <Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n"
      << "    <DataItem Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">0 "
      << num(y0) << " " << num(x0) << "</DataItem>\n"
      << "    <DataItem Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">1 "
      << num(dx) << " " << num(dx) << "</DataItem>\n   </Geometry>\n";
  for (const char* name : {"nu", "above", "contacts", "critical"})
    xml << attribute(name, "Scalar", "Node", field(name));
  xml << "  </Grid>\n </Domain>\n</Xdmf>\n";
  return {"localnu", 1, 0, 0, NX, NY};
}

std::string paraview_state(const Summary& s, const std::string& xdmf_name,
                           const std::string& xdmf_path) {
  auto py = [](const std::string& v) {  // a Python string literal
    std::string out = "\"";
    for (char c : v) out += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
    return out + "\"";
  };
  std::ostringstream o;
  o << "# ParaView state written by to-xdmf for " << xdmf_name << " (ParaView 5.11 or later).\n"
    << "# In ParaView: File > Load State..., this file. Or: paraview --state=THIS_FILE, or "
       "pvpython THIS_FILE.\n"
    << "import os\n"
    << "from paraview.simple import *\n\n"
    << "try:\n    here = os.path.dirname(os.path.abspath(__file__))\nexcept NameError:\n    here = "
       "os.getcwd()\n"
    << "xdmf = os.path.join(here, " << py(xdmf_name) << ")\n"
    << "if not os.path.exists(xdmf):\n    xdmf = " << py(xdmf_path) << "\n"
    << "reader = XDMFReader(registrationName=" << py(xdmf_name) << ", FileNames=[xdmf])\n"
    << "reader.UpdatePipelineInformation()\n"
    << "view = GetActiveViewOrCreate(\"RenderView\")\n"
    << "view.InteractionMode = \"2D\"\n"
    << "view.OrientationAxesVisibility = 0\n";
  if (s.kind == "localnu") {
    o << "field = Show(reader, view)\n"
      << "field.SetRepresentationType(\"Surface\")\n"
      << "ColorBy(field, (\"POINTS\", \"nu\"))\n"
      << "lut = GetColorTransferFunction(\"nu\")\n"
      << "lut.RescaleTransferFunction(0.0, 1.0)\n"
      << "lut.NanColor = [0.8, 0.8, 0.8]\n"
      << "field.SetScalarBarVisibility(view, True)\n";
  } else {
    o << "# the grains: disks of their own radius (Point Gaussian scaled by the radius array)\n"
      << "grains = ExtractBlock(registrationName=\"grains\", Input=reader, "
         "Selectors=[\"/Root/grains\"])\n"
      << "disks = Show(grains, view)\n"
      << "disks.SetRepresentationType(\"Point Gaussian\")\n"
      << "disks.ShaderPreset = \"Plain circle\"\n"
      << "disks.ScaleByArray = 1\n"
      << "disks.SetScaleArray = [\"POINTS\", \"radius\"]\n"
      << "disks.UseScaleFunction = 0\n"
      << "disks.GaussianRadius = 1.0\n"
      << "ColorBy(disks, (\"POINTS\", \"nu\"))\n"
      << "lut = GetColorTransferFunction(\"nu\")\n"
      << "lut.AutomaticRescaleRangeMode = \"Never\"\n"
      << "lut.RescaleTransferFunction(0.0, 1.0)\n"
      << "lut.NanColor = [0.8, 0.8, 0.8]\n"
      << "disks.SetScalarBarVisibility(view, True)\n"
      << "# the walls\n"
      << "walls = ExtractBlock(registrationName=\"walls\", Input=reader, "
         "Selectors=[\"/Root/walls\"])\n"
      << "box = Show(walls, view)\n"
      << "box.ColorArrayName = [\"POINTS\", \"\"]\n"
      << "box.AmbientColor = box.DiffuseColor = [0.3, 0.3, 0.3]\n"
      << "box.LineWidth = 2.0\n"
      << "# the contacts, hidden: click the eye beside 'contacts' (coloured by critical)\n"
      << "contacts = ExtractBlock(registrationName=\"contacts\", Input=reader, "
         "Selectors=[\"/Root/contacts\"])\n"
      << "points = Show(contacts, view)\n"
      << "points.SetRepresentationType(\"Points\")\n"
      << "points.PointSize = 4.0\n"
      << "ColorBy(points, (\"POINTS\", \"critical\"))\n"
      << "Hide(contacts, view)\n"
      << "scene = GetAnimationScene()\n"
      << "scene.UpdateAnimationUsingDataTimeSteps()\n";
  }
  o << "SetActiveSource(reader)\n"
    << "ResetCamera(view)\n"
    << "Render(view)\n";
  return o.str();
}

}  // namespace cdpile::io::xdmf
