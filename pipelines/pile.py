#!/usr/bin/python3
"""Pictures of the pile itself from a run file (HDF5, docs/schema.md): the grains, the force
network (a segment between the centres of each pair in contact, its width proportional to
f_n / <f_n>, the frame's mean over its active contacts) and the critical contacts in red,
in the laboratory frame (gravity down, the box turned by the tilt angle).

    pipelines/pile.py figure RUN [-o FILE.png] [--theta-c DEG]
    pipelines/pile.py movie RUN [-o FILE.mp4] [--fps 8]

figure: three panels, the first frame, the frame half way to theta_c and the last frame
before theta_c (theta_c: --theta-c, else the run's recorded avalanche angle, else its last
frame). movie: every frame, with ffmpeg (Debian package ffmpeg), H.264 at a few hundred kB
for a 500-grain run. A contact is critical when f_n > 0 and |f_t| >= (1 - eps) mu f_n with
the run's critical_eps, mu_grain and mu_wall (docs/analysis.md, "Definitions").
Needs python3-matplotlib, python3-h5py and python3-numpy (Debian).
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdpile_py import pictures  # noqa: E402
from cdpile_py.runfile import Run  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("what", choices=["figure", "movie"])
    ap.add_argument("run", help="run file (HDF5)")
    ap.add_argument("-o", dest="out", help="output (default: RUN with -pile.png or .mp4)")
    ap.add_argument("--theta-c", type=float, help="avalanche angle [deg] (default: the run's)")
    ap.add_argument("--fps", type=int, default=8, help="movie frames per second")
    ap.add_argument("--force", action="store_true", help="replace an existing output")
    a = ap.parse_args()
    stem = os.path.splitext(a.run)[0]
    out = a.out or (stem + ("-pile.png" if a.what == "figure" else ".mp4"))
    if os.path.exists(out) and not a.force:
        raise SystemExit(f"pile.py: {out}: exists; not overwritten (use --force to replace it)")
    try:
        run = Run(a.run)
        # what every picture reads, read now: a file without it is not a run
        _ = (run.frame_tilt, run.frame_step, run.offset, run.count, run.radius, run.species, pictures.box_width(run))
    except (OSError, KeyError) as e:  # not a run file: one line, no traceback
        raise SystemExit(f"pile.py: {a.run}: not a run or pile file ({e})")
    if run.frames == 0:
        raise SystemExit(f"pile.py: {a.run}: /contacts/step: no frame to draw")
    if a.what == "figure":
        ks = pictures.figure(run, out, a.theta_c)
        print(f"{out}: frames {ks} (tilt {', '.join(f'{run.frame_tilt[k]:.2f}' for k in ks)} deg)")
    else:
        pictures.movie(run, out, a.fps)
        print(f"{out}: {run.frames} frames, {os.path.getsize(out) / 1e6:.2f} MB")


if __name__ == "__main__":
    sys.exit(main())
