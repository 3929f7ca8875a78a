# A synthetic nu_bar = nu_inf (1 + A r^alpha) with A = 2, alpha = -1.5 is recovered within the stated uncertainty (and exactly without noise).
# the exact values below are read with every bit (--digits 0), not the 6 significant digits of a table for people
clusterfit() { command clusterfit --digits 0 "$@"; }
"$PY" "$CDPILE_SOURCE/tests/tools/clusterfit/synthetic.py" noisy.tsv 0.01 7 law
clusterfit noisy.tsv --nu-inf pile > f.tsv
expect_eq "3 3" "$(tsv_rows f.tsv fits) $(tsv_result f.tsv windows_fitted)"
for k in 1 2 3; do
  A=$(tsv_value f.tsv fits A $k); As=$(tsv_value f.tsv fits A_se $k)
  al=$(tsv_value f.tsv fits alpha $k); als=$(tsv_value f.tsv fits alpha_se $k)
  expect_eq "1 1 10 8" "$(tsv_value f.tsv fits converged $k) $(tsv_value f.tsv fits weighted $k) $(tsv_value f.tsv fits points $k) $(tsv_value f.tsv fits dof $k)"
  expect_near 2 "$A" "3*$As" "(A, window $k)"
  expect_near -1.5 "$al" "3*$als" "(alpha, window $k)"
  # the stated errors are those of 1 % noise, not zero and not huge
  awk -v s="$As" 'BEGIN { exit !(s > 0.005 && s < 0.2) }'
done
# affine fits over the three windows: slopes compatible with 0
expect_near 0 "$(tsv_value f.tsv affine c1 1)" "3*$(tsv_value f.tsv affine c1_se 1)" "(dA/dtheta)"
expect_near 0 "$(tsv_value f.tsv affine c1 2)" "3*$(tsv_value f.tsv affine c1_se 2)" "(dalpha/dtheta)"
# L = 10 by default: radii 11..20 are outside the fit and the model is nu_inf there
expect_eq "0 0.05" "$(tsv_value f.tsv model in_fit 11) $(tsv_value f.tsv model model 11)"

# Without noise (se = 0: unweighted), the parameters come back to round-off.
"$PY" "$CDPILE_SOURCE/tests/tools/clusterfit/synthetic.py" exact.tsv 0 1 law
clusterfit exact.tsv --table fits > e.tsv
expect_eq 0 "$(tsv_value e.tsv fits weighted 1)"
expect_near 2 "$(tsv_value e.tsv fits A 1)" 1e-8
expect_near -1.5 "$(tsv_value e.tsv fits alpha 2)" 1e-8
# nu_inf as a free parameter: 3 parameters, 7 dof, the same answer
clusterfit exact.tsv --nu-inf fit --table fits > free.tsv
expect_near 0.05 "$(tsv_value free.tsv fits nu_inf 1)" 1e-9
expect_near 2 "$(tsv_value free.tsv fits A 1)" 1e-6
expect_eq 7 "$(tsv_value free.tsv fits dof 1)"
# L = 5 fits radii 1..5 only; --r-min 2 from 2
clusterfit exact.tsv --r-max 5 --r-min 2 --table fits > l5.tsv
expect_eq 4 "$(tsv_value l5.tsv fits points 1)"
# r_c (eq 5) with nu_c = 0.08: [(0.08/0.05 - 1)/2]^(1/-1.5) = 0.3^(-2/3)
clusterfit exact.tsv --nu-c 0.08 --table fits > rc.tsv
expect_near "exp(-2/3*log(0.3))" "$(tsv_value rc.tsv fits r_c 1)" 1e-7
