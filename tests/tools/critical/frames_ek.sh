# The frames table has Ek (mean translational kinetic energy per free grain) from the grains' velocities: by hand, and equal to the per-step Ek of the same step.
# the exact values below are read with every bit (--digits 0), not the 6 significant digits of a table for people
critical() { command critical --digits 0 "$@"; }
printf 'frame\ttheta\ti\tj\tx\ty\tfn\tft\n0\t1\t0\t1\t0\t0\t1\t0.5\n0\t1\t1\t2\t1\t0\t1\t0\n1\t2\t0\t1\t0\t0\t1\t0.5\n' > ok.tsv
table-to-run ok.tsv run.h5 1 0.5
# Three free disks of diameter 1 m, density 2500: m = 2500 pi / 4. In frame 1, grain 0 moves
# at (3, 4) m/s and grain 2 at (0, -1): Ek = m (25 + 1) / 2 / 3 grains.
"$PY" -c "import h5py; f = h5py.File('run.h5', 'r+'); v = f['particles/grains/velocity/value']; v[1, 0] = (3, 4); v[1, 2] = (0, -1)"
critical run.h5 --table frames --quiet > f.tsv
expect_eq "0 J m-1" "$(tsv_value f.tsv frames Ek 1) $(sed -n 's/.* Ek \[\([^]]*\)\].*/\1/p' f.tsv)"
expect_near "2500*3.141592653589793/4*26/2/3" "$(tsv_value f.tsv frames Ek 2)" 1e-9
# ek_norm = Ek / (m g D), g = 9.81 m/s^2, D = 1 m
expect_near "26/2/3/9.81" "$(tsv_value f.tsv frames ek_norm 2)" 1e-12
# On a simulated run, a frame's Ek is the per-step Ek of its step (the same velocities).
deposit --grains 60 --width 8 --seed 1 -o pile.h5 --quiet
tilt-cd pile.h5 --rate 0.5 --to 10 --frame-every 5 -o tilt.h5 --quiet
critical tilt.h5 --quiet > c.tsv
awk -F'\t' '/^# table: /{t = $0} /^#/ || !NF {next}
  t ~ /steps$/  { if (!hs) { for (i = 1; i <= NF; i++) sc[$i] = i; hs = 1; next } ek[$sc["step"]] = $sc["Ek"] }
  t ~ /frames$/ { if (!hf) { for (i = 1; i <= NF; i++) fc[$i] = i; hf = 1; next }
                  if ($fc["step"] in ek) { n++; if ($fc["Ek"] != ek[$fc["step"]]) { print "step " $fc["step"] ": frame Ek " $fc["Ek"] " step Ek " ek[$fc["step"]]; bad = 1 } } }
  END { if (n < 2) { print "only " n " frames compared"; bad = 1 } exit bad }' c.tsv
