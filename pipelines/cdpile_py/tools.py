"""The tools' own tables of a run, for a script that needs a step's or a contact's state:
critical's steps table (nu, and the agitation ek_norm = Ek/(m g D)) and its per-contact
table (critical --contacts: whether each counted contact is critical, sliding, slipping).
A script reads these instead of applying the tools' rules again, so a rule changes in one
place, the C++ (docs/analysis.md)."""
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

from .runfile import Product

PIPELINES = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def tool(name):
    """The cdpile tool NAME: in $CDPILE_BIN (the pipelines' Makefiles export theirs), else on
    PATH, else in the source tree's build/bin, where the Makefiles look by default."""
    folder = os.environ.get("CDPILE_BIN")
    if folder:
        return os.path.join(folder, name)
    return shutil.which(name) or os.path.join(PIPELINES, "..", "build", "bin", name)


class Critical:
    """critical's tables of one run (a partial run too) read with OPTIONS, the rule of the
    critical contacts (--eps E, --walls, --floor-grains grain, ...): the tool runs once, and
    its refusal is the script's, in the tool's one line."""

    def __init__(self, run_path, *options):
        with tempfile.TemporaryDirectory() as d:
            product, contacts = os.path.join(d, "critical.h5"), os.path.join(d, "contacts.h5")
            done = subprocess.run([tool("critical"), run_path, *options, "--quiet", "-o", product,
                                   "--contacts", contacts], stderr=subprocess.PIPE, text=True)
            if done.returncode != 0:
                sys.exit(done.stderr.strip() or f"{tool('critical')} {run_path}: exit {done.returncode}")
            self.steps = Product(product).table("steps")
            self.contacts = Product(contacts).table("contacts")
        self._frames = {}

    def frame(self, k):
        """The counted contacts of frame K as {(i, j): (critical, sliding)}: every active
        contact the rule counts, so one absent is not active (or not counted)."""
        if k not in self._frames:
            c = self.contacts
            rows = np.flatnonzero(c["frame"] == k)
            self._frames[k] = {(int(c["i"][r]), int(c["j"][r])): (int(c["critical"][r]), c["sliding"][r] == 1)
                               for r in rows}
        return self._frames[k]

    def critical_pairs(self, k):
        """The pairs (i, j) of frame K's counted contacts that are critical."""
        return {pair for pair, (critical, _) in self.frame(k).items() if critical}
