#!/usr/bin/python3
"""Checks an HDF5 file against the required items of H5MD 1.1 and of its units module
(https://nongnu.org/h5md/h5md.html, modules/units), independently of cdpile's code:

  check_h5md.py FILE...     prints one line per file, exit 1 at the first violation

Checked: /h5md version Integer[2] = [1, y]; author/name, creator/name and creator/version
fixed-length scalar strings (author/email too if present); every module under
/h5md/modules has version Integer[2]; the units module has a scalar string `system`;
every /particles group has a box with dimension (scalar Integer) and boundary (fixed-length
strings [D], each 'periodic' or 'none'), edges [D] or [D][D] when present (required with a
periodic boundary); every time-dependent element in /particles and /observables has an
Integer step [variable] strictly increasing, a time of the same length (increasing) if
present, and a value whose first dimension is the number of steps; in a particle group,
the particle index is the next dimension and equal across elements; position and velocity
end in D; every `unit` attribute of an element's value, time or time-independent dataset
is a scalar variable-length ASCII string in the units module's notation (an optional
leading number, then unit symbols with an optional SI prefix and signed power, each
symbol once) using its symbols, and the units module is declared when units are used.
"""
import re
import sys

import h5py
import numpy as np

SYMBOLS = {"m", "Ang", "L", "s", "Hz", "kg", "g", "u", "N", "dyn", "Pa", "bar", "atm", "poise",
           "J", "cal", "erg", "eV", "W", "K", "mol", "A", "C", "V", "cd", "rad", "degree",
           "pi", "kB", "Nav", "c", "e"}
PREFIXES = ["da", "E", "P", "T", "G", "M", "k", "h", "d", "c", "m", "u", "n", "p", "f", "a"]


class Violation(Exception):
    pass


def need(cond, where, what):
    if not cond:
        raise Violation(f"{where}: {what}")


def string_attr(obj, name, where, fixed=None, shape=()):
    need(name in obj.attrs, where, f"missing attribute '{name}'")
    aid = obj.attrs.get_id(name)
    t = aid.get_type()
    need(isinstance(t, h5py.h5t.TypeStringID), where, f"'{name}' is not a string")
    if fixed is not None:
        need(t.is_variable_str() != fixed, where,
             f"'{name}' must be a {'fixed' if fixed else 'variable'}-length string")
    need(aid.shape == shape, where, f"'{name}' has shape {aid.shape}, expected {shape}")
    v = obj.attrs[name]
    if isinstance(v, np.ndarray):
        return [x.decode() if isinstance(x, bytes) else str(x) for x in v.ravel()]
    return v.decode() if isinstance(v, bytes) else str(v)


def int_attr(obj, name, where, shape):
    need(name in obj.attrs, where, f"missing attribute '{name}'")
    v = np.asarray(obj.attrs[name])
    need(np.issubdtype(v.dtype, np.integer), where, f"'{name}' is not an Integer")
    need(v.shape == shape, where, f"'{name}' has shape {v.shape}, expected {shape}")
    return v


def unit_ok(text):
    """The units module's notation, with its SI symbols and prefixes."""
    factors = text.split(" ")
    need(all(factors), "unit", f"'{text}': empty factor")
    seen = set()
    for k, f in enumerate(factors):
        if re.fullmatch(r"[0-9]+(\.[0-9]*)?([+-][0-9]+)?", f):
            need(k == 0, "unit", f"'{text}': a number may only be the first factor")
            continue
        m = re.fullmatch(r"([A-Za-z]+)([+-]?[1-9][0-9]*)?", f)
        need(m is not None, "unit", f"'{text}': '{f}' is not a unit factor")
        sym = m.group(1)
        ok = sym in SYMBOLS or any(sym.startswith(p) and sym[len(p):] in SYMBOLS for p in PREFIXES)
        need(ok, "unit", f"'{text}': '{sym}' is not a symbol of the units module")
        need(sym not in seen, "unit", f"'{text}': '{sym}' appears twice")
        seen.add(sym)


def check_unit(ds, where, units):
    if "unit" not in ds.attrs:
        return 0
    need(units, where, "a unit attribute, but /h5md/modules/units is not declared")
    aid = ds.attrs.get_id("unit")
    t = aid.get_type()
    need(isinstance(t, h5py.h5t.TypeStringID) and t.is_variable_str(), where,
         "unit must be a variable-length string")
    need(t.get_cset() == h5py.h5t.CSET_ASCII, where, "unit must use the ASCII character set")
    need(aid.shape == (), where, "unit must be scalar")
    v = ds.attrs["unit"]
    try:
        unit_ok(v.decode() if isinstance(v, bytes) else str(v))
    except Violation as e:
        raise Violation(f"{where}: {str(e).removeprefix('unit: ')}")
    return 1


