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
    if c.GetNumberOfPoints() != expected["contacts"][k]:
        fail(f"frame {k}: {c.GetNumberOfPoints()} contacts, expected {expected['contacts'][k]}")
    for name in ("fn", "ft", "status", "critical", "i", "j", "gap", "mobilisation", "normal"):
        if c.PointData[name] is None:
            fail(f"frame {k}: contact array {name} missing")
    if int(np.asarray(c.PointData["critical"]).sum()) != expected["critical"][k]:
        fail(f"frame {k}: {int(np.asarray(c.PointData['critical']).sum())} critical contacts, the run's "
             f"observable 'critical' says {expected['critical'][k]}")
    if np.abs(np.asarray(c.PointData["fn"]) - np.asarray(expected["fn"][k])).max() > 0:
        fail(f"frame {k}: fn differs from the run's")

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
fraction = drawn.mean()
# The disks' area as the parallel camera shows it: height 2 x parallel scale.
cam = view.GetActiveCamera()
height = 2 * cam.GetParallelScale()
width = height * dims[0] / dims[1]
radii = np.asarray(expected["radius"])
want = float(np.sum(math.pi * radii ** 2)) / (width * height)
print(f"image {dims[0]} x {dims[1]}: {100 * fraction:.1f} % of pixels drawn, the disks' area is "
      f"{100 * want:.1f} % of the view")
if not (0.75 * want < fraction < 1.35 * want + 0.02):
    fail(f"{100 * fraction:.1f} % of the pixels drawn, the disks cover {100 * want:.1f} % of the view")
# every grain's centre is drawn
fx, fy, _ = cam.GetFocalPoint()
centres = np.asarray(expected["positions"][-1])
px = ((centres[:, 0] - fx) / width + 0.5) * dims[0]
py = (0.5 - (centres[:, 1] - fy) / height) * dims[1]
inside = (px >= 0) & (px < dims[0]) & (py >= 0) & (py < dims[1])
hit = drawn[py[inside].astype(int), px[inside].astype(int)]
if inside.sum() < len(centres) or not hit.all():
    fail(f"{int(hit.sum())} of {len(centres)} grain centres drawn")
colours = {tuple(p) for p in pix[drawn]}
print(f"{len(centres)} grain centres drawn; {len(colours)} colours")

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
