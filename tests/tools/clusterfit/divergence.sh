# A synthetic r_c = C (theta_c - theta)^-beta with beta = 0.5, theta_c = 20.5 is recovered within the stated uncertainty, with theta_c fitted or given.
# the exact values below are read with every bit (--digits 0), not the 6 significant digits of a table for people
clusterfit() { command clusterfit --digits 0 "$@"; }
"$PY" "$CDPILE_SOURCE/tests/tools/clusterfit/synthetic.py" d.tsv 0.002 11 divergence
clusterfit d.tsv --nu-inf pile --nu-c 0.08 --power-from 10 > f.tsv
expect_eq "10 10 1" "$(tsv_result f.tsv windows_fitted) $(tsv_result f.tsv power_points) $(tsv_result f.tsv theta_c_fitted)"
b=$(tsv_result f.tsv beta); bs=$(tsv_result f.tsv beta_se)
t=$(tsv_result f.tsv theta_c_deg); ts=$(tsv_result f.tsv theta_c_se_deg)
expect_near 0.5 "$b" "3*$bs" "(beta)"
expect_near 20.5 "$t" "3*$ts" "(theta_c)"
awk -v s="$bs" 'BEGIN { exit !(s > 0 && s < 0.5) }'
# r_c of each window against C (theta_c - theta)^-beta, within 3 stated errors
for k in 1 5 10; do
  th=$(tsv_value f.tsv fits theta $k)
  expect_near "6*exp(-0.5*log(20.5-$th))" "$(tsv_value f.tsv fits r_c $k)" "3*$(tsv_value f.tsv fits r_c_se $k)" "(r_c at $th)"
done
# theta_c given: beta alone, closer
clusterfit d.tsv --nu-inf pile --nu-c 0.08 --power-from 10 --theta-c 20.5 > g.tsv
expect_eq "0 20.5" "$(tsv_result g.tsv theta_c_fitted) $(tsv_result g.tsv theta_c_deg)"
expect_near 0.5 "$(tsv_result g.tsv beta)" "3*$(tsv_result g.tsv beta_se)" "(beta, theta_c given)"
# The default power range starts at 15 deg (the paper's): windows 15..19 only
clusterfit d.tsv --nu-inf pile --nu-c 0.08 > p.tsv
expect_eq 5 "$(tsv_result p.tsv power_points)"
# --rc-from affine: A and alpha from the affine fits (exactly constant here) give the same r_c
clusterfit d.tsv --nu-inf pile --nu-c 0.08 --rc-from affine --power-from 10 > a.tsv
expect_near "$(tsv_value f.tsv fits r_c 3)" "$(tsv_value a.tsv fits r_c 3)" "3*$(tsv_value f.tsv fits r_c_se 3)"
# nu_c and nu_inf from a critical product (ensemble table, nu_c result)
{ printf '# kind: critical\n# result nu_c = 0.08\n# result nu_c_se = 0.001\n\n\n# table: ensemble\ntheta\tnu\tnu_se\n'
  awk -F'\t' '$4 == "1.0" { print $1 "\t" $7 "\t" 0.0001 }' d.tsv; } > critical.tsv
clusterfit d.tsv --nu critical.tsv --power-from 10 > c.tsv
expect_eq "ensemble critical" "$(sed -n 's/^# parameter nu_inf = //p' c.tsv) $(sed -n 's/^# parameter nu_c_source = //p' c.tsv)"
expect_near "$(awk -F'\t' '$4 == "1.0" { print $7; exit }' d.tsv)" "$(tsv_value c.tsv fits nu_inf 1)" 1e-15
expect_near 0.5 "$(tsv_result c.tsv beta)" "3*$(tsv_result c.tsv beta_se)" "(beta, nu from critical)"