def check_element(obj, where, units, particles=None):
    """A time-dependent group or a time-independent dataset; returns (units, particles)."""
    n_units = 0
    if isinstance(obj, h5py.Dataset):
        n_units += check_unit(obj, where, units)
        if particles is not None and obj.ndim >= 1:
            particles.add(obj.shape[0])
        return n_units
    need("value" in obj and "step" in obj, where, "an element group needs 'step' and 'value'")
    step = obj["step"]
    need(np.issubdtype(step.dtype, np.integer), where + "/step", "not Integer")
    if step.ndim == 0:  # fixed step storage
        rows = obj["value"].shape[0]
    else:
        need(step.ndim == 1, where + "/step", "not rank 1")
        s = step[:]
        need(np.all(np.diff(s) > 0), where + "/step", "not strictly increasing")
        rows = s.size
        if "time" in obj:
            t = obj["time"]
            need(t.shape == (rows,), where + "/time", f"shape {t.shape}, expected ({rows},)")
            need(np.all(np.diff(t[:]) >= 0), where + "/time", "decreasing")
    value = obj["value"]
    need(value.shape[0] == rows, where + "/value", f"{value.shape[0]} rows for {rows} steps")
    if particles is not None:
        need(value.ndim >= 2, where + "/value", "no particle dimension")
        particles.add(value.shape[1])
    n_units += check_unit(value, where + "/value", units)
    if "time" in obj:
        n_units += check_unit(obj["time"], where + "/time", units)
    return n_units


def check(path):
    with h5py.File(path, "r") as f:
        need("h5md" in f, path, "missing group /h5md")
        h = f["h5md"]
        v = int_attr(h, "version", "/h5md", (2,))
        need(v[0] == 1, "/h5md", f"version {list(v)}, expected 1.x")
        need("author" in h and "creator" in h, "/h5md", "missing author or creator group")
        string_attr(h["author"], "name", "/h5md/author", fixed=True)
        if "email" in h["author"].attrs:
            string_attr(h["author"], "email", "/h5md/author", fixed=True)
        string_attr(h["creator"], "name", "/h5md/creator", fixed=True)
        string_attr(h["creator"], "version", "/h5md/creator", fixed=True)
        units = False
        if "modules" in h:
            for name, m in h["modules"].items():
                int_attr(m, "version", f"/h5md/modules/{name}", (2,))
                if name == "units":
                    string_attr(m, "system", "/h5md/modules/units")
                    units = True
        n_elements = n_units = 0
        for gname, g in f.get("particles", {}).items():
            where = f"/particles/{gname}"
            need("box" in g, where, "missing box")
            box = g["box"]
            d = int(int_attr(box, "dimension", where + "/box", ()))
            bounds = string_attr(box, "boundary", where + "/box", fixed=True, shape=(d,))
            need(all(b in ("periodic", "none") for b in bounds), where + "/box",
                 f"boundary {bounds}: each 'periodic' or 'none'")
            if "edges" in box:
                e = box["edges"]
                shape = e["value"].shape[1:] if isinstance(e, h5py.Group) else e.shape
                need(shape in ((d,), (d, d)), where + "/box/edges", f"shape {shape} for D = {d}")
            else:
                need("periodic" not in bounds, where + "/box", "a periodic box needs edges")
            particles = set()
            for ename, e in g.items():
                if ename == "box":
                    continue
                n_units += check_element(e, f"{where}/{ename}", units, particles)
                n_elements += 1
                if ename in ("position", "velocity", "force", "image"):
                    val = e["value"] if isinstance(e, h5py.Group) else e
                    need(val.shape[-1] == d, f"{where}/{ename}", f"last dimension {val.shape[-1]}, D = {d}")
            need(len(particles) <= 1, where, f"elements disagree on the number of particles: {sorted(particles)}")

        def observables(g, where):
            nonlocal n_elements, n_units
            for name, e in g.items():
                w = f"{where}/{name}"
                if isinstance(e, h5py.Group) and "value" not in e:
                    observables(e, w)
                    continue
                n_units += check_element(e, w, units)
                n_elements += 1
        if "observables" in f:
            observables(f["observables"], "/observables")
        return n_elements, n_units


def main():
    for path in sys.argv[1:]:
        try:
            n, u = check(path)
        except Violation as e:
            print(f"{path}: not H5MD 1.1: {e}", file=sys.stderr)
            sys.exit(1)
        print(f"{path}: H5MD 1.1 ({n} elements, {u} units checked)")


if __name__ == "__main__":
    main()
