"""Quadtree quads at thin junction wedges (issue 12: min scaled Jacobian > 0.2 where the
input does not force a corner).

A segment meeting a boundary edge or another segment at a small angle leaves a thin wedge
whose gap triangulation is a ladder of slivers; split into quads they kept the slivers'
small angles at corners with an interior side (stress seed 15001: 0.045 to 0.185).

Oracle: NumPy only.  Each quad corner's sine ``cross / (|a| |b|)`` from the points, and
which corners the input forces (both sides of the corner are line cells: the input's own
angle, exempt); every other corner must have a sine above 0.2.  The mesh must also keep
every input vertex and cover the domain's area (shoelace), so a mesh that dropped the
wedge would fail.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from meshwright import quadrangulate
from meshwright.geometry import polygon


def _corner_sines(points, quads, lines):
    """(q, 4) corner sines and (q, 4) bool: forced corners (both sides line cells)."""
    n = len(points)
    lines = np.asarray(lines, dtype=np.int64)
    keys = np.concatenate([lines[:, 0] * n + lines[:, 1], lines[:, 1] * n + lines[:, 0]])
    quads = np.asarray(quads, dtype=np.int64)
    prev, nxt = np.roll(quads, 1, axis=1), np.roll(quads, -1, axis=1)
    forced = np.isin(prev * n + quads, keys) & np.isin(quads * n + nxt, keys)
    q = points[quads]
    into = q - np.roll(q, 1, axis=1)
    out = np.roll(q, -1, axis=1) - q
    cross = into[..., 0] * out[..., 1] - into[..., 1] * out[..., 0]
    return cross / (np.hypot(into[..., 0], into[..., 1]) * np.hypot(out[..., 0], out[..., 1])), forced


def _area(loop):
    x, y = np.asarray(loop, dtype=np.float64).T
    return 0.5 * abs(math.fsum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _check(outer, segments, points, size, seed=0):
    dom = polygon(np.array(outer), segments=[np.array(s) for s in segments],
                  points=np.array(points) if points else None)
    mesh = quadrangulate(dom, size, method="quadtree", seed=seed)
    assert set(mesh.cells) == {"quad", "line"}
    sines, forced = _corner_sines(mesh.points, mesh.cells["quad"], mesh.cells["line"])
    assert (sines > 0).all()
    free = sines[~forced]
    assert free.min() > 0.2, f"unforced corner sine {free.min():.4f}"
    inputs = np.vstack([outer] + [np.array(s) for s in segments] + ([points] if points else []))
    for p in inputs:
        assert (mesh.points == p).all(axis=1).any(), f"input vertex {p} is no mesh vertex"
    q = mesh.points[mesh.cells["quad"]]
    x, y = q[..., 0], q[..., 1]
    area = 0.5 * (x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y).sum()
    assert area == pytest.approx(_area(outer), rel=1e-9)
    return forced


def test_segments_meeting_an_edge_and_a_segment_at_small_angles():
    # Dyadic coordinates, so the junction lies exactly on the first segment: 3.0 degrees
    # between the first segment and the bottom edge, the second ending on the first at 7.1
    # degrees, the third meeting the right edge at 4.0 degrees.
    outer = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    s1 = [(0.125, 0.0), (0.875, 0.0390625)]
    s2 = [(0.5, 0.01953125), (0.875, 0.0859375)]
    s3 = [(1.0, 0.75), (0.4, 0.7080078125)]
    forced = _check(outer, [s1, s2, s3], [], 0.04)
    assert forced.any()  # the wedges' tips are the input's own angles



def test_sliver_domain_corner_of_0_007_degrees():
    # The whole domain is one wedge (thin stress domains reach 0.003 degrees): no core
    # cell fits, the gap is the ladder, and the tip quad's centre sits 1e-4 of the way in.
    forced = _check([(0.0, 0.0), (1.0, 0.0), (1.0, 2.0**-13)], [], [], 2.0**-4)
    assert forced.any()

def test_stress_15001_domain_45_junction_at_1_7_degrees():
    # A segment from the middle of an outer edge inward, 1.7 degrees off the edge, and
    # five more meeting at junctions inside; the default size.
    outer = [
        [0.8746471405029297, 0.041515350341796875], [0.9258937835693359, 0.18309402465820312],
        [0.5779008865356445, 0.5292034149169922], [0.3937091827392578, 0.5017185211181641],
        [0.22632122039794922, 0.5236024856567383], [0.10414886474609375, 0.6301975250244141],
        [0.0250701904296875, 0.5547542572021484], [-0.30372047424316406, 0.9202175140380859],
        [-0.2533454895019531, 0.6758995056152344], [-0.22654342651367188, 0.5540695190429688],
        [-0.3392019271850586, 0.3951292037963867], [-0.6679134368896484, 0.6272296905517578],
        [-0.6435623168945312, 0.5884590148925781], [-0.7699661254882812, 0.5623435974121094],
        [-0.48944854736328125, 0.3354377746582031], [-0.4998664855957031, -0.025412559509277344],
        [-0.7986984252929688, -0.1756734848022461], [-0.7215900421142578, -0.3128328323364258],
        [-0.583064079284668, -0.5599508285522461], [-0.5189990997314453, -0.5853137969970703],
        [-0.5117301940917969, -0.7821798324584961], [-0.21134662628173828, -0.6102466583251953],
        [-0.23179054260253906, -0.7803230285644531], [-0.1936187744140625, -0.9092321395874023],
        [0.029134750366210938, -0.5436906814575195], [0.057890892028808594, -0.7635469436645508],
        [0.06993579864501953, -0.6603288650512695], [0.10317039489746094, -0.894073486328125],
        [0.2594442367553711, -0.5622892379760742], [0.5642337799072266, -0.8099699020385742],
        [0.37308406829833984, -0.413604736328125], [0.4862174987792969, -0.5311040878295898],
        [0.7295846939086914, -0.4697742462158203], [0.7085971832275391, -0.19177722930908203],
    ]
    segments = [
        [[0.08655309677124023, -0.7772011756896973], [0.02163827419281006, -0.19430029392242432]],
        [[-0.5510315895080566, -0.5726323127746582], [-0.2755157947540283, -0.2863161563873291]],
        [[0.2991752624511719, 0.04326820373535156], [0.011898040771484375, -0.30205345153808594]],
        [[-0.2741737365722656, -0.1273059844970703], [-0.2389850616455078, 0.1851053237915039]],
        [[-0.033748626708984375, 0.048931121826171875], [0.26326560974121094, 0.000102996826171875]],
        [[0.1568737030029297, -0.018793106079101562], [-0.26097798347473145, -0.01015174388885498]],
    ]
    points = [[0.08371734619140625, -0.21572303771972656], [-0.252180814743042, 0.06795108318328857]]
    _check(outer, segments, points, None, seed=807261)


def test_stress_15001_domain_127_junctions():
    outer = [[0.9092178344726562, 0.0], [0.2409982681274414, 0.7417163848876953],
             [-0.6649932861328125, 0.48314571380615234], [-0.7143049240112305, -0.5189723968505859],
             [0.2632122039794922, -0.8100824356079102]]
    segments = [
        [[0.8256903886795044, 0.09271454811096191], [0.4644508436322212, 0.05215193331241608]],
        [[0.2520170211791992, -0.1669301986694336], [-0.28601741790771484, 0.0978384017944336]],
        [[0.19760608673095703, -0.22875690460205078], [-0.2208242416381836, 0.20643329620361328]],
        [[0.10147666931152344, -0.1468048095703125], [0.050254106521606445, -0.0676419734954834]],
        [[-0.08777523040771484, -0.05319786071777344], [-0.11621665954589844, 0.09763574600219727]],
    ]
    points = [[0.18476271629333496, -0.1338341236114502], [0.09299850463867188, -0.11995935440063477]]
    _check(outer, segments, points, 0.19336535585481474, seed=145124)


def test_boundary_size_follows_the_boundary_spacing():
    # size="boundary": the spacing of the boundary as given (1/32 along the bottom, one
    # segment per other side), graded inward.
    bottom = [(i / 32, 0.0) for i in range(33)]
    outer = bottom + [(1.0, 1.0), (0.0, 1.0)]
    mesh = quadrangulate(polygon(np.array(outer)), "boundary", method="quadtree")
    assert set(mesh.cells) == {"quad", "line"}
    sines, _ = _corner_sines(mesh.points, mesh.cells["quad"], mesh.cells["line"])
    assert sines.min() > 0.2
    for p in outer:
        assert (mesh.points == p).all(axis=1).any()
    q = mesh.points[mesh.cells["quad"]]
    x, y = q[..., 0], q[..., 1]
    assert 0.5 * (x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y).sum() == pytest.approx(1.0, rel=1e-12)
    side = np.hypot(*(np.roll(q, -1, axis=1) - q).transpose(2, 0, 1))
    on_bottom = y.min(axis=1) == 0.0
    on_top = y.max(axis=1) == 1.0
    assert side[on_bottom].max() < 1.5 / 32  # the bottom's own spacing
    assert side[on_top].mean() > 3.0 / 32  # graded up away from it
