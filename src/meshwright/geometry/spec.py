"""JSON geometry files: a documented, hand-writable description of a :class:`Domain`.

Schema (version 1)
------------------
Top level (an object)::

    {
      "version": 1,                                         optional, must be 1
      "outer": LOOP,                                        required
      "holes": [LOOP, ...],                                 optional
      "segments": [CHAIN, ...],                             optional interior constraints
      "points": [[x, y], ...],                              optional interior points
      "regions": [{"point": [x, y], "marker": 1,            optional region seeds;
                   "max_area": 0.1, "attribute": 0.5}, ...],  max_area, attribute optional
      "size": 0.1,                                          optional suggested spacing
      "open_boundary": false                                optional: outer is the convex hull
                                                            closing open segments (Triangle -c)
    }

A LOOP (closed) or CHAIN (open unless its ends meet) is one of::

    [[x, y], [x, y], ...]                                   polygon / polyline vertices
    {"polygon": [[x, y], ...], "markers": M}                same, with markers
    {"circle": {"center": [x, y], "radius": r}, "marker": m}
    {"ellipse": {"center": [x, y], "a": a, "b": b, "rotation": 0.0}, "marker": m}
    {"naca": "2412", "chord": 1.0, "aoa": 0.0, "origin": [0, 0],
     "closed_te": true, "marker": m}                        NACA 4-digit section
    {"curves": [CURVE, ...]}                                curves joined end to start

where ``M`` is an int or a list with one int per polygon edge, and a CURVE is one of::

    {"line": [[x0, y0], [x1, y1]], "marker": m}
    {"arc": {"center": [x, y], "radius": r, "theta0": a0, "theta1": a1},
     "degrees": false, "marker": m}                         signed sweep a1 - a0
    {"polyline": [[x, y], ...], "markers": M, "marker": m}
    {"spline": [[x, y], ...], "closed": false, "marker": m}   centripetal Catmull-Rom

``marker`` is always optional (default 1 on loops, 0 on constraints).  Unknown keys are
errors, so typos do not pass silently.  Example: a unit square with a circular hole::

    {"outer": [[0, 0], [1, 0], [1, 1], [0, 1]],
     "holes": [{"circle": {"center": [0.5, 0.5], "radius": 0.2}, "marker": 2}],
     "size": 0.05}
"""

from __future__ import annotations

import json
import math
import numbers
from pathlib import Path

import numpy as np

from meshwright.core.errors import FormatError, GeometryError, InputError
from meshwright.geometry.curves import Arc, Line, Polyline, Spline
from meshwright.geometry.domain import Domain
from meshwright.geometry.shapes import ellipse_loop, naca_loop

__all__ = ["domain_from_dict", "domain_to_dict", "load_domain", "save_domain"]

_TOP = {"version", "outer", "holes", "segments", "points", "regions", "size", "open_boundary"}


def _check_keys(obj: dict, allowed: set, where: str) -> None:
    _object(obj, where)
    extra = set(obj) - allowed
    if extra:
        raise FormatError(f"{where}: unknown key(s) {sorted(extra)}; allowed {sorted(allowed)}")


def _object(v, where: str) -> dict:
    if not isinstance(v, dict):
        raise FormatError(f"{where}: expected an object, got {_json_type(v)}")
    return v


def _list(v, where: str) -> list:
    if not isinstance(v, (list, tuple)):
        raise FormatError(f"{where}: expected a list, got {_json_type(v)}")
    return v


def _json_type(v) -> str:
    """What a JSON value is, for messages: ``a string "abc"``, ``null``, ..."""
    names = {
        bool: "a boolean", int: "an integer", float: "a number", str: "a string", list: "a list", dict: "an object"
    }
    if v is None:
        return "null"
    try:
        text = json.dumps(v)
    except (TypeError, ValueError):
        text = repr(v)
    return f"{names.get(type(v), type(v).__name__)} {text[:40]}"


