# deposit | tilt-cd through a pipe: the run has every step, its frames and both tools'
# provenance; a run written to stdout reads back.
set -o pipefail
deposit --grains 100 --width 12 --seed 1 -o - --quiet | tilt-cd - --to 0.2 --rate 0.01 --frame-every 5 -o run.h5 --quiet
"$PY" - <<'PY'
import h5py, numpy as np
def t(v): return v.decode() if isinstance(v, bytes) else v  # fixed-length strings read as bytes
f = h5py.File("run.h5", "r")
assert t(f.attrs["kind"]) == "run"
assert list(f["observables/tilt_angle/step"][:]) == list(range(1, 21))
assert np.allclose(f["observables/tilt_angle/value"][:], 0.01 * np.arange(1, 21))
assert list(f["contacts/step"][:]) == [0, 5, 10, 15, 20]
assert f["results"].attrs["steps"] == 20 and t(f["results"].attrs["stop_reason"]) == "to"
assert f["parameters"].attrs["tilt_rate_deg_per_step"] == 0.01
tools = [t(f["provenance"][k].attrs["tool"]) for k in f["provenance"]]
assert tools == ["deposit", "tilt-cd"], tools
assert t(f["provenance/001"].attrs["inputs"]) == "stdin"
assert "checkpoint" not in f
for name in ["critical", "critical_grain", "sliding", "contacts", "sweeps", "residual", "converged"]:
    assert f["observables"][name]["value"].shape == (20,), name
PY
deposit --grains 60 --width 10 -o pile.h5 --quiet
expect_eq "grains $(( 60 + $(h5dump -a /parameters/floor_grains pile.h5 | grep -A1 DATA | tail -1 | awk '{print $2}') )) frames 3 contacts" \
  "$(tilt-cd pile.h5 --to 0.1 --rate 0.01 --frame-every 5 -o - --quiet | cli-demo - | cut -d' ' -f1-5)"
