# The documented pipeline critical + localnu | correlate | clusterfit on a run whose nu, nu_bar(r) and fit are known by construction.
# A line of 201 contacts 1 D apart (x = 0..200), critical ones every 10 D from x = 20 to 180
# (17 of them), in two frames at theta = 5.5 and 6.5 deg. nu = 17/201. Around a critical contact
# r <= 9 D holds 2r + 1 contacts, one critical: nu_i(r) = 1/(2r+1); 10 <= r <= 19 adds its
# critical neighbours, two for the 15 inner ones and one for the 2 at the ends of the chain:
# nu_bar = (15 x 3 + 2 x 2)/17/(2r+1) = 49/(17(2r+1)). No contact within 20 D of a critical
# one is missing (the line runs 20 D beyond the chain).
# the exact values below are read with every bit (--digits 0), not the 6 significant digits of a table for people
clusterfit() { command clusterfit --digits 0 "$@"; }
correlate() { command correlate --digits 0 "$@"; }
localnu() { command localnu --digits 0 "$@"; }
awk 'BEGIN { print "frame\ttheta\ti\tj\tx\ty\tfn\tft"
  for (f = 0; f < 2; f++) for (k = 0; k <= 200; k++)
    print f "\t" 5.5 + f "\t" k "\t" k + 1 "\t" k "\t0\t2\t" ((k % 10 == 0 && k >= 20 && k <= 180) ? 1 : 0.3) }' > line.tsv
table-to-run line.tsv run.h5 1 0.5

critical run.h5 -o critical.tsv --quiet
localnu run.h5 -o - --quiet | correlate - -o - | clusterfit - --nu critical.tsv --nu-c 0.1 > fit.tsv

# critical: nu of each frame and the ensemble nu
expect_near 17/201 "$(tsv_value critical.tsv frames nu 1)" 1e-15
expect_near 17/201 "$(tsv_value critical.tsv ensemble nu 1)" 1e-15
# clusterfit: two windows ([5, 6) and [6, 7)), each with one bin of the ensemble, nu_inf from critical's ensemble
expect_eq "2 2" "$(tsv_rows fit.tsv fits) $(tsv_result fit.tsv windows_fitted)"
expect_eq "ensemble option" "$(sed -n 's/^# parameter nu_inf = //p' fit.tsv) $(sed -n 's/^# parameter nu_c_source = //p' fit.tsv)"
expect_near 17/201 "$(tsv_value fit.tsv fits nu_inf 1)" 1e-15
# nu_bar(r) carried through localnu and correlate (model table, window 1: rows r = 1..20)
for r in 1 2 5 9; do expect_near "1/(2*$r+1)" "$(tsv_value fit.tsv model nu_bar $r)" 1e-15 "(r = $r)"; done
for r in 10 15 19; do expect_near "49/17/(2*$r+1)" "$(tsv_value fit.tsv model nu_bar $r)" 1e-15 "(r = $r)"; done
# r = 20: 5 critical around the 13 inner ones, 4 around the next two, 3 around the ends
expect_near "(13*5+2*4+2*3)/17/41" "$(tsv_value fit.tsv model nu_bar 20)" 1e-15
# the same fit in both windows (the frames are identical)
expect_eq "$(tsv_value fit.tsv fits A 1) $(tsv_value fit.tsv fits alpha 1)" "$(tsv_value fit.tsv fits A 2) $(tsv_value fit.tsv fits alpha 2)"
# eq (5) from the printed A and alpha
A=$(tsv_value fit.tsv fits A 1); al=$(tsv_value fit.tsv fits alpha 1)
expect_near "exp(log((0.1*201/17 - 1)/$A)/$al)" "$(tsv_value fit.tsv fits r_c 1)" 1e-9 "(r_c)"
# A and alpha minimise the unweighted sum of squares of nu_bar/nu_inf - 1 - A r^alpha over
# r = 1..10 (L = 10 D; correlate's se is 0 here, so the fit is unweighted): the gradient vanishes.
"$PY" - "$A" "$al" <<'P'
import sys
import numpy as np
a, al = float(sys.argv[1]), float(sys.argv[2])
r = np.arange(1.0, 11.0)
nb = np.where(r <= 9, 1 / (2 * r + 1), 49 / 17 / (2 * r + 1))
y = nb / (17 / 201) - 1
e = y - a * r**al
g = np.array([np.sum(e * r**al), np.sum(e * a * r**al * np.log(r))])
assert np.all(np.abs(g) < 1e-7 * np.sum(np.abs(y))), g
for da, dal in ((1e-3, 0), (-1e-3, 0), (0, 1e-3), (0, -1e-3)):  # and it is a minimum
    assert np.sum((y - (a + da) * r**(al + dal))**2) > np.sum(e**2)
P
# The same chain through TSV pipes gives the same fit.
localnu run.h5 --format tsv -o - --quiet | correlate - --format tsv -o - | clusterfit - --nu critical.tsv --nu-c 0.1 > fit2.tsv
expect_eq "$A $al" "$(tsv_value fit2.tsv fits A 1) $(tsv_value fit2.tsv fits alpha 1)"
# Provenance: every tool of both chains is recorded in order, the correlate chain (through
# the pipe, stdin) then critical's (--nu critical.tsv), each entry marked with its input
expect_eq "localnu stdin|correlate stdin|critical critical.tsv|clusterfit " \
  "$(awk -F'\t' '/^# provenance: / { sub(/^# provenance: /, ""); printf "%s%s %s", n++ ? "|" : "", $1, $6 }' fit.tsv)"
