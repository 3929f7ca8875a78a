"""Run by pvpython (ParaView 5.11) under a virtual X display, from tests/tools/to-xdmf/paraview.sh:

  pvpython check_paraview.py EXPECTED.json RUN.paraview.py IMAGE.png NU.xdmf NU.paraview.py

Loads the ParaView state that to-xdmf wrote for a run (as File > Load State does), checks
what ParaView's XDMF Reader read against the run file's numbers (EXPECTED.json, extracted by
paraview.sh with h5py), renders one image and checks its pixels: disks drawn at the grain
centres, covering the area their radii say. Then opens a localnu product's XDMF (NU.xdmf)
and checks its grid and nu field against the product's map, and loads that product's state
(NU.paraview.py, docs/analysis.md's recipe) and renders it.
"""
import json
import math
import os
import sys

from paraview import servermanager
from paraview.simple import *  # noqa: F401,F403
import vtk
from vtk.numpy_interface import dataset_adapter as dsa
import numpy as np

expected = json.load(open(sys.argv[1]))
state, image = sys.argv[2], sys.argv[3]


def fail(what):
    print("check_paraview: " + what, file=sys.stderr)
    sys.exit(1)


with open(state) as f:
    code = compile(f.read(), state, "exec")
scope = {"__file__": state, "__name__": "__main__"}
exec(code, scope)
reader, view = scope["reader"], scope["view"]
grains, contacts = scope["grains"], scope["contacts"]

times = list(reader.TimestepValues)
if len(times) != expected["frames"]:
    fail(f"{len(times)} time steps, expected {expected['frames']}")
if max(abs(a - b) for a, b in zip(times, expected["times"])) > 1e-12:
    fail(f"times {times}, expected {expected['times']}")


def fetch(source, t):
    source.UpdatePipeline(t)
    d = servermanager.Fetch(source)
    if not d.IsA("vtkCompositeDataSet"):
        return dsa.WrapDataObject(d)
    it = d.NewIterator()
    it.InitTraversal()
    blocks = []
    while not it.IsDoneWithTraversal():
        blocks.append(it.GetCurrentDataObject())
        it.GoToNextItem()
    if len(blocks) != 1:
        fail(f"{len(blocks)} blocks")
    return dsa.WrapDataObject(blocks[0])


for k, t in enumerate(times):
    g = fetch(grains, t)
    if g.GetNumberOfPoints() != expected["grains"]:
        fail(f"frame {k}: {g.GetNumberOfPoints()} grains, expected {expected['grains']}")
    for name, comps in (("radius", 1), ("species", 1), ("mass", 1), ("velocity", 3), ("angular_velocity", 1),
                        ("orientation", 1), ("nu", 1)):
        a = g.PointData[name]
        if a is None or (a.shape[1] if a.ndim == 2 else 1) != comps:
            fail(f"frame {k}: grain array {name} missing or not {comps} components")
    pts = np.asarray(g.Points)
    want = np.asarray(expected["positions"][k])
    if np.abs(pts[:, :2] - want).max() > 0 or np.abs(pts[:, 2]).max() > 0:
        fail(f"frame {k}: grain positions differ from the run's")
    if np.abs(np.asarray(g.PointData["velocity"])[:, :2] - np.asarray(expected["velocities"][k])).max() > 0 or \
            np.abs(np.asarray(g.PointData["velocity"])[:, 2]).max() > 0:
        fail(f"frame {k}: velocities differ from the run's (or z != 0)")
    if abs(float(g.FieldData["tilt_angle"][0]) - expected["tilt"][k]) > 1e-12:
        fail(f"frame {k}: tilt_angle {g.FieldData['tilt_angle'][0]}, expected {expected['tilt'][k]}")
    c = fetch(contacts, t)
    if c.GetNumberOfCells() != expected["contacts"][k]:
        fail(f"frame {k}: {c.GetNumberOfCells()} contact segments, expected {expected['contacts'][k]}")
    for name in ("fn", "ft", "status", "critical", "i", "j", "gap", "mobilisation", "normal", "fn_rel", "point"):
        if c.CellData[name] is None:
            fail(f"frame {k}: contact array {name} missing")
    if int(np.asarray(c.CellData["critical"]).sum()) != expected["critical"][k]:
        fail(f"frame {k}: {int(np.asarray(c.CellData['critical']).sum())} critical contacts, the run's "
             f"observable 'critical' says {expected['critical'][k]}")
    if np.abs(np.asarray(c.CellData["fn"]) - np.asarray(expected["fn"][k])).max() > 0:
        fail(f"frame {k}: fn differs from the run's")
    # each segment joins the centres of the pair (a wall contact: the centre and the contact point)
    ends = np.asarray(c.Points)[:, :2]
    cells = c.VTKObject.GetCells()
    ci, cj = np.asarray(c.CellData["i"]), np.asarray(c.CellData["j"])
    conn = np.asarray(dsa.vtkDataArrayToVTKArray(cells.GetConnectivityArray())).reshape(-1, 2)
    centres = np.asarray(expected["positions"][k])
    if np.abs(ends[conn[:, 0]] - centres[ci]).max() > 0:
        fail(f"frame {k}: a segment does not start at its grain i")
    gg = cj >= 0
    if np.abs(ends[conn[gg, 1]] - centres[cj[gg]]).max() > 0:
        fail(f"frame {k}: a segment does not end at its grain j")
    mean = np.asarray(expected["fn"][k])[np.asarray(expected["fn"][k]) > 0].mean()
    if np.abs(np.asarray(c.CellData["fn_rel"]) * mean - np.asarray(expected["fn"][k])).max() > 1e-12 * mean:
        fail(f"frame {k}: fn_rel is not fn / <fn>")

