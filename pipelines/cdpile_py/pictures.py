"""Pictures of the pile itself from a run file (docs/schema.md): the grains, the force
network (a segment between the centres of each pair in contact, its width proportional to
f_n / <f_n>, the frame's mean over its active contacts) and the critical contacts in red,
in the laboratory frame (gravity down, the box turned by the tilt angle); a figure of three
angles, or a video of every frame (pipelines/pile.py; figures.py draws the study's)."""
import os
import shutil

import numpy as np
from matplotlib.collections import LineCollection, PatchCollection
from matplotlib.patches import Circle

from .style import plt, save_png
from .tools import Critical

RED = (0.85, 0.0, 0.0)


def box_width(run):
    """The box's width [m]."""
    return float(run.parameters["box_width_m"])


_critical = {}  # critical's tables of each run drawn, read once for all its frames


def frame(run, k):
    """Grain centres, and the contacts of frame k: i, j, fn, ft, point, and critical (as
    critical says of every active contact, walls included, by the run's critical_eps,
    mu_grain and mu_wall)."""
    c = run.contacts(k, ("i", "j", "fn", "ft", "point"))
    if run.path not in _critical:
        eps = ["--eps", repr(float(run.parameters["critical_eps"]))] if "critical_eps" in run.parameters else []
        _critical[run.path] = Critical(run.path, "--walls", "--floor-grains", "grain", *eps)
    critical = _critical[run.path].critical_pairs(k)
    c["critical"] = np.array([(int(i), int(j)) in critical for i, j in zip(c["i"], c["j"])], dtype=bool)
    return run.positions(k), c


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
    pos, c = frame(run, k)
    theta = run.frame_tilt[k]
    pivot = np.array([box_width(run) / 2, 0.0])
    centres = to_lab(pos, theta, pivot)
    glued = run.species != 0
    disks = [Circle(xy, r) for xy, r in zip(centres, run.radius)]
    face = np.where(glued[:, None], [[0.72, 0.72, 0.72]], [[0.86, 0.90, 0.96]])
    ax.add_collection(PatchCollection(disks, facecolors=face, edgecolors=(0.6, 0.65, 0.75), linewidths=0.3))
    walls = to_lab([[0, top], [0, 0], [box_width(run), 0], [box_width(run), top]], theta, pivot)
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
    pivot = np.array([box_width(run) / 2, 0.0])
    corners = [[0, 0], [box_width(run), 0], [0, top], [box_width(run), top]]
    pts = np.vstack([to_lab(corners, t, pivot) for t in thetas])
    pad = 0.03 * box_width(run)
    # room above for the arrow of gravity
    return (pts[:, 0].min() - pad, pts[:, 0].max() + pad), (pts[:, 1].min() - pad, pts[:, 1].max() + 6 * pad)


def pile_top(run):
    return max(float((run.positions(k)[:, 1] + run.radius).max()) for k in (0, run.frames - 1))


def make_figure(run, theta_c=None):
    """The figure of three angles: (figure, its three axes, the frames drawn, theta_c)."""
    theta_c = theta_c if theta_c is not None else run.avalanche_angle
    if theta_c is None:
        theta_c = float(run.frame_tilt[-1]) + 1e-9
    ks = pick_frames(run.frame_tilt, theta_c)
    top = pile_top(run)
    xl, yl = limits(run, top, run.frame_tilt[ks])
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
    save_png(fig, out)
    plt.close(fig)
    return ks


def movie(run, out, fps):
    """Every frame as a video (H.264 by ffmpeg)."""
    from matplotlib.animation import FFMpegWriter

    if shutil.which("ffmpeg") is None:
        raise SystemExit("pile.py: ffmpeg is not installed (Debian package ffmpeg; scripts/install-deps.sh)")
    top = pile_top(run)
    xl, yl = limits(run, top, [0.0, float(run.frame_tilt.max())])
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