def _number(v, where: str, positive: bool = False) -> float:
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Real):
        raise FormatError(f"{where}: expected a number, got {_json_type(v)}")
    try:
        v = float(v)
    except OverflowError:
        raise FormatError(f"{where}: {str(v)[:20]}... is too large for a float") from None
    if not math.isfinite(v) or (positive and v <= 0):
        raise FormatError(f"{where}: expected a {'positive ' if positive else ''}finite number, got {v!r}")
    return float(v)


def _int(v, where: str) -> int:
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Integral):
        raise FormatError(f"{where}: expected an integer, got {_json_type(v)}")
    if not -(2**31) <= int(v) < 2**31:
        raise FormatError(f"{where}: {int(v)} does not fit a 32-bit marker")
    return int(v)


def _bool(v, where: str) -> bool:
    if not isinstance(v, bool):
        raise FormatError(f"{where}: expected true or false, got {_json_type(v)}")
    return v


def _marker(obj: dict, where: str) -> int | None:
    m = obj.get("marker")
    return None if m is None else _int(m, where + ".marker")


def _point(v, where: str) -> tuple[float, float]:
    if not isinstance(v, (list, tuple, np.ndarray)) or len(v) != 2:
        raise FormatError(f"{where}: expected a point [x, y], got {_json_type(v)}")
    return _number(v[0], where + "[0]"), _number(v[1], where + "[1]")


def _points(v, where: str, least: int = 1) -> np.ndarray:
    _list(v, where)
    a = np.array([_point(p, f"{where}[{i}]") for i, p in enumerate(v)], dtype=np.float64).reshape(-1, 2)
    if len(a) < least:
        raise FormatError(f"{where}: expected at least {least} [x, y] pairs, got {len(a)}")
    return a


def _markers(obj: dict, where: str):
    key = "markers" if "markers" in obj else "marker"
    m = obj.get(key)
    if m is None or (isinstance(m, int) and not isinstance(m, bool)):
        return None if m is None else _int(m, f"{where}.{key}")
    if isinstance(m, list) and all(isinstance(k, int) and not isinstance(k, bool) for k in m):
        return np.asarray([_int(k, f"{where}.{key}[{i}]") for i, k in enumerate(m)], dtype=np.int32)
    raise FormatError(f"{where}.{key}: markers must be an int or a list of ints, got {_json_type(m)}")


def _curve(obj, where: str):
    if not isinstance(obj, dict):
        raise FormatError(f"{where}: a curve must be an object, got {_json_type(obj)}")
    if "line" in obj:
        _check_keys(obj, {"line", "marker"}, where)
        p = _points(obj["line"], where + ".line", 2)
        return Line(p[0], p[1], _marker(obj, where))
    if "arc" in obj:
        _check_keys(obj, {"arc", "degrees", "marker"}, where)
        a = obj["arc"]
        _check_keys(a, {"center", "radius", "theta0", "theta1"}, where + ".arc")
        missing = [key for key in ("center", "radius", "theta0", "theta1") if key not in a]
        if missing:
            raise FormatError(f"{where}.arc: missing {missing[0]!r}")
        k = math.pi / 180.0 if _bool(obj.get("degrees", False), where + ".degrees") else 1.0
        return Arc(
            _point(a["center"], where + ".arc.center"),
            _number(a["radius"], where + ".arc.radius", positive=True),
            k * _number(a["theta0"], where + ".arc.theta0"),
            k * _number(a["theta1"], where + ".arc.theta1"),
            _marker(obj, where),
        )
    if "polyline" in obj:
        _check_keys(obj, {"polyline", "markers", "marker"}, where)
        m = _markers(obj, where)
        arr = isinstance(m, np.ndarray)
        return Polyline(
            _points(obj["polyline"], where + ".polyline", 2),
            m if arr else None,
            marker=None if arr else m,
        )
    if "spline" in obj:
        _check_keys(obj, {"spline", "closed", "marker"}, where)
        return Spline(
            _points(obj["spline"], where + ".spline", 2),
            _bool(obj.get("closed", False), where + ".closed"),
            _marker(obj, where),
        )
    raise FormatError(f"{where}: a curve needs one of 'line', 'arc', 'polyline', 'spline'")


