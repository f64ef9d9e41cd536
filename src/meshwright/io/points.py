"""Point-set files: ``.txt`` / ``.csv`` / ``.xyz`` tables, NumPy ``.npy`` and Triangle ``.node``."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from meshwright.core.errors import FormatError, fmt_point

__all__ = ["read_points"]

_COMMENT_CHARS = ("#", "%")


def read_points(path) -> np.ndarray:
    """Read a point set.

    Supported files, chosen by extension:

    * ``.npy``: an (n, 2) or (n, 3) numeric array;
    * ``.node``: Triangle / TetGen vertices (attributes and markers ignored);
    * anything else (``.txt``, ``.csv``, ``.xyz``, ...): one point per line, 2 or 3
      numbers separated by whitespace and/or commas; ``#`` or ``%`` start a comment,
      blank lines are skipped, as is one non-numeric header line before the data.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    (n, 2) or (n, 3) float64, C-contiguous

    Raises
    ------
    FormatError
        Naming the file and, for text files, the line that cannot be parsed.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".npy":
        points = _read_npy(path)
    elif suffix == ".node":
        from meshwright.io.triangle_format import read_node

        try:
            points = read_node(path).points
        except UnicodeDecodeError as exc:
            raise FormatError(f"{path}: not UTF-8 text (byte {exc.start}: {exc.reason})") from exc
    else:
        points = _read_table(path)
    if len(points) == 0:
        raise FormatError(f"{path}: no points found")
    bad = np.flatnonzero(~np.isfinite(points).all(axis=1))
    if len(bad):
        raise FormatError(f"{path}: point {int(bad[0])} has a non-finite coordinate {fmt_point(points[bad[0]])}")
    return np.ascontiguousarray(points, dtype=np.float64)


def _read_npy(path: Path) -> np.ndarray:
    try:
        arr = np.load(path, allow_pickle=False)
    except (ValueError, OSError, EOFError) as exc:
        if isinstance(exc, FileNotFoundError):
            raise
        raise FormatError(f"{path}: not a readable .npy array ({exc})") from exc
    if arr.ndim != 2 or arr.shape[1] not in (2, 3) or not np.issubdtype(arr.dtype, np.number):
        raise FormatError(f"{path}: expected a numeric (n, 2) or (n, 3) array, got {arr.dtype} {arr.shape}")
    return arr.astype(np.float64)


def _read_table(path: Path) -> np.ndarray:
    """Parse a text table; the fast path is ``np.loadtxt``, a line-by-line pass only runs
    to name the offending line when that fails."""
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except UnicodeDecodeError as exc:
        raise FormatError(f"{path}: not UTF-8 text (byte {exc.start}: {exc.reason})") from exc
    data_lines = []
    for lineno, line in enumerate(lines, start=1):
        for char in _COMMENT_CHARS:
            line = line.split(char, 1)[0]
        if line.strip():
            data_lines.append((lineno, line.strip()))
    if not data_lines:
        raise FormatError(f"{path}: no points found")
    first_no, first = data_lines[0]
    if not _numeric(first):
        data_lines = data_lines[1:]  # a header line such as "x,y,z"
        if not data_lines:
            raise FormatError(f"{path}: only a header line ({first!r}), no points")
    text = "\n".join(line.replace(",", " ") for _, line in data_lines)
    try:
        with warnings.catch_warnings():
            # a line of separators only (",") leaves no data: the shape check below names it
            warnings.simplefilter("ignore", UserWarning)
            arr = np.loadtxt(text.splitlines(), dtype=np.float64, ndmin=2)
    except ValueError:
        arr = None
    if arr is None or arr.shape[1] not in (2, 3):
        _raise_first_bad_line(path, data_lines)
    bad = np.flatnonzero(~np.isfinite(arr).all(axis=1))
    if len(bad):
        i = int(bad[0])
        raise FormatError(
            f"{path}: point {i} has a non-finite coordinate {fmt_point(arr[i])} (line {data_lines[i][0]})"
        )
    return arr


def _numeric(line: str) -> bool:
    try:
        [float(f) for f in line.replace(",", " ").split()]
    except ValueError:
        return False
    return True


def _raise_first_bad_line(path: Path, data_lines: list[tuple[int, str]]) -> None:
    width = None
    for lineno, line in data_lines:
        fields = line.replace(",", " ").split()
        if not _numeric(line):
            raise FormatError(f"{path}, line {lineno}: cannot parse {line!r} as numbers")
        if len(fields) not in (2, 3):
            raise FormatError(f"{path}, line {lineno}: expected 2 or 3 coordinates, got {len(fields)} in {line!r}")
        if width is not None and len(fields) != width:
            raise FormatError(f"{path}, line {lineno}: {len(fields)} coordinates where earlier lines have {width}")
        width = len(fields)
    raise FormatError(f"{path}: cannot parse the point table")
