"""Helpers shared by the example scripts: the output folder and multi-panel figures.

Figures are drawn on the Agg canvas directly, so the scripts run headless.
"""

from __future__ import annotations

import sys
from pathlib import Path


def output_dir() -> Path:
    """The folder named on the command line (default ``examples-output``), created."""
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "examples-output")
    out.mkdir(parents=True, exist_ok=True)
    return out


def panels(n: int, size: float = 5.0):
    """A figure with ``n`` side-by-side axes; returns (figure, list of axes)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(size * n, size))
    FigureCanvasAgg(fig)
    axes = [fig.add_subplot(1, n, i + 1) for i in range(n)]
    return fig, axes


def zoom(ax, xlim, ylim) -> None:
    """Show only the window ``xlim`` x ``ylim`` of an equal-aspect plot."""
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)


def save(fig, path: Path) -> None:
    """Write the figure and say where."""
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    print(f"wrote {path}")
