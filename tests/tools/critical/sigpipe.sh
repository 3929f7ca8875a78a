# A reader that closes the pipe once it has what it wanted (| head) ends the tool quietly
# with the shell's status for SIGPIPE (141, as coreutils), not "broken pipe" and exit 1.
deposit --grains 60 --width 10 --seed 5 -o pile.h5 --quiet
tilt-cd pile.h5 --to 10 --rate 0.01 --frame-every 500 -o run.h5 --quiet
# 125 kB of steps at full precision (--digits 0): more than a pipe holds (64 kB), so
# critical is still writing when head exits
set +e
critical run.h5 --table steps --digits 0 --quiet 2> stderr.txt | head -n 1 > first.txt
status=("${PIPESTATUS[@]}")
set -e
expect_eq "141 0 0" "${status[*]} $(wc -c < stderr.txt)" "(critical's and head's status, stderr bytes)"
grep -q '^# table: steps' first.txt
# A pipe closed before the tool writes (deterministic): HDF5 too, killed by SIGPIPE.
"$PY" - <<'PY'
import os, subprocess
for cmd in (["deposit", "--grains", "20", "--width", "6", "-o", "-", "--quiet"], ["critical", "run.h5", "--quiet"]):
    r, w = os.pipe()
    os.close(r)
    p = subprocess.run(cmd, stdout=w, stderr=subprocess.PIPE)
    os.close(w)
    assert (p.returncode, p.stderr) == (-13, b""), (cmd, p.returncode, p.stderr)
PY
