# to-lammps writes a run as a LAMMPS dump custom, one snapshot per frame (id type x y z radius vx vy vz omegaz mass), whose values are the run's; --first/--last/--every choose frames; from-lammps reads it back as atoms snapshots.
deposit --grains 12 --width 5 --seed 3 --quiet -o pile.h5
tilt-cd pile.h5 --rate 1 --to 3 --frame-every 1 --quiet -o run.h5
to-lammps run.h5 --quiet -o run.dump
expect_eq 4 "$(grep -c '^ITEM: TIMESTEP$' run.dump)"
expect_eq 4 "$(grep -c '^ITEM: ATOMS id type x y z radius vx vy vz omegaz mass$' run.dump)"
"$PY" - <<'PY'
import h5py, numpy as np
f = h5py.File("run.h5", "r")
g = f["particles/grains"]
pos, vel, om = g["position/value"][:], g["velocity/value"][:], g["angular_velocity/value"][:]
steps, r, m, sp = g["position/step"][:], g["radius"][:], g["mass"][:], g["species"][:]
lines = open("run.dump").read().split("\n")
k = -1
for i, l in enumerate(lines):
    if l == "ITEM: TIMESTEP":
        k += 1
        assert int(lines[i + 1]) == steps[k]
        n = int(lines[i + 3])
        assert n == r.size
        assert lines[i + 4] == "ITEM: BOX BOUNDS ff ff pp"
        rows = np.array([[float(x) for x in lines[i + 9 + q].split()] for q in range(n)])
        assert (rows[:, 0] == np.arange(1, n + 1)).all() and (rows[:, 1] == sp + 1).all()
        assert (rows[:, 2] == pos[k, :, 0]).all() and (rows[:, 3] == pos[k, :, 1]).all() and (rows[:, 4] == 0).all()
        assert (rows[:, 5] == r).all() and (rows[:, 6] == vel[k, :, 0]).all() and (rows[:, 7] == vel[k, :, 1]).all()
        assert (rows[:, 9] == om[k]).all() and (rows[:, 10] == m).all()
        ylo, yhi = map(float, lines[i + 6].split())
        assert ylo <= (pos[k, :, 1] - r).min() and yhi >= (pos[k, :, 1] + r).max()
assert k == 3
PY
# a frame range
to-lammps run.h5 --first 1 --last 3 --every 2 --quiet > some.dump
expect_eq 2 "$(grep -c '^ITEM: TIMESTEP$' some.dump)"
# from-lammps reads the snapshots (no contacts in them: frames without rows)
from-lammps run.dump --quiet > back.tsv
grep -qx 'frame	i	j	wall	x	y	fn	ft' back.tsv
expect_fail 1 "to-lammps: run.h5: no frame 9 (4 frames)" to-lammps run.h5 --first 9
