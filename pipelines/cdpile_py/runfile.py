"""The one reader of cdpile's HDF5 files in the pipelines (docs/schema.md): a run or pile
of tilt-cd or deposit (Run), and an analysis product of critical, localnu, correlate or
clusterfit (Product)."""
import os
import statistics
import sys

import h5py
import numpy as np


def text(s):
    """A string attribute or label as str (HDF5 fixed-length strings come as bytes)."""
    return s.decode() if isinstance(s, bytes) else str(s)


def scalar(v):
    """An attribute as a number or a string: one-element arrays unwrapped, bytes decoded."""
    if isinstance(v, np.ndarray) and v.size == 1:
        v = v.item()
    if isinstance(v, bytes):
        return v.decode()
    return v


def attributes(f, group):
    """The attributes of f[group] as a dict of scalars ({} when the file has no such group)."""
    return {k: scalar(v) for k, v in f[group].attrs.items()} if group in f else {}


def run_costs(path):
    """The CPU [s] each run of a file's history cost, from its /provenance (docs/schema.md,
    `cpu_s`): one dict per run ({"run", "deposit_s", "tilt_s"}, None where not recorded), in
    the order of the inputs; a product of several runs names each by its `via`."""
    runs = {}
    with h5py.File(path, "r") as f:
        if "provenance" not in f:
            return []
        for key in sorted(f["provenance"]):
            a = attributes(f, f"provenance/{key}")
            tool = a.get("tool")
            if tool not in ("deposit", "tilt-cd"):
                continue
            run = a.get("via", "") or os.path.basename(path)
            cost = runs.setdefault(run, {"run": run, "deposit_s": None, "tilt_s": None})
            cost["deposit_s" if tool == "deposit" else "tilt_s"] = a.get("cpu_s")
    return list(runs.values())


def cost_line(path):
    """One line saying what a study's runs cost, from a product of all its runs."""
    costs = run_costs(path)
    both = [c["deposit_s"] + c["tilt_s"] for c in costs
            if c["deposit_s"] is not None and c["tilt_s"] is not None]
    if not costs:
        return "Cost: no run in the product's history."
    if not both:
        return (f"Cost: not recorded by its {len(costs)} run(s) (files written before "
                "2026-12-02 do not record their CPU).")
    both.sort()
    n = len(both)
    med = statistics.median(both)
    total = sum(both)
    total_text = f"{total:.3g} s of CPU" if total < 3600 else f"{total / 3600:.3g} CPU-hours"
    return (f"Cost: {total_text} for the {n} of {len(costs)} runs that record it (deposit and "
            f"tilt; a run {med:.3g} s, median, {both[0]:.3g} to {both[-1]:.3g} s).")


def _dataset(name, doc=None):
    """A Run property: the dataset `name`, read whole when first asked for."""
    return property(lambda run: run._read(name), doc=doc)


