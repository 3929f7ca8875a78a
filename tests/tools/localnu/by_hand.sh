# nu_i(r), nu_bar, the pdfs and the map of two hand-built frames, from a contact table and from the same contacts in a run file.
# Five contacts on a line at x = 0..4 (D = 1, mu = 0.5): frame 0 (theta 2 deg) has
# contacts 0 and 3 critical (|ft| = mu fn), frame 1 (theta 4 deg) contacts 0 and 1.
# Within r = 1 of x = 0: {0, 1}; of x = 1, 2, 3: three contacts; of x = 4: {3, 4}.
# the exact values below are read with every bit (--digits 0), not the 6 significant digits of a table for people
localnu() { command localnu --digits 0 "$@"; }
cat > line.tsv <<'T'
frame	theta	i	j	x	y	fn	ft
0	2	0	1	0	0	2	1
0	2	1	2	1	0	2	0.2
0	2	2	3	2	0	2	-0.2
0	2	3	4	3	0	2	-1
0	2	4	5	4	0	2	0.2
1	4	0	1	0	0	2	1
1	4	1	2	1	0	2	-1
1	4	2	3	2	0	2	0.2
1	4	3	4	3	0	2	0.2
1	4	4	5	4	0	2	0.2
T
opts="--radii 1,2 --pdf-radius 1 --pdf-bins 4 --map-radius 1 --map-spacing 2 --nu-c 0.5"
localnu line.tsv --mu 0.5 --diameter 1 $opts --quiet > t.tsv
# frames: N = 5, Nc = 2, nu = 2/5; no theta_c: both frames are loading
expect_eq 2 "$(tsv_rows t.tsv frames)"
expect_eq "5 2 0.4 1" "$(tsv_value t.tsv frames N 1) $(tsv_value t.tsv frames Nc 1) $(tsv_value t.tsv frames nu 1) $(tsv_value t.tsv frames loading 2)"
# states rows: (frame 0, r 1), (frame 0, r 2), (frame 1, r 1), (frame 1, r 2)
# frame 0, r = 1: nu_0 = 1/2, nu_3 = 1/3 -> nu_bar 5/12; r = 2: nu_0 = 1/3, nu_3 = 1/4 -> 7/24
expect_near 5/12 "$(tsv_value t.tsv states nu_bar 1)" 1e-15
expect_near 7/24 "$(tsv_value t.tsv states nu_bar 2)" 1e-15
expect_near "1/4+1/9" "$(tsv_value t.tsv states sum2 1)" 1e-15
expect_eq 2 "$(tsv_value t.tsv states n 1)"
# se = sd/sqrt(n): sd of {1/2, 1/3} = (1/6)/sqrt(2) -> se = 1/12
expect_near 1/12 "$(tsv_value t.tsv states se 1)" 1e-15
# frame 1, r = 1: nu_0 = 2/2, nu_1 = 2/3 -> 5/6
expect_near 5/6 "$(tsv_value t.tsv states nu_bar 3)" 1e-15
# pdfs at r = 1 over both frames, bins of 1/4: critical nu_i = 1/2, 1/3 | 1, 2/3;
# non-critical 1/3, 1/3, 1/2 | 1/3, 0, 0 -> count_c 0 1 2 1, count_nc 2 3 1 0
for b in 1 2 3 4; do c+="$(tsv_value t.tsv pdf count_c $b) "; n+="$(tsv_value t.tsv pdf count_nc $b) "; done
expect_eq "0 1 2 1 " "$c"
expect_eq "2 3 1 0 " "$n"
expect_near 2 "$(tsv_value t.tsv pdf P_c 3)" 1e-15      # 2 / (4 x 1/4)
expect_near 4/3 "$(tsv_value t.tsv pdf P_nc 1)" 1e-15   # 2 / (6 x 1/4)
# the map: last loading frame (1); nodes x = 0, 2, 4: nu = 2/2, 1/3, 0/2; above nu_c = 0.5: 1 0 0
expect_eq 1 "$(tsv_result t.tsv map_frame)"
expect_eq 3 "$(tsv_rows t.tsv map)"
expect_near 1/3 "$(tsv_value t.tsv map nu 2)" 1e-15
expect_eq "1 0 0" "$(tsv_value t.tsv map above 1) $(tsv_value t.tsv map above 2) $(tsv_value t.tsv map above 3)"
expect_eq "0 2 4" "$(tsv_value t.tsv map x_D 1) $(tsv_value t.tsv map x_D 2) $(tsv_value t.tsv map x_D 3)"

