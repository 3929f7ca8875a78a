#include "cdpile/io/xdmf.hpp"

#include "cdpile/error.hpp"
#include "cdpile/io/products.hpp"
#include "cdpile/parameter_keys.hpp"

#include <algorithm>
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

std::string attribute(const std::string& name, const char* type, const char* center,
                      const std::string& data) {
  return "   <Attribute Name=\"" + name + "\" AttributeType=\"" + type + "\" Center=\"" + center +
         "\">" + data + "</Attribute>\n";
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

namespace {

// A pile's or run's frames as write_run reads them: the rows of each frame in the file, its
// tilt and step.
struct RunFrames {
  std::vector<std::int64_t> offsets, steps;
  std::vector<double> tilt_deg;
  std::vector<std::size_t> count;  // contacts per frame
};

// How the XDMF text names the sidecar's arrays and the frames' times.
struct Refs {
  const RunReader& run;
  const std::string &data_ref, &sidecar_ref;
  std::string side(const std::string& path, const std::string& dims, const char* type,
                   int precision) const {
    return item(array(sidecar_ref, path, dims, type, precision));
  }
  std::string time_of(std::size_t k) const { return num(run.frame_time(k)); }
};

std::string literal(double v, const char* type, int precision) {
  return std::string("<DataItem Dimensions=\"1\" NumberType=\"") + type + "\" Precision=\"" +
         std::to_string(precision) + "\" Format=\"XML\">" + num(v) + "</DataItem>";
}

// Stage 1: every frame's arrays in the sidecar: virtual datasets mapped onto the run's rows
// for what the run holds, real ones for what is derived (nu of every grain, each contact's
// critical flag, mobilisation and fn_rel: `derived`), the network's segments; the summary's
// counts, top and colour ranges.
void write_sidecar(const h5::File& sidecar, const RunReader& run, const std::string& data_ref,
                   const Derived& derived, RunFrames& rf, Summary& sum) {
  // Every frame's arrays are whole datasets of the file beside (ParaView's Xdmf3 reader
  // reads no hyperslab, and crashes on a hyperslab geometry): virtual datasets for what the
  // run holds, mapped onto its rows and never copied; real ones for what is derived.
  const std::string& file = run.name();
  const h5::File& data = run.file();
  const std::size_t F = run.frame_count(), N = run.grain_count();
  const std::string cg = "/contacts", gp = "/particles/grains";
  std::vector<std::size_t>& count = rf.count;
  count.assign(F, 0);
  analysis::ColourRanges ranges;
  double top = run.header().box.height;
  for (std::size_t k = 0; k < F; ++k) {
    const Frame fr = run.frame(k);
    const Contacts& c = fr.contacts;
    const auto o = static_cast<hsize_t>(rf.offsets[k]);
    const hsize_t nc = c.size(), n = N;
    count[k] = c.size();
    sum.contacts += c.size();
    const std::string fk = "/frames/" + std::to_string(k);
    auto vmap = [&](const std::string& path, const std::string& src, std::vector<hsize_t> dims,
                    std::vector<hsize_t> src_start, std::vector<hsize_t> src_count,
                    std::vector<hsize_t> dst_count) {
      h5::write_virtual(
          sidecar, fk + path, dims, data, data_ref,
          {{src, src_start, src_count, std::vector<hsize_t>(dims.size(), 0), dst_count}});
    };
    vmap("/position", gp + "/position/value", {n, 2}, {k, 0, 0}, {1, n, 2}, {n, 2});
    vmap("/velocity", gp + "/velocity/value", {n, 3}, {k, 0, 0}, {1, n, 2}, {n, 2});
    vmap("/angular_velocity", gp + "/angular_velocity/value", {n}, {k, 0}, {1, n}, {n});
    vmap("/orientation", gp + "/orientation/value", {n}, {k, 0}, {1, n}, {n});
    for (std::size_t g = 0; g < N; ++g)
      top = std::max(top, fr.grains.position[g].y() + fr.grains.radius[g]);

    // nu of every grain, and each contact's critical flag, mobilisation and fn_rel
    analysis::FrameFields fields;
    try {
      fields = derived.fields(fr);
    } catch (const Error& e) {
      throw Error(file, "/contacts", "frame " + std::to_string(k) + ": " + e.what());
    }
    ranges.add(fields);
    h5::write(sidecar, fk + "/nu", fields.nu);
    if (nc == 0) continue;

    // The force network: a segment per contact, from the centre of i to the centre of j,
    // or to the contact point for a wall (the points after the grains' centres).
    h5::write_virtual(sidecar, fk + "/network/points", {n + nc, 2}, data, data_ref,
                      {{gp + "/position/value", {k, 0, 0}, {1, n, 2}, {0, 0}, {n, 2}},
                       {cg + "/point", {o, 0}, {nc, 2}, {n, 0}, {nc, 2}}});
    std::vector<std::int32_t> lines(2 * nc);
    for (std::size_t q = 0; q < nc; ++q) {
      lines[2 * q] = c.i[q];
      lines[2 * q + 1] = c.j[q] >= 0 ? c.j[q] : static_cast<std::int32_t>(N + q);
    }
    h5::write(sidecar, fk + "/network/lines", lines.data(), {nc, 2});
    h5::write(sidecar, fk + "/contacts/critical", fields.critical);
    h5::write(sidecar, fk + "/contacts/mobilisation", fields.mobilisation);
    h5::write(sidecar, fk + "/contacts/fn_rel", fields.fn_rel);
    for (const char* name : {"i", "j", "fn", "ft", "gap", "status"})
      vmap(std::string("/contacts/") + name, cg + "/" + name, {nc}, {o}, {nc}, {nc});
    vmap("/contacts/normal", cg + "/normal", {nc, 3}, {o, 0}, {nc, 2}, {nc, 2});
    vmap("/contacts/point", cg + "/point", {nc, 3}, {o, 0}, {nc, 2}, {nc, 2});
  }
  sum.top = top;
  sum.nu_max = ranges.nu_max();
  sum.fn_rel_high = ranges.fn_rel_high();
  {  // the grains' vertices: without them the Xdmf3 reader makes points but no cells
    std::vector<std::int32_t> v(N);
    for (std::size_t g = 0; g < N; ++g) v[g] = static_cast<std::int32_t>(g);
    h5::write(sidecar, "/grains/vertices", v);
  }
  h5::set_attr(sidecar, "/", "source", data_ref);
  h5::set_attr(sidecar, "/", "meaning",
               "/frames/K: frame K of the source; virtual datasets read the source's rows in "
               "place; nu: critical / contacts (by the run's rule) within " +
                   num(derived.nu_radius) +
                   " mean diameters of the grain's centre, NaN where none; contacts/critical: 1 "
                   "if critical by the run's rule; mobilisation: |ft| / (mu fn); fn_rel: fn / "
                   "the mean fn of the frame's active contacts; network/lines: the two points "
                   "of each contact's segment in network/points (the grains' centres, then the "
                   "contact points)");
}

// Stage 2: the grains' XDMF, a temporal collection of one grid per frame.
void write_grains_xml(std::ostream& xml, const Refs& x, const RunFrames& rf, std::size_t N,
                      std::size_t contacts) {
  const std::string& file = x.run.name();
  const std::string& data_ref = x.data_ref;
  const std::string gp = "/particles/grains";
  const std::size_t F = rf.tilt_deg.size();
  const std::string sN = std::to_string(N);
  xml << header();
  xml << "  <!-- " << xml_escape(file) << ": " << N << " grains, " << F << " frames, " << contacts
      << " contact rows; written by to-xdmf for ParaView's XDMF readers (Xdmf3 and the legacy "
         "XDMF 2) -->\n";
  xml << "  <Grid Name=\"grains\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < F; ++k) {
    const std::string fk = "/frames/" + std::to_string(k);
    xml << "  <Grid Name=\"grains_" << k << "\" GridType=\"Uniform\">\n   <Time Value=\""
        << x.time_of(k) << "\"/>\n"
        << "   <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << N
        << "\" NodesPerElement=\"1\">" << x.side("/grains/vertices", sN, "Int", 4)
        << "</Topology>\n"
        << "   <Geometry GeometryType=\"XY\">" << x.side(fk + "/position", sN + " 2", "Float", 8)
        << "</Geometry>\n";
    xml << attribute("radius", "Scalar", "Node",
                     item(array(data_ref, gp + "/radius", sN, "Float", 8)));
    xml << attribute("species", "Scalar", "Node",
                     item(array(data_ref, gp + "/species", sN, "UChar", 1)));
    xml << attribute("mass", "Scalar", "Node", item(array(data_ref, gp + "/mass", sN, "Float", 8)));
    xml << attribute("velocity", "Vector", "Node", x.side(fk + "/velocity", sN + " 3", "Float", 8));
    xml << attribute("angular_velocity", "Scalar", "Node",
                     x.side(fk + "/angular_velocity", sN, "Float", 8));
    xml << attribute("orientation", "Scalar", "Node", x.side(fk + "/orientation", sN, "Float", 8));
    xml << attribute("nu", "Scalar", "Node", x.side(fk + "/nu", sN, "Float", 8));
    xml << attribute("tilt_angle", "Scalar", "Grid", literal(rf.tilt_deg[k], "Float", 8));
    xml << attribute("step", "Scalar", "Grid", literal(static_cast<double>(rf.steps[k]), "Int", 8));
    xml << "  </Grid>\n";
  }
  xml << "  </Grid>\n </Domain>\n</Xdmf>\n";
}

// Stage 3: the force network's XDMF, one grid of segments per frame.
void write_network_xml(std::ostream& net, const Refs& x, const RunFrames& rf, std::size_t N) {
  const std::string& file = x.run.name();
  const std::size_t F = rf.tilt_deg.size();
  const std::string sN = std::to_string(N);
  // The second file: what is drawn over the grains. Apart, so that the file a user opens
  // holds one point per grain; every grid temporal, so that the Xdmf3 reader keeps them all.
  net << header();
  net << "  <!-- " << xml_escape(file) << ": the force network of " << F
      << " frames, gravity and the walls; written by to-xdmf for ParaView's XDMF readers -->\n";
  net << "  <Grid Name=\"contacts\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < F; ++k) {
    const std::string fk = "/frames/" + std::to_string(k);
    const std::size_t c = rf.count[k];
    const std::string sc = std::to_string(c), sP = std::to_string(N + c);
    net << "  <Grid Name=\"contacts_" << k << "\" GridType=\"Uniform\">\n   <Time Value=\""
        << x.time_of(k) << "\"/>\n";
    if (c == 0) {  // no segment: the grains' centres alone
      net << "   <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << N
          << "\" NodesPerElement=\"1\"/>\n"
          << "   <Geometry GeometryType=\"XY\">" << x.side(fk + "/position", sN + " 2", "Float", 8)
          << "</Geometry>\n";
    } else {
      net << "   <Topology TopologyType=\"Polyline\" NumberOfElements=\"" << c
          << "\" NodesPerElement=\"2\">" << x.side(fk + "/network/lines", sc + " 2", "Int", 4)
          << "</Topology>\n"
          << "   <Geometry GeometryType=\"XY\">"
          << x.side(fk + "/network/points", sP + " 2", "Float", 8) << "</Geometry>\n";
      const std::string ck = fk + "/contacts/";
      for (const char* name : {"i", "j"})
        net << attribute(name, "Scalar", "Cell", x.side(ck + name, sc, "Int", 4));
      for (const char* name : {"fn", "ft", "gap"})
        net << attribute(name, "Scalar", "Cell", x.side(ck + name, sc, "Float", 8));
      net << attribute("status", "Scalar", "Cell", x.side(ck + "status", sc, "Char", 1));
      net << attribute("critical", "Scalar", "Cell", x.side(ck + "critical", sc, "UChar", 1));
      net << attribute("mobilisation", "Scalar", "Cell",
                       x.side(ck + "mobilisation", sc, "Float", 8));
      net << attribute("fn_rel", "Scalar", "Cell", x.side(ck + "fn_rel", sc, "Float", 8));
      net << attribute("normal", "Vector", "Cell", x.side(ck + "normal", sc + " 3", "Float", 8));
      net << attribute("point", "Vector", "Cell", x.side(ck + "point", sc + " 3", "Float", 8));
    }
    net << attribute("tilt_angle", "Scalar", "Grid", literal(rf.tilt_deg[k], "Float", 8));
    net << "  </Grid>\n";
  }
  net << "  </Grid>\n";
}

