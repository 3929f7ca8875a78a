# to-lammps --contacts writes each frame's contacts between grains as a LAMMPS dump local (id1 id2 fn ft critical) whose rows read back equal the run's (ids, forces to the last bit, the critical flag by the run's rule, which its observable 'critical' counts with the wall contacts'), with the atoms dump's timesteps; it refuses the atoms dump's own name.
deposit --grains 30 --width 6 --seed 2 --quiet -o pile.h5
tilt-cd pile.h5 --rate 2 --to 6 --frame-every 1 --quiet -o run.h5
to-lammps run.h5 --quiet -o run.dump --contacts run.contacts.dump
expect_eq 4 "$(grep -c '^ITEM: ENTRIES id1 id2 fn ft critical$' run.contacts.dump)"
"$PY" - <<'PY'
import h5py, numpy as np
f = h5py.File("run.h5", "r")
c, par = f["contacts"], f["parameters"].attrs
steps = f["particles/grains/position/step"][:]
obs_step, obs_crit = f["observables/critical/step"][:], f["observables/critical/value"][:]
lines = open("run.contacts.dump").read().split("\n")
atoms = open("run.dump").read().split("\n")
atom_steps = [int(atoms[i + 1]) for i, l in enumerate(atoms) if l == "ITEM: TIMESTEP"]
k, total_critical = -1, 0
for i, l in enumerate(lines):
    if l != "ITEM: TIMESTEP":
        continue
    k += 1
    step = int(lines[i + 1])
    assert step == steps[k] == atom_steps[k], (step, steps[k])
    n = int(lines[i + 3])
    assert lines[i + 2] == "ITEM: NUMBER OF ENTRIES" and lines[i + 8] == "ITEM: ENTRIES id1 id2 fn ft critical"
    rows = [lines[i + 9 + q].split() for q in range(n)]
    o, m = c["offset"][k], c["count"][k]
    j = c["j"][o:o + m]
    pair = j >= 0
    assert n == pair.sum(), (n, pair.sum())
    assert [int(r[0]) for r in rows] == (c["i"][o:o + m][pair] + 1).tolist()
    assert [int(r[1]) for r in rows] == (j[pair] + 1).tolist()
    fn, ft = c["fn"][o:o + m][pair], c["ft"][o:o + m][pair]
    assert [float(r[2]) for r in rows] == fn.tolist()  # the shortest text that reads back
    assert [float(r[3]) for r in rows] == ft.tolist()
    want = ((fn > 0) & (np.abs(ft) >= (1 - par["critical_eps"]) * par["mu_grain"] * fn)).astype(int)
    assert [int(r[4]) for r in rows] == want.tolist()
    total_critical += want.sum()
    # the run's own count at this step (every contact row, a wall's by mu_wall): the pairs'
    # flags are those of the dump
    fa, ta, ja = c["fn"][o:o + m], c["ft"][o:o + m], c["j"][o:o + m]
    mua = np.where(ja < 0, par["mu_wall"], par["mu_grain"])
    alls = (fa > 0) & (np.abs(ta) >= (1 - par["critical_eps"]) * mua * fa)
    assert (alls[pair].astype(int) == want).all()
    q = np.searchsorted(obs_step, step)
    if q < len(obs_step) and obs_step[q] == step:
        assert obs_crit[q] == alls.sum(), (step, obs_crit[q], alls.sum())
assert k == 3 and total_critical > 0, (k, total_critical)
# each snapshot's box is the atoms dump's
assert [l for l in lines if l.startswith("ITEM: BOX")] == [l for l in atoms if l.startswith("ITEM: BOX")]
PY
# a frame range applies to both files
to-lammps run.h5 --first 2 --quiet -o last.dump --contacts last.contacts.dump
expect_eq 2 "$(grep -c '^ITEM: TIMESTEP$' last.contacts.dump)"
expect_eq "$(sed -n 2p last.dump)" "$(sed -n 2p last.contacts.dump)"
expect_fail 2 "to-lammps: --contacts and -o name the same file ./new.dump (see 'to-lammps --help')" \
  to-lammps run.h5 -o new.dump --contacts ./new.dump
test ! -e new.dump
expect_fail 1 "to-lammps: run.contacts.dump: exists; not overwritten (use --force to replace it)" \
  to-lammps run.h5 -o other.dump --contacts run.contacts.dump
test ! -e other.dump
