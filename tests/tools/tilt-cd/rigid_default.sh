# Rigid contacts (--stiffness 0) at the tools' other defaults (docs/method.md, "Sub-steps"): no sub-steps and a cap of 100 000 sweeps at h, recorded in /parameters, so a small pile tilted through its avalanche has every step converged at the full step and its contact law satisfied to 1e-4 g h; the compliant defaults' rescue (--max-substeps 64 --max-sweeps 2000, given) leaves rigid steps at the cap on the same pile. An option given wins over the rigid default; a branch of a compliant run at --stiffness 0 takes the rigid defaults, and says so.
deposit --grains 60 --width 8 --seed 3 -o pile.h5 --quiet
tilt-cd pile.h5 --rate 0.05 --stiffness 0 -o run.h5 --quiet 2> stderr.txt
expect_eq 0 "$(wc -c < stderr.txt)" "(bytes on stderr)"
tilt-cd pile.h5 --rate 0.05 --stiffness 0 --to 10 --max-substeps 64 --max-sweeps 2000 -o split.h5 --quiet 2> split.txt
tilt-cd pile.h5 --rate 0.05 --to 0.1 --stiffness 0 --max-sweeps 3000 -o capped.h5 --quiet
tilt-cd pile.h5 --rate 0.05 --to 0.1 --stiffness 0 --max-substeps 4 -o four.h5 --quiet
tilt-cd pile.h5 --rate 0.05 --to 0.1 -o soft.h5 --quiet
tilt-cd soft.h5 --branch-at 0.05 --stiffness 0 --to 0.1 -o branch.h5 2> branch.txt
grep -qx "tilt-cd: soft.h5: branch: max_sweeps 100000 (the run's 2000: the default with rigid contacts)" branch.txt
grep -qx "tilt-cd: soft.h5: branch: max_substeps 1 (the run's 64: the default with rigid contacts)" branch.txt
"$PY" - <<'PY'
import h5py, numpy as np
def params(path):
    with h5py.File(path, "r") as f:
        p = f["parameters"].attrs
        return int(p["max_substeps"]), int(p["max_sweeps"])
assert params("run.h5") == (1, 100000), params("run.h5")
assert params("split.h5") == (64, 2000), params("split.h5")
assert params("capped.h5") == (1, 3000), params("capped.h5")
assert params("four.h5") == (4, 100000), params("four.h5")
assert params("soft.h5") == (64, 2000), params("soft.h5")
assert params("branch.h5") == (1, 100000), params("branch.h5")
with h5py.File("run.h5", "r") as f:
    r, o = f["results"].attrs, f["observables"]
    assert float(f["parameters"].attrs["contact_stiffness_N_m2"]) == 0.0
    assert int(r["avalanche_detected"]) == 1, dict(r)
    assert int(r["unconverged_steps"]) == 0, dict(r)
    assert o["converged/value"][:].min() == 1
    assert o["substeps/value"][:].max() == 1
    law = o["law_residual/value"][:]
    assert np.all(np.isfinite(law)) and law.max() < 1e-4, law.max()
    assert o["sweeps/value"][:].max() > 2000, "no step needed more than the compliant cap: no test of it"
with h5py.File("split.h5", "r") as f:
    assert int(f["results"].attrs["unconverged_steps"]) > 0, "the split rigid steps all converged"
PY
grep -q "hit the sweep cap" split.txt
