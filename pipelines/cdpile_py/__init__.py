"""What the pipelines' scripts share (pipelines/*.py, pipelines/indeterminacy/*.py,
pipelines/selection/*.py): the one reader of the run and product files (runfile), the
rules the tools apply, mirrored where a script needs them per contact or per step (rules),
table reading, writing and formatting (tables), statistics (stats, scipy) and the
figures' common steps (style).

A script finds the package by putting the folder that holds it, pipelines/, first on
sys.path:

    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # from a subfolder
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))                   # from pipelines/

Needs Debian's python3-numpy, python3-h5py, python3-scipy and, for figures,
python3-matplotlib.
"""