def _chain(obj, where: str, closed: bool) -> list:
    if isinstance(obj, list):
        return [Polyline(_points(obj, where, 2), closed=closed)]
    if not isinstance(obj, dict):
        raise FormatError(f"{where}: expected a list of points or an object, got {_json_type(obj)}")
    if "polygon" in obj:
        _check_keys(obj, {"polygon", "markers", "marker"}, where)
        m = _markers(obj, where)
        arr = isinstance(m, np.ndarray)
        pts = _points(obj["polygon"], where + ".polygon", 2)
        return [Polyline(pts, m if arr else None, closed=closed, marker=None if arr else m)]
    if "circle" in obj:
        _check_keys(obj, {"circle", "marker"}, where)
        c = obj["circle"]
        w = where + ".circle"
        _check_keys(c, {"center", "radius"}, w)
        return [
            Arc(
                _point(c.get("center", [0.0, 0.0]), w + ".center"),
                _number(c.get("radius", 1.0), w + ".radius", positive=True),
                0.0,
                2.0 * math.pi,
                _marker(obj, where),
            )
        ]
    if "ellipse" in obj:
        _check_keys(obj, {"ellipse", "marker"}, where)
        e = obj["ellipse"]
        w = where + ".ellipse"
        _check_keys(e, {"center", "a", "b", "rotation"}, w)
        return ellipse_loop(
            _point(e.get("center", [0.0, 0.0]), w + ".center"),
            _number(e.get("a", 2.0), w + ".a", positive=True),
            _number(e.get("b", 1.0), w + ".b", positive=True),
            _number(e.get("rotation", 0.0), w + ".rotation"),
            _marker(obj, where),
        )
    if "naca" in obj:
        _check_keys(obj, {"naca", "chord", "aoa", "origin", "closed_te", "marker"}, where)
        if not isinstance(obj["naca"], str):
            raise FormatError(f"{where}.naca: expected a string of 4 digits, got {_json_type(obj['naca'])}")
        marker = _marker(obj, where)
        return naca_loop(
            obj["naca"],
            _number(obj.get("chord", 1.0), where + ".chord", positive=True),
            _number(obj.get("aoa", 0.0), where + ".aoa"),
            _point(obj.get("origin", [0.0, 0.0]), where + ".origin"),
            _bool(obj.get("closed_te", True), where + ".closed_te"),
            marker=1 if marker is None else marker,
        )
    if "curves" in obj:
        _check_keys(obj, {"curves"}, where)
        if not isinstance(obj["curves"], list) or not obj["curves"]:
            raise FormatError(f"{where}.curves: expected a non-empty list, got {_json_type(obj['curves'])}")
        return [_curve(c, f"{where}.curves[{i}]") for i, c in enumerate(obj["curves"])]
    raise FormatError(
        f"{where}: a loop needs one of 'polygon', 'circle', 'ellipse', 'naca', 'curves'"
    )


def domain_from_dict(d: dict) -> Domain:
    """Build a :class:`Domain` from a dict following the schema in this module's docstring.

    Raises
    ------
    FormatError
        The dict does not follow the schema (message gives the location, e.g.
        ``holes[1].curves[0]``).
    GeometryError
        The geometry it describes is invalid.
    """
    if not isinstance(d, dict):
        raise FormatError(f"geometry must be a JSON object, got {_json_type(d)}")
    _check_keys(d, _TOP, "geometry")
    if "version" in d and (isinstance(d["version"], bool) or d["version"] != 1):
        raise FormatError(f"unsupported geometry version {d['version']!r}; this reader knows 1")
    if "outer" not in d:
        raise FormatError("geometry: missing 'outer'")
    try:
        outer = _chain(d["outer"], "outer", True)
        holes = [_chain(h, f"holes[{i}]", True) for i, h in enumerate(_list(d.get("holes", []), "holes"))]
        segs = [_chain(s, f"segments[{i}]", False) for i, s in enumerate(_list(d.get("segments", []), "segments"))]
        points = _points(d["points"], "points") if d.get("points") is not None else None
        regions, attributes = [], []
        for i, r in enumerate(_list(d.get("regions", []), "regions")):
            where = f"regions[{i}]"
            if not isinstance(r, dict) or "point" not in r:
                raise FormatError(f"{where}: expected {{'point': [x, y], 'marker': m, 'max_area': a}}")
            _check_keys(r, {"point", "marker", "max_area", "attribute"}, where)
            x, y = _point(r["point"], where + ".point")
            area = r.get("max_area")
            marker = _int(r.get("marker", 0), where + ".marker")
            regions.append(
                (x, y, marker, None if area is None else _number(area, where + ".max_area", positive=True))
            )
            attribute = r.get("attribute")
            attributes.append(float(marker) if attribute is None else _number(attribute, where + ".attribute"))
        size = None if d.get("size") is None else _number(d["size"], "size", positive=True)
        open_boundary = d.get("open_boundary", False)
        if not isinstance(open_boundary, bool):
            raise FormatError(f"open_boundary: expected true or false, got {open_boundary!r}")
        return Domain(
            outer, holes, segments=segs, points=points, regions=regions, size=size,
            region_attributes=attributes, open_boundary=open_boundary,
        )
    except InputError as exc:
        raise FormatError(str(exc)) from exc


