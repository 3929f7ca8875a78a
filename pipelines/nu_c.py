#!/usr/bin/python3
"""Which nu_c a study's eq (5) and Fig 5 maps use (pipelines/Makefile):

    nu_c.py CRITICAL.h5
    nu_c.py --map CRITICAL.h5

prints the options that give it: the limit of the envelope over static states
(--nu-c NU_C_STATIC --nu-c-se SE) when critical found one, since a number of the pile comes
from states the pile can be in (docs/analysis.md, "Static and moving states"); else nothing,
and the tools take the critical product's nu_c (every state), if it has one. With --map,
the threshold of a map: --nu-c NU_C_STATIC, else --nu CRITICAL.h5 when the product has a
nu_c, else nothing.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdpile_py.runfile import Product  # noqa: E402

args = sys.argv[1:]
for_map = args[:1] == ["--map"]
path = args[-1]
r = Product(path, tables=False).results
if "nu_c_static" in r:
    se = "" if for_map else f" --nu-c-se {float(r.get('nu_c_static_se', 0.0)):.17g}"
    print(f"--nu-c {float(r['nu_c_static']):.17g}{se}")
elif for_map and "nu_c" in r:
    print(f"--nu {path}")
