"""The figures' common steps: matplotlib without a display, and figures written whole (to a
temporary renamed when complete) as PNG at 110 dpi, with a PDF beside it where asked."""
import os

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt  # noqa: E402

DPI = 110


def save_png(fig, path):
    """The figure as PNG at `path`."""
    tmp = path + ".tmp.png"  # renamed when complete: no partial picture under the name asked for
    fig.savefig(tmp, dpi=DPI)
    os.replace(tmp, path)


def save(fig, folder, stem, pdf=True):
    """The figure laid out tight as folder/stem.png and, with pdf, folder/stem.pdf, then
    closed; returns the PNG's path."""
    fig.tight_layout()
    png = os.path.join(folder, stem + ".png")
    save_png(fig, png)
    if pdf:
        path = os.path.join(folder, stem + ".pdf")
        fig.savefig(path + ".tmp.pdf")
        os.replace(path + ".tmp.pdf", path)
    plt.close(fig)
    return png
