# The overlap warning is about the run's own steps (docs/method.md, "Warnings"): a pile deposited at the default stiffness keeps the overlaps its impacts made (here 0.0048 D, beyond the 1e-3 D bound; whether an impact goes that deep depends on the pile and the solver's path: this one does), and a tilt of it records them in max_overlap_m but warns only about what it adds (max_overlap_grown_m).
deposit --grains 200 --width 6 --seed 1 -o pile.h5 --quiet
tilt-cd pile.h5 --to 0.3 -o run.h5 --quiet 2> stderr.txt
expect_eq 0 "$(wc -c < stderr.txt)" "(bytes on stderr)"
"$PY" - <<'PY'
import h5py
with h5py.File("pile.h5", "r") as f:
    D = float(f["parameters"].attrs["diameter_mean_m"])
    inherited = float(f["results"].attrs["max_overlap_m"])
    assert inherited > 1e-3 * D, inherited / D
with h5py.File("run.h5", "r") as f:
    r = f["results"].attrs
    # the pile's overlap is still there, as deep as it was: the rule never pushes it out
    assert abs(float(r["max_overlap_m"]) - inherited) < 1e-2 * inherited, (r["max_overlap_m"] / D, inherited / D)
    assert float(r["max_overlap_grown_m"]) < 1e-4 * D, r["max_overlap_grown_m"] / D
    assert int(r["warnings"]) == 0, dict(r)
PY
