"""What to mesh: domains bounded by loops of true curves, their constructors and file formats.

* :mod:`~meshwright.geometry.curves`: ``Line``, ``Arc``, ``Polyline``, ``Parametric``,
  ``Spline`` with evaluation, arc length and projection;
* :mod:`~meshwright.geometry.domain`: ``Domain`` (validation, orientation, containment,
  discretisation into a ``Discretization``);
* :mod:`~meshwright.geometry.shapes`: polygons, circles, NACA sections, far fields and the
  ``BUILTIN_DOMAINS`` registry;
* :mod:`~meshwright.geometry.poly` (Triangle ``.poly``) and :mod:`~meshwright.geometry.spec`
  (JSON) readers and writers;
* :mod:`~meshwright.geometry.surface` (``Surface``, ``combine``), its built-ins
  (:mod:`~meshwright.geometry.solids`: ``box``, ``sphere``, ``extrude``, ``far_field``) and
  readers (:mod:`~meshwright.geometry.surface_io`): closed surfaces for tetrahedral meshing.
"""

from meshwright.geometry.curves import Arc, Curve, Line, Parametric, Polyline, Spline
from meshwright.geometry.domain import Discretization, Domain
from meshwright.geometry.poly import read_poly, write_poly
from meshwright.geometry.shapes import (
    BUILTIN_DOMAINS,
    FARFIELD,
    WALL,
    airfoil_in_farfield,
    annulus,
    builtin,
    circle,
    circles,
    ellipse,
    ellipse_loop,
    from_shapely,
    naca,
    naca_loop,
    polygon,
    rectangle,
    three_element_airfoil,
    three_element_loops,
)
from meshwright.geometry.solids import box, extrude, far_field, sphere
from meshwright.geometry.spec import domain_from_dict, domain_to_dict, load_domain, save_domain
from meshwright.geometry.surface import Surface, combine
from meshwright.geometry.surface_io import read_surface, write_smesh

__all__ = [
    "Curve",
    "Line",
    "Arc",
    "Polyline",
    "Parametric",
    "Spline",
    "Domain",
    "Discretization",
    "read_poly",
    "write_poly",
    "domain_from_dict",
    "domain_to_dict",
    "load_domain",
    "save_domain",
    "BUILTIN_DOMAINS",
    "builtin",
    "WALL",
    "FARFIELD",
    "polygon",
    "rectangle",
    "circle",
    "ellipse",
    "ellipse_loop",
    "annulus",
    "circles",
    "naca",
    "naca_loop",
    "three_element_loops",
    "three_element_airfoil",
    "airfoil_in_farfield",
    "from_shapely",
    "Surface",
    "combine",
    "box",
    "sphere",
    "extrude",
    "far_field",
    "read_surface",
    "write_smesh",
]
