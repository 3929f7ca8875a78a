"""What the pipelines' scripts share (pipelines/*.py, pipelines/indeterminacy/*.py,
pipelines/selection/*.py): the one reader of the run and product files (runfile), the
tools' own tables of a run where a script needs a step's or a contact's state (tools:
critical's nu, agitation, static steps and its per-contact critical, sliding and slip,
never the rules applied again in Python), table reading, writing and formatting (tables),
statistics (stats, scipy) and the figures' common steps (style).

A script finds the package by putting the folder that holds it, pipelines/, first on
sys.path:

    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # from a subfolder
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))                   # from pipelines/

Needs Debian's python3-numpy, python3-h5py, python3-scipy and, for figures,
python3-matplotlib; and the built tools (tools.tool: $CDPILE_BIN, else PATH, else
build/bin).
"""
