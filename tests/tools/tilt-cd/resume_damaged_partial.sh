# --resume on partial runs damaged where the reader alone does not look (found by the structure mutator; docs/fuzzing.md): a rank-0 series /observables/law_residual_rms/value, and a checkpoint impulse outside its Coulomb cone (R_t = 2e290). Each is refused in one line naming the file and the object, exit 1, the partial left as it was, no output and no temporaries.
check() {  # check GZ MESSAGE
  rm -rf case && mkdir case && cd case
  gunzip -c "$CDPILE_SOURCE/tests/data/$1" > run.h5.partial
  cp run.h5.partial ../before.h5
  local rc=0
  tilt-cd unused-pile.h5 --resume -o run.h5 --quiet > ../out.txt 2> ../err.txt || rc=$?
  expect_eq 1 "$rc" "(exit code: $(cat ../err.txt))"
  expect_eq "$2" "$(cat ../err.txt)"
  test ! -s ../out.txt
  cmp run.h5.partial ../before.h5
  expect_eq "run.h5.partial" "$(ls -A)" "(files left)"
  cd ..
}
check partial-scalar-observable.h5.gz "tilt-cd: run.h5.partial: /observables/law_residual_rms/value: expected rows along a first dimension, found 0 dimensions"
check partial-impulse-outside-cone.h5.gz "tilt-cd: run.h5.partial: /checkpoint/impulse_rt: impulse 1 of pair (0, 4): (R_n, R_t) = (3.00821e-06, 1.97585e+290) N s/m is outside the Coulomb cone of mu = 0.5"