// Stage 4: gravity as an arrow above the pile and the walls, after the network.
void write_gravity_and_walls(std::ostream& net, const Refs& x, const RunFrames& rf, double w,
                             double top) {
  const std::size_t F = rf.tilt_deg.size();
  // Gravity, drawn as an arrow above the pile: the run turns gravity in the box's frame,
  // g = g (sin theta, -cos theta), so this is what shows the tilt as time runs.
  const double L = 0.2 * w;
  net << "  <Grid Name=\"gravity\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < F; ++k) {
    const double th = rf.tilt_deg[k] * M_PI / 180.0;
    const Vec2 g{std::sin(th), -std::cos(th)};
    const Vec2 tail{0.5 * w - 0.5 * L * g.x(), top + 0.6 * L - 0.5 * L * g.y()};
    const Vec2 head = tail + L * g;
    auto barb = [&](double turn) {  // 25 degrees off the shaft, a quarter of its length
      const double a = std::atan2(-g.y(), -g.x()) + turn;
      return Vec2(head + 0.25 * L * Vec2(std::cos(a), std::sin(a)));
    };
    const Vec2 b1 = barb(25 * M_PI / 180), b2 = barb(-25 * M_PI / 180);
    net << "  <Grid Name=\"gravity_" << k << "\" GridType=\"Uniform\">\n   <Time Value=\""
        << x.time_of(k) << "\"/>\n"
        << "   <Topology TopologyType=\"Polyline\" NumberOfElements=\"3\" NodesPerElement=\"2\">"
           "<DataItem Dimensions=\"3 2\" NumberType=\"Int\" Format=\"XML\">0 1 1 2 1 "
           "3</DataItem></Topology>\n"
        << "   <Geometry GeometryType=\"XY\"><DataItem Dimensions=\"4 2\" NumberType=\"Float\" "
           "Precision=\"8\" Format=\"XML\">"
        << num(tail.x()) << " " << num(tail.y()) << " " << num(head.x()) << " " << num(head.y())
        << " " << num(b1.x()) << " " << num(b1.y()) << " " << num(b2.x()) << " " << num(b2.y())
        << "</DataItem></Geometry>\n";
    net << attribute("tilt_angle", "Scalar", "Grid", literal(rf.tilt_deg[k], "Float", 8));
    net << "  </Grid>\n";
  }
  net << "  </Grid>\n";

  // The walls: left wall down, the floor, right wall up (the box frame; gravity turns).
  net << "  <Grid Name=\"walls\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < F; ++k)
    net << "  <Grid Name=\"walls_" << k << "\" GridType=\"Uniform\">\n   <Time Value=\""
        << x.time_of(k) << "\"/>\n"
        << "   <Topology TopologyType=\"Polyline\" NumberOfElements=\"1\" NodesPerElement=\"4\">"
           "<DataItem Dimensions=\"1 4\" NumberType=\"Int\" Format=\"XML\">0 1 2 "
           "3</DataItem></Topology>\n"
        << "   <Geometry GeometryType=\"XY\"><DataItem Dimensions=\"4 2\" NumberType=\"Float\" "
           "Precision=\"8\" Format=\"XML\">0 "
        << num(top) << " 0 0 " << num(w) << " 0 " << num(w) << " " << num(top)
        << "</DataItem></Geometry>\n  </Grid>\n";
  net << "  </Grid>\n </Domain>\n</Xdmf>\n";
}

}  // namespace

