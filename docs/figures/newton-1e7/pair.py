# Pairs the runs of RUNS_TSV (first argument) seed by seed with the pcg runs of PCG_TSV
# (second argument; default ../stiff-limit/runs.tsv) (docs/figures/newton-1e7/README.md,
# docs/figures/newton-gmres/README.md, docs/figures/following-rounds/README.md): a table per
# seed, then the mean of the per-seed ratios or differences with its standard error. The
# third argument names the runs of RUNS_TSV (default newton), the base's pcg.
import sys, math
def read(p):
    rows = {}
    for line in open(p):
        f = line.rstrip('\n').split('\t')
        if f[0] == 'run': h = f; continue
        rows[f[0]] = dict(zip(h, f))
    return rows
import os
base = read(sys.argv[2] if len(sys.argv) > 2 else
            os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'stiff-limit', 'runs.tsv'))
new = read(sys.argv[1])
label = sys.argv[3] if len(sys.argv) > 3 else 'newton'
out = []
print('\t'.join(['seed'] + [f'{q}_{w}' for q in ('cpu', 'sweeps', 'substeps', 'theta', 'nu') for w in ('pcg', label)]))
for run, r in sorted(new.items(), key=lambda kv: int(kv[0].split('seed=')[1].split()[0])):
    b = base.get(run)
    if not b: continue
    print('\t'.join([run.split('seed=')[1].split()[0], b['cpu_s'], r['cpu_s'], b['sweeps_per_step'], r['sweeps_per_step'], b['substeps_mean'], r['substeps_mean'], b['theta_c_deg'], r['theta_c_deg'], b['nu_0_10'], r['nu_0_10']]))
    per_step = (float(r['cpu_s']) / float(r['steps'])) / (float(b['cpu_s']) / float(b['steps']))
    out.append((per_step, float(r['theta_c_deg']) - float(b['theta_c_deg']), float(r['nu_0_10']) - float(b['nu_0_10']), float(r['sweeps_per_step']) / float(b['sweeps_per_step'])))
def ms(x):
    n = len(x); m = sum(x) / n
    se = math.sqrt(sum((v - m) ** 2 for v in x) / (n - 1) / n) if n > 1 else float('nan')
    return m, se
if out:
    for i, name in enumerate([f'cpu per step ratio {label}/pcg', f'theta_c {label} - pcg [deg]', f'nu_0_10 {label} - pcg', f'sweeps ratio {label}/pcg']):
        m, se = ms([o[i] for o in out])
        print(f'# {name}: {m:.4f} +- {se:.4f} ({len(out)} pairs)')
