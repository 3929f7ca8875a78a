# Every choice of critical that moves a reported number is recorded in the product's /parameters: the static classification's rest and slip thresholds, the mobilisation window, and the envelope's fitted range when one is asked (it decides nu_c where the envelope keeps rising).
deposit --grains 40 --width 8 --seed 1 -o p.h5 --quiet
tilt-cd p.h5 --rate 1 --to 3 -o run.h5 --quiet
critical run.h5 -o default.h5 --quiet
critical run.h5 --rest-energy 2e-6 --rest-speed 0.03 --slip-speed 0.002 --mobilisation-window 1 \
  --envelope-from 0.5 --envelope-to 2.5 -o asked.h5 --quiet
"$PY" - <<'P'
import h5py
d = dict(h5py.File("default.h5", "r")["parameters"].attrs)
a = dict(h5py.File("asked.h5", "r")["parameters"].attrs)
assert (d["rest_energy_mgD"], d["rest_speed_sqrt_gD"], d["mobilisation_window_deg"]) == (1e-6, 1e-2, 2.0), d
assert "envelope_fit_from_deg" not in d and "envelope_fit_to_deg" not in d, d
assert (a["rest_energy_mgD"], a["rest_speed_sqrt_gD"], a["slip_speed_sqrt_gD"], a["mobilisation_window_deg"]) \
    == (2e-6, 0.03, 0.002, 1.0), a
assert (a["envelope_fit_from_deg"], a["envelope_fit_to_deg"]) == (0.5, 2.5), a
P
# Only the upper end asked: only it is recorded.
critical run.h5 --envelope-to 2 -o to.h5 --quiet
"$PY" -c 'import h5py; p = h5py.File("to.h5", "r")["parameters"].attrs; assert p["envelope_fit_to_deg"] == 2.0 and "envelope_fit_from_deg" not in p, dict(p)'
