# The pile's pictures (pipelines/pile.py), drawn offscreen and looked at pixel by pixel: the figure at three angles has every contact's segment with f_n >= <f_n> drawn black and every critical one red at its midpoint, the last panel is the last frame before theta_c with its tilt angle in its title, the box is turned by the tilt (lab frame); make movie writes a small H.264 video of every frame; an existing output is not replaced.
# ctest: slow, timeout 120
deposit --grains 30 --width 6 --seed 2 --quiet -o pile.h5
tilt-cd pile.h5 --rate 2 --to 6 --frame-every 1 --quiet -o run.h5
"$PY" - "$CDPILE_SOURCE/pipelines" <<'PY'
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
from cdpile_py import pictures
from cdpile_py.runfile import Run

run = Run("run.h5")
fig, axes, ks, theta_c = pictures.make_figure(run, theta_c=5.0)  # frames at 0, 2, 4 deg; 6 is past it
assert list(run.frame_tilt[ks]) == [0.0, 2.0, 4.0], run.frame_tilt[ks]
fig.canvas.draw()
img = np.asarray(fig.canvas.buffer_rgba())[..., :3].astype(int)
H = img.shape[0]


def near(ax, xy, test):
    """Whether a pixel within 2 of the display point of data point xy passes test."""
    col, row = ax.transData.transform(xy)
    c, r = int(round(col)), int(round(H - row))
    return bool(test(img[r - 2:r + 3, c - 2:c + 3]).any())


red = lambda b: (b[..., 0] > 150) & (b[..., 1] < 80) & (b[..., 2] < 80)
black = lambda b: b.sum(axis=-1) < 150
found = {"critical": 0, "loaded": 0}
for ax, k in zip(axes, ks):
    pos, c = pictures.frame(run, k)
    pivot = np.array([pictures.box_width(run) / 2, 0.0])
    pairs = c["j"] >= 0
    a = pictures.to_lab(pos[c["i"][pairs]], run.frame_tilt[k], pivot)
    b = pictures.to_lab(pos[c["j"][pairs]], run.frame_tilt[k], pivot)
    mid = (a + b) / 2
    # a segment's width is proportional to f_n / <f_n>: those at or above the mean are thick
    mean = c["fn"][c["fn"] > 0].mean()
    crit, loaded = c["critical"][pairs], (c["fn"][pairs] >= mean) & ~c["critical"][pairs]
    for q in np.flatnonzero(crit):
        assert near(ax, mid[q], red), f"frame {k}: critical contact {q} not red at its midpoint"
    for q in np.flatnonzero(loaded):
        assert near(ax, mid[q], black), f"frame {k}: loaded contact {q} not drawn at its midpoint"
    found["critical"] += int(crit.sum())
    found["loaded"] += int(loaded.sum())
    # the box turned by the tilt: the floor's slope in the picture is -tan(theta)
    floor = pictures.to_lab([[0, 0], [pictures.box_width(run), 0]], run.frame_tilt[k], pivot)
    slope = (floor[1, 1] - floor[0, 1]) / (floor[1, 0] - floor[0, 0])
    assert abs(slope + np.tan(np.radians(run.frame_tilt[k]))) < 1e-12
assert found["critical"] > 0 and found["loaded"] > 0, found
title = axes[2].get_title()
assert title.startswith("before theta_c: 4.00 deg: "), title
assert "red" in fig._suptitle.get_text() and "theta_c = 5.00 deg" in fig._suptitle.get_text()
print(f"pile figure: {found['critical']} critical segments red, {found['loaded']} loaded segments drawn; {title}")
PY
"$PY" "$CDPILE_SOURCE/pipelines/pile.py" figure run.h5 -o pile.png --theta-c 5 > fig.log
test -s pile.png && test ! -e pile.png.tmp.png
expect_fail 1 "pile.py: pile.png: exists; not overwritten (use --force to replace it)" \
  "$PY" "$CDPILE_SOURCE/pipelines/pile.py" figure run.h5 -o pile.png
# not a run: one line, no picture
echo "not a run" > bad.h5
if "$PY" "$CDPILE_SOURCE/pipelines/pile.py" figure bad.h5 -o bad.png 2> bad.err; then exit 1; fi
expect_eq 1 "$(wc -l < bad.err)"
grep -q '^pile.py: bad.h5: not a run or pile file (' bad.err
test ! -e bad.png
if ! command -v ffmpeg > /dev/null; then
  echo "the movie is not checked: ffmpeg (Debian package ffmpeg) is not installed; scripts/install-deps.sh installs it" >&2
  exit 0
fi
make --no-print-directory -s -C "$CDPILE_SOURCE/pipelines" movie RUN="$PWD/run.h5" > movie.log
test -s run.mp4 && test ! -e run.mp4.tmp.mp4
expect_eq "h264|4" "$(ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=codec_name,nb_read_frames -of csv=p=0 run.mp4 | tr ',' '|')"
(( $(stat -c %s run.mp4) < 5000000 ))
if make --no-print-directory -s -C "$CDPILE_SOURCE/pipelines" movie 2> err.txt; then exit 1; fi
grep -qx "pipelines: movie: give RUN=path/to/run.h5" err.txt
