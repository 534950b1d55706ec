"""Shared helpers for thermodec plot scripts: read JSON, save PNG atomically."""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load_args():
    if len(sys.argv) != 3:
        sys.exit(f"usage: {sys.argv[0]} DATA.json OUT.png")
    with open(sys.argv[1]) as f:
        return json.load(f), sys.argv[2]


def save(fig, path):
    tmp = os.path.join(os.path.dirname(os.path.abspath(path)), "." + os.path.basename(path) + ".tmp.png")
    fig.savefig(tmp, dpi=110, bbox_inches="tight")
    plt.close(fig)
    os.replace(tmp, path)
