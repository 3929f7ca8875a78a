# nu_bar pooled in theta windows over frames and runs, with the cluster-robust errors, from a hand-built localnu product.
# Two frames of five contacts on a line (D = 1): frame 0 (theta 2) nu_i(1) of its critical
# contacts = 1/2, 1/3; frame 1 (theta 4) = 1, 2/3 (see localnu/by_hand.sh).
# the exact values below are read with every bit (--digits 0), not the 6 significant digits of a table for people
correlate() { command correlate --digits 0 "$@"; }
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
localnu line.tsv --mu 0.5 --diameter 1 --radii 1 -o l.h5 --quiet
# windows of 1 deg: [2, 3) holds frame 0, [4, 5) frame 1; one frame -> se over its contacts
correlate l.h5 > w1.tsv
expect_eq 2 "$(tsv_rows w1.tsv windows)"
expect_eq "2 2 3 contacts" "$(tsv_value w1.tsv windows theta 1) $(tsv_value w1.tsv windows theta_lo 1) $(tsv_value w1.tsv windows theta_hi 1) $(tsv_value w1.tsv windows se_over 1)"
expect_near 5/12 "$(tsv_value w1.tsv windows nu_bar 1)" 1e-15
expect_near 5/6 "$(tsv_value w1.tsv windows nu_bar 2)" 1e-15
expect_near 1/6 "$(tsv_value w1.tsv windows se 2)" 1e-15   # sd of {1, 2/3} / sqrt(2)
expect_near 2/5 "$(tsv_value w1.tsv windows nu_pile 1)" 1e-15
expect_eq 2 "$(tsv_rows w1.tsv frames)"
# one window of 5 deg holds both frames of the one run: pooled (5/6 + 5/3)/4 = 5/8; se over
# the 2 frames: 2 ((5/6 - 2 5/8)^2 + (5/3 - 2 5/8)^2) / 4^2 = (5/24)^2
correlate l.h5 --window 5 --table windows > w5.tsv
expect_eq "1 1 2 4 frames" "$(tsv_rows w5.tsv windows) $(tsv_value w5.tsv windows runs 1) $(tsv_value w5.tsv windows frames 1) $(tsv_value w5.tsv windows n 1) $(tsv_value w5.tsv windows se_over 1)"
expect_near 5/8 "$(tsv_value w5.tsv windows nu_bar 1)" 1e-15
expect_near 5/24 "$(tsv_value w5.tsv windows se 1)" 1e-15
expect_near 3 "$(tsv_value w5.tsv windows theta 1)" 1e-15
# Two runs: the table and a copy of it (the same file twice is refused). Clusters are the
# runs, each S = 5/2, N = 4: nu_bar = 5/8 and se = 0 (identical runs); runs = 2.
cp line.tsv line2.tsv
localnu line.tsv line2.tsv --mu 0.5 --diameter 1 --radii 1 -o - --quiet | correlate - --window 5 > r2.tsv
expect_eq "2 4 8 runs" "$(tsv_value r2.tsv windows runs 1) $(tsv_value r2.tsv windows frames 1) $(tsv_value r2.tsv windows n 1) $(tsv_value r2.tsv windows se_over 1)"
expect_near 5/8 "$(tsv_value r2.tsv windows nu_bar 1)" 1e-15
expect_near 0 "$(tsv_value r2.tsv windows se 1)" 1e-15
# --from/--to select frames; the others are counted
correlate l.h5 --from 3 --to 10 > sel.tsv
expect_eq "1 1 4" "$(tsv_result sel.tsv frames_used) $(tsv_result sel.tsv frames_outside_range) $(tsv_value sel.tsv windows theta 1)"
# A table without theta: every frame in one window with theta NA
cut -f1,3- line.tsv > notheta.tsv
localnu notheta.tsv --mu 0.5 --diameter 1 --radii 1 -o - --quiet | correlate - > nt.tsv
expect_eq "1 NA" "$(tsv_rows nt.tsv windows) $(tsv_value nt.tsv windows theta 1)"
expect_near 5/8 "$(tsv_value nt.tsv windows nu_bar 1)" 1e-15
# TSV input gives the same as HDF5 input
localnu line.tsv --mu 0.5 --diameter 1 --radii 1 --quiet > l.tsv
expect_eq "$(correlate l.h5 --table windows | grep -v '^# \(command\|input\|provenance\|tool\)')" \
          "$(correlate l.tsv --table windows | grep -v '^# \(command\|input\|provenance\|tool\)')"
