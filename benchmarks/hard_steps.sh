# Sourced by the scripts that run admm_on_steps' methods on exported hard steps
# (prox_newton.sh, tnnmg.sh), from their OUTDIR, with $bin and $bench set:
#   hard_pile [TO]            one 1000-grain pile 30 D wide (seed 1, the tools' defaults),
#                             tilted at 0.01 degree per step (to TO degrees, or past its
#                             avalanche): pile.h5, run.h5
#   export_set NAME DEG K [N] its first N (4) steps from DEG degrees at stiffness K, at the
#                             full h with pcg's impulses to 1e-6 or 200 000 sweeps: NAME/
#                             and NAME.pcg.tsv (export_steps: pcg's sweeps and CPU per step)
#   method SET NAME OPTS...   admm_on_steps OPTS on SET's steps into SET.NAME.tsv
# Each keeps what exists, so a second call makes only what is missing.
hard_pile() {
  [ -e pile.h5 ] || "$bin/deposit" --grains 1000 --width 30 --seed 1 --quiet -o pile.h5
  [ -e run.h5 ] || "$bin/tilt-cd" pile.h5 --rate 0.01 ${1:+--to "$1"} --quiet -o run.h5
}
export_set() {
  [ -d "$1" ] || "$bench/export_steps" run.h5 "$2" "${4:-4}" "$1" --all --stiffness "$3" --max-substeps 1 \
    --max-sweeps 200000 > "$1.pcg.tsv"
}
method() {
  local set=$1 name=$2; shift 2
  [ -e "$set.$name.tsv" ] || { "$bench/admm_on_steps" "$@" "$set"/*.dat > "$set.$name.tsv.tmp" &&
    mv "$set.$name.tsv.tmp" "$set.$name.tsv"; }
}