# One image, at the last frame, as the state shows it.
view.ViewSize = [400, 300]
view.ViewTime = times[-1]
GetAnimationScene().AnimationTime = times[-1]
Render(view)
SaveScreenshot(image, view, ImageResolution=[400, 300])
png = vtk.vtkPNGReader()
png.SetFileName(image)
png.Update()
dims = png.GetOutput().GetDimensions()
pix = np.asarray(dsa.WrapDataObject(png.GetOutput()).PointData[0])[:, :3].reshape(dims[1], dims[0], 3)[::-1]
bg = pix[0, 0].astype(int)
drawn = np.abs(pix.astype(int) - bg).sum(axis=2) > 30
# The parallel camera: height 2 x parallel scale; world (x, y) to pixel (column, row).
cam = view.GetActiveCamera()
height = 2 * cam.GetParallelScale()
width = height * dims[0] / dims[1]
fx, fy, _ = cam.GetFocalPoint()


def to_pixel(x, y):
    return ((np.asarray(x) - fx) / width + 0.5) * dims[0], (0.5 - (np.asarray(y) - fy) / height) * dims[1]


# The disks' area against the pixels drawn between the walls, up to the top grain (the
# colour bars, the arrow and the text lie outside)
centres = np.asarray(expected["positions"][-1])
radii = np.asarray(expected["radius"])
c0, r1 = to_pixel(0.0, 0.0)
c1, r0 = to_pixel(scope_width := float(max(centres[:, 0] + radii)), float(max(centres[:, 1] + radii)))
region = drawn[int(r0) + 1:int(r1) - 1, int(c0) + 2:int(c1) - 1]
fraction = region.mean()
want = float(np.sum(math.pi * radii ** 2)) / (scope_width * float(max(centres[:, 1] + radii)))
print(f"image {dims[0]} x {dims[1]}: {100 * fraction:.1f} % of pixels drawn inside the pile's bounds, the disks' "
      f"area is {100 * want:.1f} %")
if not (0.75 * want < fraction < 1.35 * want + 0.02):
    fail(f"{100 * fraction:.1f} % of the pixels drawn, the disks cover {100 * want:.1f} % of the pile's bounds")
# every grain's centre is drawn
px, py = to_pixel(centres[:, 0], centres[:, 1])
inside = (px >= 0) & (px < dims[0]) & (py >= 0) & (py < dims[1])
hit = drawn[py[inside].astype(int), px[inside].astype(int)]
if inside.sum() < len(centres) or not hit.all():
    fail(f"{int(hit.sum())} of {len(centres)} grain centres drawn")
colours = {tuple(p) for p in pix[drawn]}
print(f"{len(centres)} grain centres drawn; {len(colours)} colours")


def near(col, row, test):
    """Whether a pixel within 2 of (col, row) passes test (the lines' anti-aliasing)."""
    c, r = int(round(float(col))), int(round(float(row)))
    block = pix[max(r - 2, 0):r + 3, max(c - 2, 0):c + 3].astype(int)
    return bool(test(block).any())


red = lambda b: (b[..., 0] > 150) & (b[..., 1] < 90) & (b[..., 2] < 90)
grey = lambda b: (np.abs(b[..., 0] - b[..., 1]) < 20) & (np.abs(b[..., 1] - b[..., 2]) < 20) & (b[..., 0] < 170)
li, lj, lc = (np.asarray(expected[k]) for k in ("last_i", "last_j", "last_critical"))
mid_x = (centres[li, 0] + np.where(lj >= 0, centres[np.maximum(lj, 0), 0], centres[li, 0])) / 2
mid_y = (centres[li, 1] + np.where(lj >= 0, centres[np.maximum(lj, 0), 1], centres[li, 1])) / 2
mcol, mrow = to_pixel(mid_x, mid_y)
pairs = lj >= 0
crit = pairs & (lc == 1)
if crit.sum() == 0:
    fail("the last frame has no critical contact between grains to look for")
red_found = [near(mcol[q], mrow[q], red) for q in np.flatnonzero(crit)]
if not all(red_found):
    fail(f"{sum(red_found)} of {int(crit.sum())} critical segments red at their midpoints")
strong = np.flatnonzero(pairs & (lc == 0) & (np.asarray(expected["last_fn"]) > 0))
grey_found = [near(mcol[q], mrow[q], grey) for q in strong]
if sum(grey_found) < 0.9 * len(strong):
    fail(f"{sum(grey_found)} of {len(strong)} loaded segments drawn grey to black at their midpoints")
