# --eps is one declaration (analysis/critical_option.hpp) for the four tools that apply the critical test: each refuses a value outside [0, 0.999999] with the same line when the command line is parsed, before any input is read (missing.h5 does not exist), and accepts the range's ends.
for tool in tilt-cd critical localnu to-xdmf; do
  for bad in 1 -0.001; do
    expect_fail 2 "$tool: --eps: expected a finite number in [0, 0.999999], got '$bad' (out of range) (see '$tool --help')" \
      "$tool" missing.h5 --eps "$bad"
  done
done
# The ends of the range are taken: the refusal is then the missing input's, not the option's.
for tool in critical localnu; do
  for good in 0 0.999999; do
    expect_fail 1 "$tool: missing.h5: no such file" "$tool" missing.h5 --eps "$good"
  done
done