# --theta-c 3: only frame 0 is loading, so only it enters the pdfs (2 critical, 3 not);
# --map-frame 0 maps it (node x = 0: {0, 1} with contact 0 critical -> 1/2).
localnu line.tsv --mu 0.5 --diameter 1 $opts --theta-c 3 --map-frame 0 --quiet > c.tsv
expect_eq "2 3" "$(tsv_result c.tsv pdf_critical) $(tsv_result c.tsv pdf_noncritical)"
expect_eq "1 0" "$(tsv_value c.tsv frames loading 1) $(tsv_value c.tsv frames loading 2)"
expect_near 1/2 "$(tsv_value c.tsv map nu 1)" 1e-15
# --map-theta 3.9 picks frame 1, --pdf-from 3 pools frame 1 alone (2 critical, 3 not)
localnu line.tsv --mu 0.5 --diameter 1 $opts --map-theta 3.9 --pdf-from 3 --quiet > m.tsv
expect_eq "1 2 3" "$(tsv_result m.tsv map_frame) $(tsv_result m.tsv pdf_critical) $(tsv_result m.tsv pdf_noncritical)"

# --exclude-self: frame 0, r = 1: contact 0 sees {1} (0/1), contact 3 sees {2, 4} (0/2)
localnu line.tsv --mu 0.5 --diameter 1 $opts --exclude-self --table states --quiet > x.tsv
expect_near 0 "$(tsv_value x.tsv states nu_bar 1)" 0
# r = 2: contact 0 sees {1, 2} (0), contact 3 sees {1, 2, 4} (0); frame 1 r = 1: 1/1 and 1/2
expect_near 3/4 "$(tsv_value x.tsv states nu_bar 3)" 1e-15

# --per-contact: nu_i(r) of every contact of the mapped frame (frame 1)
localnu line.tsv --mu 0.5 --diameter 1 $opts --per-contact --table contacts --quiet > pc.tsv
expect_eq "1 0.6666666666666666 0.3333333333333333 0 0" \
  "$(for k in 1 2 3 4 5; do printf '%s ' "$(tsv_value pc.tsv contacts nu_r1 $k)"; done | sed 's/ $//')"

# The same contacts in a run file (mu and D from the run): the same states and pdfs.
table-to-run line.tsv run.h5 1 0.5
localnu run.h5 $opts --quiet > r.tsv
body() { awk -v t="$2" '/^# table: /{on = ($0 == "# table: " t)} on && !/^#/ && NF' "$1"; }
expect_eq "$(body t.tsv states | cut -f4-)" "$(body r.tsv states | cut -f4-)" "(states: table vs run)"
expect_eq "$(body t.tsv pdf)" "$(body r.tsv pdf)" "(pdf: table vs run)"
expect_eq "$(body t.tsv map)" "$(body r.tsv map)" "(map: table vs run)"
expect_eq 1 "$(tsv_value r.tsv frames diameter 1)"
# The run records an avalanche at 3 deg: the loading phase ends there (frame 1 is out).
table-to-run line.tsv run3.h5 1 0.5 3
localnu run3.h5 $opts --quiet > r3.tsv
expect_eq "3 recorded 0" "$(tsv_result r3.tsv run0_theta_c_deg) $(tsv_result r3.tsv run0_theta_c_from) $(tsv_value r3.tsv frames loading 2)"
# HDF5 output holds the same numbers (read back with h5py).
localnu line.tsv --mu 0.5 --diameter 1 $opts -o t.h5 --quiet
"$PY" - <<'P'
import h5py
f = h5py.File("t.h5", "r")
assert f.attrs["kind"] in (b"localnu", "localnu"), f.attrs["kind"]
nb = f["tables/states/nu_bar"][:]
assert abs(nb[0] - 5/12) < 1e-15 and abs(nb[2] - 5/6) < 1e-15, nb
assert list(f["tables/pdf/count_c"][:]) == [0, 1, 2, 1]
P