def load_domain(path) -> Domain:
    """Read a JSON geometry file (schema in this module's docstring) as a :class:`Domain`."""
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise FormatError(f"{path}: cannot read ({exc.strerror})") from exc
    except UnicodeDecodeError as exc:
        raise FormatError(f"{path}: not UTF-8 text (byte {exc.start}: {exc.reason})") from exc
    except json.JSONDecodeError as exc:
        raise FormatError(f"{path}:{exc.lineno}:{exc.colno}: invalid JSON: {exc.msg}") from exc
    try:
        return domain_from_dict(data)
    except FormatError as exc:
        raise FormatError(f"{path}: {exc}") from exc
    except GeometryError as exc:
        raise GeometryError(f"{path}: {exc}") from exc


def _curve_dict(c) -> dict:
    out: dict
    if isinstance(c, Line):
        out = {"line": [c.p0.tolist(), c.p1.tolist()]}
    elif isinstance(c, Arc):
        out = {
            "arc": {"center": c.center.tolist(), "radius": c.radius, "theta0": c.t0, "theta1": c.t1}
        }
    elif isinstance(c, Polyline):
        out = {"polyline": c.points.tolist()}
        if c.markers is not None:
            out["markers"] = c.markers.tolist()
    elif isinstance(c, Spline):
        out = {"spline": c.points.tolist(), "closed": c.closed}
    else:
        raise InputError(
            f"cannot write a {type(c).__name__} curve to JSON (only lines, arcs, polylines, splines)"
        )
    if c.marker is not None and "markers" not in out:
        out["marker"] = c.marker
    return out


def domain_to_dict(domain: Domain) -> dict:
    """The dict :func:`domain_from_dict` reads back into an equivalent domain.

    Loops are written normalised (outer counter-clockwise, holes clockwise) as curve
    chains.  Raises :class:`~meshwright.core.errors.InputError` for parametric curves,
    which have no JSON form.
    """
    d: dict = {
        "version": 1,
        "outer": {"curves": [_curve_dict(c) for c in domain.loops[0]]},
        "holes": [{"curves": [_curve_dict(c) for c in lp]} for lp in domain.loops[1:]],
    }
    if domain.constraints:
        d["segments"] = [{"curves": [_curve_dict(c) for c in ch]} for ch in domain.constraints]
    if len(domain.points):
        d["points"] = domain.points.tolist()
    if domain.regions:
        d["regions"] = [
            {
                "point": [x, y],
                "marker": m,
                **({} if a is None else {"max_area": a}),
                **({} if v == m else {"attribute": float(v)}),
            }
            for (x, y, m, a), v in zip(domain.regions, domain.region_attributes)
        ]
    if domain.open_boundary:
        d["open_boundary"] = True
    if domain.size is not None and domain.size.constant is not None:
        d["size"] = domain.size.constant
    return d


def save_domain(domain: Domain, path) -> None:
    """Write a Domain as a JSON geometry file (see :func:`domain_to_dict`)."""
    Path(path).write_text(json.dumps(domain_to_dict(domain), indent=1) + "\n")
