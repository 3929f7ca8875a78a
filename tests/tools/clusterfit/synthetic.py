# Writes a correlate product (TSV) whose nu_bar follows eq (4) with known A(theta),
# alpha(theta) and nu_inf(theta), plus Gaussian noise of the stated standard error.
#   synthetic.py OUT NOISE SEED MODE
# MODE "law": windows theta = 6, 8, 12 with A = 2, alpha = -1.5, nu_inf = 0.05.
# MODE "divergence": windows theta = 10..19, A = 1.5, alpha = -1.2 and nu_inf chosen so that
#   r_c = [(nu_c/nu_inf - 1)/A]^(1/alpha) = C (theta_c - theta)^-beta with nu_c = 0.08,
#   C = 6, beta = 0.5, theta_c = 20.5 (eq 5 inverted).
import sys
import numpy as np

out, noise, seed, mode = sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
rng = np.random.default_rng(seed)
rows = []
if mode == "law":
    windows = [(t, 2.0, -1.5, 0.05) for t in (6.0, 8.0, 12.0)]
else:
    windows = []
    for t in np.arange(10.0, 19.5, 1.0):
        rc = 6.0 * (20.5 - t) ** -0.5
        windows.append((t, 1.5, -1.2, 0.08 / (1.0 + 1.5 * rc ** -1.2)))
for t, a, alpha, nu_inf in windows:
    for r in range(1, 21):
        nb = nu_inf * (1 + a * r ** alpha) if r <= 10 else nu_inf
        se = noise * nb
        rows.append((t, t - 0.5, t + 0.5, r, nb + se * rng.standard_normal() if se > 0 else nb, se, nu_inf))
with open(out, "w") as f:
    f.write("# kind: correlate\n\n\n# table: windows\n")
    f.write("theta\ttheta_lo\ttheta_hi\tr\tnu_bar\tse\tnu_pile\n")
    for row in rows:
        f.write("\t".join(repr(float(v)) for v in row) + "\n")