Summary write_run(std::ostream& xml, std::ostream& network_xml, const h5::File& sidecar,
                  const RunReader& run, const std::string& data_ref, const std::string& sidecar_ref,
                  const Derived& derived) {
  const std::string& file = run.name();
  const h5::File& data = run.file();
  const std::size_t F = run.frame_count(), N = run.grain_count();
  if (F == 0) throw Error(file, "/particles/grains/position", "no frame to show");
  const RunHeader& h = run.header();
  const std::string cg = "/contacts";
  // The run's rows of each frame, and its tilt in degrees as the file holds it.
  RunFrames rf;
  rf.offsets = h5::read<std::int64_t>(data, cg + "/offset", {F});
  rf.tilt_deg = h5::read<double>(data, cg + "/tilt_angle", {F});
  rf.steps = h5::read<std::int64_t>(data, cg + "/step", {F});

  Summary sum{h.kind, F, N, 0, 0, 0};
  sum.diameter = derived.diameter;
  sum.width = h.box.width;
  sum.tilt_last_deg = rf.tilt_deg[F - 1];
  write_sidecar(sidecar, run, data_ref, derived, rf, sum);
  const Refs x{run, data_ref, sidecar_ref};
  write_grains_xml(xml, x, rf, N, sum.contacts);
  write_network_xml(network_xml, x, rf, N);
  write_gravity_and_walls(network_xml, x, rf, h.box.width, sum.top);
  return sum;
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
                           const std::string& xdmf_path, const std::string& network_name,
                           const std::string& network_path) {
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
    o << "network_xdmf = os.path.join(here, " << py(network_name) << ")\n"
      << "if not os.path.exists(network_xdmf):\n    network_xdmf = " << py(network_path) << "\n"
      << "overlay = XDMFReader(registrationName=" << py(network_name)
      << ", FileNames=[network_xdmf])\n"
      << "overlay.UpdatePipelineInformation()\n";
    const double nu_high = s.nu_max > 0 ? s.nu_max : 1.0;
    const double fn_high = s.fn_rel_high > 0 ? s.fn_rel_high : 1.0;
    o << "# the grains: disks of their own radius (Point Gaussian scaled by the radius array),\n"
      << "# coloured by nu on the range of the run's values (0 to the largest over the frames)\n"
      << "grains = reader  # the file holds the grains alone\n"
      << "disks = Show(grains, view)\n"
      << "disks.SetRepresentationType(\"Point Gaussian\")\n"
      << "disks.ShaderPreset = \"Plain circle\"\n"
      << "disks.ScaleByArray = 1\n"
      << "disks.SetScaleArray = [\"POINTS\", \"radius\"]\n"
      << "disks.UseScaleFunction = 0\n"
      << "disks.GaussianRadius = 1.0\n"
      << "ColorBy(disks, (\"POINTS\", \"nu\"))\n"
      << "lut = GetColorTransferFunction(\"nu\")\n"
      << "# pale grey-blue (not white: the background) to a mid blue, light enough for the\n"
      << "# network drawn over the disks\n"
      << "lut.RGBPoints = [0.0, 0.84, 0.87, 0.92, " << num(nu_high) << ", 0.35, 0.55, 0.85]\n"
      << "lut.AutomaticRescaleRangeMode = \"Never\"\n"
      << "lut.NanColor = [0.93, 0.82, 0.6]  # sand: no contact within reach, apart from nu = 0\n"
      << "disks.SetScalarBarVisibility(view, True)\n"
      << "nu_bar = GetScalarBar(lut, view)\n"
      << "nu_bar.Title = \"nu (grains)\"\n"
      << "nu_bar.ComponentTitle = \"\"\n"
      << "nu_bar.TitleColor = nu_bar.LabelColor = [0.0, 0.0, 0.0]\n"
      << "nu_bar.RangeLabelFormat = \"%-#6.3g\"\n"
      << "# the walls\n"
      << "walls = ExtractBlock(registrationName=\"walls\", Input=overlay, "
         "Selectors=[\"/Root/walls\"])\n"
      << "box = Show(walls, view)\n"
      << "box.ColorArrayName = [\"POINTS\", \"\"]\n"
      << "box.AmbientColor = box.DiffuseColor = [0.3, 0.3, 0.3]\n"
      << "box.LineWidth = 2.0\n"
      << "# the force network: a segment between the centres of each pair in contact, grey to\n"
      << "# black with f_n / <f_n> (the frame's mean), drawn in front of the disks\n"
      << "contacts = ExtractBlock(registrationName=\"contacts\", Input=overlay, "
         "Selectors=[\"/Root/contacts\"])\n"
      << "network = Transform(registrationName=\"network\", Input=contacts)\n"
      << "network.Transform = \"Transform\"\n"
      << "network.Transform.Translate = [0.0, 0.0, " << num(s.diameter) << "]\n"
      << "chains = Show(network, view)\n"
      << "chains.SetRepresentationType(\"Surface\")\n"
      << "chains.LineWidth = 2.0\n"
      << "ColorBy(chains, (\"CELLS\", \"fn_rel\"))\n"
      << "fn_lut = GetColorTransferFunction(\"fn_rel\")\n"
      << "fn_lut.RGBPoints = [0.0, 0.6, 0.6, 0.6, " << num(fn_high) << ", 0.0, 0.0, 0.0]\n"
      << "fn_lut.AutomaticRescaleRangeMode = \"Never\"\n"
      << "chains.SetScalarBarVisibility(view, True)\n"
      << "fn_bar = GetScalarBar(fn_lut, view)\n"
      << "fn_bar.Title = \"f_n / <f_n>\"\n"
      << "fn_bar.ComponentTitle = \"\"\n"
      << "fn_bar.TitleColor = fn_bar.LabelColor = [0.0, 0.0, 0.0]\n"
      << "fn_bar.RangeLabelFormat = \"%-#6.3g\"\n"
      << "fn_bar.WindowLocation = \"Upper Right Corner\"\n"
      << "# the critical contacts (|f_t| >= (1 - eps) mu f_n), red, in front of the network\n"
      << "critical = Threshold(registrationName=\"critical\", Input=contacts, Scalars=[\"CELLS\", "
         "\"critical\"], LowerThreshold=0.5, UpperThreshold=1.5)\n"
      << "critical_front = Transform(registrationName=\"critical_front\", Input=critical)\n"
      << "critical_front.Transform = \"Transform\"\n"
      << "critical_front.Transform.Translate = [0.0, 0.0, " << num(2 * s.diameter) << "]\n"
      << "red = Show(critical_front, view)\n"
      << "red.SetRepresentationType(\"Surface\")\n"
      << "red.ColorArrayName = [\"POINTS\", \"\"]\n"
      << "red.AmbientColor = red.DiffuseColor = [0.9, 0.0, 0.0]\n"
      << "red.LineWidth = 3.0\n"
      << "# gravity, an arrow above the pile: it turns as the run tilts (the box's frame)\n"
      << "gravity = ExtractBlock(registrationName=\"gravity\", Input=overlay, "
         "Selectors=[\"/Root/gravity\"])\n"
      << "arrow = Show(gravity, view)\n"
      << "arrow.ColorArrayName = [\"POINTS\", \"\"]\n"
      << "arrow.AmbientColor = arrow.DiffuseColor = [0.0, 0.5, 0.0]\n"
      << "arrow.LineWidth = 3.0\n"
      << "# the tilt angle of the frame shown, top left\n"
      << "tilt = PythonAnnotation(registrationName=\"tilt\", Input=grains)\n"
      << "tilt.ArrayAssociation = \"Field Data\"\n"
      << "tilt.Expression = \"'tilt %.2f deg' % tilt_angle[0]\"\n"
      << "label = Show(tilt, view)\n"
      << "label.WindowLocation = \"Upper Left Corner\"\n"
      << "label.FontSize = 14\n"
      << "label.Color = [0.0, 0.0, 0.0]\n"
      << "view.Background = [1.0, 1.0, 1.0]\n"
      << "view.UseColorPaletteForBackground = 0\n"
      << "scene = GetAnimationScene()\n"
      << "scene.UpdateAnimationUsingDataTimeSteps()\n";
  }
  o << "SetActiveSource(reader)\n"
    << "ResetCamera(view)\n"
    << "Render(view)\n";
  return o.str();
}

}  // namespace cdpile::io::xdmf
