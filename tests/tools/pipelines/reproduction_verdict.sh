# pipelines/reproduction.py's verdict (its docstring): within twice the combined error and the
# paper's precision is reproduced, beyond it not, and a statistical error larger than the
# paper's value itself determines nothing (beta 1.03 ± 4.9 against 0.5).
"$PY" - "$CDPILE_SOURCE/pipelines" <<'PYEOF'
import sys
sys.path.insert(0, sys.argv[1])
from reproduction import verdict


class Row:
    def __init__(self, ref, value, se, sys_abs=None):
        self.ref, self.value, self.se, self.sys_abs = ref, value, se, sys_abs


assert verdict(Row(0.5, 1.03, 4.9)) == "not determined: its error is larger than the paper's value"
assert verdict(Row(0.5, 1.03, 0.1)) == "not reproduced"
assert verdict(Row(-1.5, -1.44, 0.084)) == "reproduced"
assert verdict(Row(0.08, 0.106, 0.0075, 0.01)) == "within the systematic error"
assert verdict(Row(0.08, None, None)) == "not determined"
PYEOF