print(f"{int(crit.sum())} critical segments red at their midpoints; {sum(grey_found)} of {len(strong)} other "
      f"loaded segments grey to black; {int(red(pix).sum())} red pixels")
# The tilt angle of the frame shown, as the annotation computes it and as drawn (top left)
tilt = scope["tilt"]
tilt.UpdatePipeline(times[-1])
text = servermanager.Fetch(tilt).GetColumn(0).GetValue(0)
if text != "tilt %.2f deg" % expected["tilt"][-1]:
    fail(f"tilt text {text!r}, expected 'tilt {expected['tilt'][-1]:.2f} deg'")
corner = drawn[:dims[1] // 8, :dims[0] // 4]
if corner.sum() < 20:
    fail("no text drawn in the top left corner")
print(f"tilt text: {text!r}, {int(corner.sum())} pixels in the top left corner")

# File > Open: ParaView picks its reader for run.xdmf (no reader named): one point per grain.
# The name with its folder, as the GUI gives it: ParaView 5.11's Xdmf3 reader joins a bare
# name's HDF5 references to the name itself ("run.xdmfrun.xdmf.hdf5") and aborts.
opened = OpenDataFile(os.path.join(".", expected["xdmf"]))
print(f"File > Open: {opened.GetXMLName()}")
opened.UpdatePipelineInformation()
if len(opened.TimestepValues) != expected["frames"]:
    fail(f"File > Open: {len(opened.TimestepValues)} time steps, expected {expected['frames']}")
for k, t in enumerate(opened.TimestepValues):
    g = fetch(opened, t)
    if g.GetNumberOfPoints() != expected["grains"] or g.GetNumberOfCells() != expected["grains"]:
        fail(f"File > Open, frame {k}: {g.GetNumberOfPoints()} points, {g.GetNumberOfCells()} cells, "
             f"expected one per grain ({expected['grains']})")
    if np.abs(np.asarray(g.Points)[:, :2] - np.asarray(expected["positions"][k])).max() > 0:
        fail(f"File > Open, frame {k}: grain positions differ from the run's")
    if abs(float(g.FieldData["tilt_angle"][0]) - expected["tilt"][k]) > 1e-12:
        fail(f"File > Open, frame {k}: tilt_angle differs from the run's")
net = OpenDataFile(os.path.join(".", expected["network"]))
net.UpdatePipelineInformation()
for k, t in enumerate(net.TimestepValues):
    net.UpdatePipeline(t)
    d = servermanager.Fetch(net)
    it = d.NewIterator()
    it.InitTraversal()
    cells = []
    while not it.IsDoneWithTraversal():
        cells.append(it.GetCurrentDataObject().GetNumberOfCells())
        it.GoToNextItem()
    if cells[0] != expected["contacts"][k]:
        fail(f"File > Open of the network, frame {k}: {cells[0]} segments, expected {expected['contacts'][k]}")
print(f"File > Open: {expected['grains']} points a frame, {expected['frames']} frames; network "
      f"{expected['contacts']} segments")

# The nu field of a localnu product.
nu_reader = XDMFReader(FileNames=[sys.argv[4]])
nu_reader.UpdatePipeline()
field = dsa.WrapDataObject(servermanager.Fetch(nu_reader))
m = expected["map"]
it = field.VTKObject.NewIterator() if hasattr(field.VTKObject, "NewIterator") else None
grid = field
if it is not None:
    it.InitTraversal()
    grid = dsa.WrapDataObject(it.GetCurrentDataObject())
if grid.GetNumberOfPoints() != m["nx"] * m["ny"]:
    fail(f"nu field: {grid.GetNumberOfPoints()} nodes, expected {m['nx']} x {m['ny']}")
b = grid.GetBounds()
want_b = (m["x0"], m["x0"] + (m["nx"] - 1) * m["dx"], m["y0"], m["y0"] + (m["ny"] - 1) * m["dx"])
if max(abs(a - w) for a, w in zip(b[:4], want_b)) > 1e-12:
    fail(f"nu field bounds {b[:4]}, expected {want_b}")
got = np.asarray(grid.PointData["nu"])
want_nu = np.asarray([np.nan if v is None else v for v in m["nu"]])
if not np.array_equal(np.isnan(got), np.isnan(want_nu)) or np.nanmax(np.abs(got - want_nu)) > 0:
    fail("nu field values differ from the product's map")
print(f"nu field: {m['nx']} x {m['ny']} nodes, {int(np.isnan(got).sum())} without a value")

# The map's state, as `paraview --state=map.paraview.py` loads it: the same grid, drawn.
with open(sys.argv[5]) as f:
    code = compile(f.read(), sys.argv[5], "exec")
map_scope = {"__file__": sys.argv[5], "__name__": "__main__"}
exec(code, map_scope)
map_scope["reader"].UpdatePipeline()
map_grid = servermanager.Fetch(map_scope["reader"])
if map_grid.GetNumberOfPoints() != m["nx"] * m["ny"]:
    fail(f"map state: {map_grid.GetNumberOfPoints()} nodes, expected {m['nx']} x {m['ny']}")
Render(map_scope["view"])
print(f"map state: {m['nx']} x {m['ny']} nodes drawn")
