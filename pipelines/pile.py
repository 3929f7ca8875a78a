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
import shutil
import sys

import h5py
import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PatchCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

RED = (0.85, 0.0, 0.0)


def _attr(group, name, default=None):
    v = group.attrs.get(name, default)
    return v.item() if isinstance(v, np.ndarray) and v.size == 1 else v


class Run:
    """The frames of a run (or pile) file, read one at a time."""

    def __init__(self, path):
        self.path = path
        self.f = h5py.File(path, "r")
        g, c = self.f["particles/grains"], self.f["contacts"]
        self.radius = g["radius"][:]
        self.species = g["species"][:]
        self.tilt = c["tilt_angle"][:]  # degree
        self.steps = c["step"][:]
        self.offset, self.count = c["offset"][:], c["count"][:]
        p = self.f["parameters"]
        self.width = float(_attr(p, "box_width_m"))
        self.eps = float(_attr(p, "critical_eps", 1e-3))
        self.mu_grain = float(_attr(p, "mu_grain", 0.5))
        self.mu_wall = float(_attr(p, "mu_wall", self.mu_grain))
        r = self.f["results"] if "results" in self.f else None
        self.theta_c = None
        if r is not None and _attr(r, "avalanche_detected", 0):
            self.theta_c = float(_attr(r, "avalanche_angle_deg"))

    @property
    def frames(self):
        return len(self.tilt)

    def frame(self, k):
        """Grain centres, and the contacts of frame k: i, j, fn, ft, point, critical."""
        pos = self.f["particles/grains/position/value"][k]
        o, n = self.offset[k], self.count[k]
        c = self.f["contacts"]
        i, j = c["i"][o:o + n], c["j"][o:o + n]
        fn, ft, point = c["fn"][o:o + n], c["ft"][o:o + n], c["point"][o:o + n]
        mu = np.where(j < 0, self.mu_wall, self.mu_grain)
        critical = (fn > 0) & (np.abs(ft) >= (1 - self.eps) * mu * fn)
        return pos, dict(i=i, j=j, fn=fn, ft=ft, point=point, critical=critical)


def pick_frames(tilt, theta_c):
    """Frames of the start, half way to theta_c and the last one before it."""
    before = np.flatnonzero(tilt < theta_c)
    last = int(before[-1]) if len(before) else len(tilt) - 1
    half = int(np.argmin(np.abs(tilt[:last + 1] - tilt[last] / 2)))
    return [0, half, last]


def to_lab(xy, theta_deg, pivot):
    """Box coordinates to the laboratory's: the run turns gravity to g (sin t, -cos t) in
    the box's frame, so the box turns by -t about the pivot (the middle of the floor)."""
    t = np.radians(theta_deg)
    rot = np.array([[np.cos(t), np.sin(t)], [-np.sin(t), np.cos(t)]])
    return (np.asarray(xy) - pivot) @ rot.T + pivot


def draw(ax, run, k, top):
    """Frame k on ax: disks, walls, the network (width by f_n / <f_n>), critical in red."""
    pos, c = run.frame(k)
    theta = run.tilt[k]
    pivot = np.array([run.width / 2, 0.0])
    centres = to_lab(pos, theta, pivot)
    glued = run.species != 0
    disks = [Circle(xy, r) for xy, r in zip(centres, run.radius)]
    face = np.where(glued[:, None], [[0.72, 0.72, 0.72]], [[0.86, 0.90, 0.96]])
    ax.add_collection(PatchCollection(disks, facecolors=face, edgecolors=(0.6, 0.65, 0.75), linewidths=0.3))
    walls = to_lab([[0, top], [0, 0], [run.width, 0], [run.width, top]], theta, pivot)
    ax.plot(walls[:, 0], walls[:, 1], color=(0.3, 0.3, 0.3), lw=1.2)
    active = c["fn"] > 0
    if active.any():
        mean = c["fn"][active].mean()
        ends = np.where((c["j"] >= 0)[:, None], pos[np.maximum(c["j"], 0)], c["point"])
        seg = np.stack([to_lab(pos[c["i"]], theta, pivot), to_lab(ends, theta, pivot)], axis=1)
        width = 1.2 * c["fn"] / mean
        plain = active & ~c["critical"]
        ax.add_collection(LineCollection(seg[plain], linewidths=width[plain], colors="black", capstyle="round"))
        crit = c["critical"]
        ax.add_collection(LineCollection(seg[crit], linewidths=np.maximum(width[crit], 1.5), colors=[RED],
                                         capstyle="round"))
    n_crit = int(c["critical"][c["j"] >= 0].sum())
    ax.set_title(f"{theta:.2f} deg: {n_crit} of {int((active & (c['j'] >= 0)).sum())} contacts critical",
                 fontsize=9)
    ax.annotate("", xy=(0.5, 0.88), xytext=(0.5, 0.99), xycoords="axes fraction",
                arrowprops=dict(arrowstyle="-|>", color="green", lw=1.5))
    ax.text(0.53, 0.935, "g", transform=ax.transAxes, color="green", ha="left", va="center")
    ax.set_aspect("equal")
    ax.axis("off")
    return n_crit


