# One name per concept: --avalanche-ek (critical's and localnu's), --mu (the analyses') and
# --theta-method (theta is the tilt everywhere else). The old spellings --avalanche-energy,
# --mu-grain and --theta still work for one version, with a warning, hidden from --help.
deposit --grains 40 --width 8 --seed 1 --mu 0.4 -o p.h5 --quiet
deposit --grains 40 --width 8 --seed 1 --mu-grain 0.4 -o old.h5 --quiet 2> stderr.txt
expect_eq "deposit: warning: --mu-grain is deprecated and will be removed; use --mu" "$(cat stderr.txt)"
h5diff --exclude-path /provenance p.h5 old.h5
opts=(--to 0.1 --rate 0.01 --quiet)
tilt-cd p.h5 "${opts[@]}" --avalanche-ek 0.002 --theta-method 0.6 --mu 0.45 -o new.h5
tilt-cd p.h5 "${opts[@]}" --avalanche-energy 0.002 --theta 0.6 --mu-grain 0.45 -o old_run.h5 2> stderr.txt
expect_eq "tilt-cd: warning: --avalanche-energy is deprecated and will be removed; use --avalanche-ek
tilt-cd: warning: --mu-grain is deprecated and will be removed; use --mu
tilt-cd: warning: --theta is deprecated and will be removed; use --theta-method" "$(cat stderr.txt)"
h5diff --exclude-path /provenance new.h5 old_run.h5
expect_eq "0.6 0.45 0.002" "$(for k in theta mu_grain avalanche_energy; do h5dump -a /parameters/$k new.h5 | sed -n 's/^ *(0): //p'; done | paste -sd ' ')"
expect_fail 2 "tilt-cd: --mu given twice (also as --mu-grain) (see 'tilt-cd --help')" tilt-cd p.h5 --mu 0.4 --mu-grain 0.4 -o x.h5
for tool in deposit tilt-cd; do
  if "$tool" --help | grep -qE -- '--(avalanche-energy|mu-grain|theta)( |$)'; then echo "$tool --help shows an old name" >&2; exit 1; fi
  "$tool" --help | grep -q -- '--theta-method'
done