class Run:
    """A run or pile file, open for reading: /parameters and /results as dicts, the per-step
    observables, the grains, and the frames' contacts read one frame at a time. Arrays are
    read when first asked for, so a script that needs the attributes alone reads nothing
    else (a partial run, RUN.h5.partial, reads the same way)."""

    def __init__(self, path):
        self.path = path
        self.f = h5py.File(path, "r")
        self.parameters = attributes(self.f, "parameters")
        self.results = attributes(self.f, "results")
        self._arrays = {}

    def close(self):
        self.f.close()

    def __enter__(self):
        return self

    def __exit__(self, *_):
        self.close()

    # --- the run's own record ---
    @property
    def gravity(self):
        return float(self.parameters["gravity_m_s2"])

    @property
    def avalanche_angle(self):
        """tilt-cd's avalanche angle [deg] (results/avalanche_angle_deg), or None without one."""
        if int(self.results.get("avalanche_detected", 0)):
            return float(self.results["avalanche_angle_deg"])
        return None

    def observable(self, name):
        """The per-step values of an observable, or None when the run has not recorded it."""
        obs = self.f["observables"]
        return obs[name + "/value"][:] if name in obs else None

    def has_observables(self, *names):
        return all(n in self.f["observables"] for n in names)

    def steps_recorded(self, name):
        """How many steps an observable holds (without reading it)."""
        return int(self.f["observables"][name + "/value"].shape[0])

    def _read(self, name):
        """A dataset read whole, once."""
        if name not in self._arrays:
            self._arrays[name] = self.f[name][:]
        return self._arrays[name]

    # --- the grains and the frames, read when first asked for ---
    radius = _dataset("particles/grains/radius")
    mass = _dataset("particles/grains/mass")
    species = _dataset("particles/grains/species")
    frame_tilt = _dataset("contacts/tilt_angle", "The tilt angle of every frame [deg].")
    frame_step = _dataset("contacts/step")
    offset = _dataset("contacts/offset")
    count = _dataset("contacts/count")

    @property
    def free(self):
        """The free grains (species 0; the others are glued to the floor)."""
        return self.species == 0

    def positions(self, k):
        """The grains' centres at frame k [m]."""
        return self.f["particles/grains/position/value"][k]

    @property
    def frames(self):
        return len(self.frame_tilt)

    def contacts(self, k, keys=("i", "j", "fn", "ft")):
        """The columns `keys` of frame k's contacts (k = -1: the last frame)."""
        o, n = int(self.offset[k]), int(self.count[k])
        c = self.f["contacts"]
        return {key: c[key][o:o + n] for key in keys}


# How critical's notes said, before 2026-11-29, that a reading of the envelope gives no nu_c:
# the reading's label, then one of these.
ENVELOPE_REASONS = ("envelope does not saturate", "envelope fit not done", "envelope fit did not converge",
                    "envelope fit failed", "no state in the loading phase")
READING_LABELS = {"nu_c": "", "nu_c_static": "static states: ", "nu_c_rest": "contacts at rest: "}


def envelope_note(notes, key):
    """Why critical's product gives no `key` (nu_c, nu_c_static or nu_c_rest), from its notes
    ("nu_c_static (static states) not determined: WHY", or the earlier "static states: WHY");
    None when no note says."""
    for n in notes:
        if n.startswith(key + " (") and " not determined: " in n:
            return n.split(" not determined: ", 1)[1]
    label = READING_LABELS[key]
    for n in notes:
        if any(n.startswith(label + w) for w in ENVELOPE_REASONS):
            return n[len(label):]
    return None


def note(notes, start):
    """The first note that starts with `start`, without it; else None."""
    for n in notes:
        if n.startswith(start):
            return n[len(start):]
    return None


class Product:
    """One analysis product: tables of columns (NaN where a value is missing), results,
    parameters and notes. With tables=False, the attributes alone are read."""

    def __init__(self, path, tables=True):
        self.path = path
        with h5py.File(path, "r") as f:
            self.results = attributes(f, "results")
            self.parameters = attributes(f, "parameters")
            notes = f["tables"].attrs.get("notes", []) if "tables" in f else []
            self.notes = [text(n) for n in np.atleast_1d(notes)]
            self.tables = {}
            if tables:
                for name, group in f["tables"].items():
                    self.tables[name] = _columns(group)

    def table(self, name):
        if name not in self.tables:
            raise SystemExit(f"figures.py: {self.path}: no table '{name}'")
        return self.tables[name]


def _columns(group):
    """A product table's columns: text columns (labels) as strings, numbers as floats with
    NaN where the column's _defined flag is 0."""
    cols = {}
    for col, ds in group.items():
        if col.endswith("_defined"):
            continue
        v = ds[()]
        if "labels" in ds.attrs:
            labels = [text(s) for s in ds.attrs["labels"]]
            v = np.array([labels[c] for c in v], dtype=object)
        else:
            v = v.astype(float)
            if col + "_defined" in group:
                v[group[col + "_defined"][()] == 0] = np.nan
        cols[col] = v
    return cols


def load(study, name):
    """The product `name` of a study's folder, or None (said on stderr) when it is missing."""
    path = os.path.join(study, name)
    if not os.path.exists(path):
        print(f"figures.py: {path}: missing, its figures are skipped", file=sys.stderr)
        return None
    return Product(path)