def limits(run, top, thetas):
    """Axis limits holding the box at every angle shown."""
    pivot = np.array([run.width / 2, 0.0])
    corners = [[0, 0], [run.width, 0], [0, top], [run.width, top]]
    pts = np.vstack([to_lab(corners, t, pivot) for t in thetas])
    pad = 0.03 * run.width
    # room above for the arrow of gravity
    return (pts[:, 0].min() - pad, pts[:, 0].max() + pad), (pts[:, 1].min() - pad, pts[:, 1].max() + 6 * pad)


def pile_top(run):
    pos = run.f["particles/grains/position/value"]
    return max(float((pos[k][:, 1] + run.radius).max()) for k in (0, run.frames - 1))


def make_figure(run, theta_c=None):
    """The figure of three angles: (figure, its three axes, the frames drawn, theta_c)."""
    theta_c = theta_c if theta_c is not None else run.theta_c
    if theta_c is None:
        theta_c = float(run.tilt[-1]) + 1e-9
    ks = pick_frames(run.tilt, theta_c)
    top = pile_top(run)
    xl, yl = limits(run, top, run.tilt[ks])
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.4))
    for ax, k, what in zip(axes, ks, ("start", "half way", "before theta_c")):
        draw(ax, run, k, top)
        ax.set_xlim(*xl)
        ax.set_ylim(*yl)
        ax.set_title(f"{what}: " + ax.get_title(), fontsize=9)
    fig.suptitle(f"{os.path.basename(run.path)}: the force network (width f_n / <f_n>), critical contacts in red; "
                 f"theta_c = {theta_c:.2f} deg", fontsize=10)
    fig.tight_layout()
    return fig, axes, ks, theta_c


def figure(run, out, theta_c=None):
    """The figure of three angles, written to out; returns the frames drawn."""
    fig, _, ks, _ = make_figure(run, theta_c)
    tmp = out + ".tmp.png"  # renamed when complete: no partial picture under the name asked for
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, out)
    return ks


def movie(run, out, fps):
    """Every frame as a video (H.264 by ffmpeg)."""
    from matplotlib.animation import FFMpegWriter

    if shutil.which("ffmpeg") is None:
        raise SystemExit("pile.py: ffmpeg is not installed (Debian package ffmpeg; scripts/install-deps.sh)")
    top = pile_top(run)
    xl, yl = limits(run, top, [0.0, float(run.tilt.max())])
    # at 100 dpi: 600 pixels wide, an even number high (H.264 in yuv420p wants even sides)
    height = 2 * round((600 * (yl[1] - yl[0]) / (xl[1] - xl[0]) + 40) / 2)
    fig, ax = plt.subplots(figsize=(6, height / 100))
    writer = FFMpegWriter(fps=fps, codec="libx264", extra_args=["-pix_fmt", "yuv420p", "-crf", "28"])
    tmp = out + ".tmp.mp4"  # renamed when complete: no partial video under the name asked for
    with writer.saving(fig, tmp, dpi=100):
        for k in range(run.frames):
            ax.clear()
            draw(ax, run, k, top)
            ax.set_xlim(*xl)
            ax.set_ylim(*yl)
            writer.grab_frame()
    plt.close(fig)
    os.replace(tmp, out)


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
    except (OSError, KeyError) as e:  # not a run file: one line, no traceback
        raise SystemExit(f"pile.py: {a.run}: not a run or pile file ({e})")
    if run.frames == 0:
        raise SystemExit(f"pile.py: {a.run}: /contacts/step: no frame to draw")
    if a.what == "figure":
        ks = figure(run, out, a.theta_c)
        print(f"{out}: frames {ks} (tilt {', '.join(f'{run.tilt[k]:.2f}' for k in ks)} deg)")
    else:
        movie(run, out, a.fps)
        print(f"{out}: {run.frames} frames, {os.path.getsize(out) / 1e6:.2f} MB")


if __name__ == "__main__":
    sys.exit(main())
