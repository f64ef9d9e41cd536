"""Zhu's pair-by-pair advancing front (issue 12, chapter 18.5.1 steps 1-9): method "zhu".

Oracles never share code with the kernel: the parity of every sub-front by this file's own
breadth-first two-colouring and face count of the live front faces (read from the arrays
after each pause), areas and convexity by exact ``Fraction`` arithmetic, conformity by a
dictionary of directed edges, and :meth:`Mesh.validate`.
"""

from __future__ import annotations

import math
from collections import defaultdict, deque
from fractions import Fraction

import numpy as np
import pytest

from meshwright.core.errors import InputError, MeshingError
from meshwright.geometry import airfoil_in_farfield, circle, circles, naca_loop, polygon
from meshwright.quad import QUAD_METHODS, quadrangulate
from meshwright.quad.pairing import _open_ears, pair_domain
from meshwright.quad.parity import ParityError, make_loops_even
from meshwright.quad import _zhu_kernel as zk
from meshwright.quad.zhu import PairFront, two_colour, zhu_front
from meshwright.sizing import gradation
from meshwright.sizing.field import as_size_field
from meshwright.tri import _front_kernel as fk
from meshwright.tri.cdt import SegmentCurves, cdt_build

# ------------------------------------------------------------------ independent oracles


def _cross(p, q, r) -> Fraction:
    """Exact (q - p) x (r - p)."""
    px, py = Fraction(float(p[0])), Fraction(float(p[1]))
    return (Fraction(float(q[0])) - px) * (Fraction(float(r[1])) - py) - (Fraction(float(q[1])) - py) * (
        Fraction(float(r[0])) - px
    )


def _pieces(faces):
    """Connected pieces of the undirected graph of ``faces`` [(a, b)], each as (face count,
    two-colourable), by breadth first search; also checks every node has as many faces in
    as out (the faces form closed loops)."""
    deg = defaultdict(int)
    adj = defaultdict(list)
    for i, (a, b) in enumerate(faces):
        deg[a] += 1
        deg[b] -= 1
        adj[a].append((b, i))
        adj[b].append((a, i))
    assert all(v == 0 for v in deg.values()), "the front is not made of closed loops"
    colour, out = {}, []
    for root in adj:
        if root in colour:
            continue
        colour[root] = 0
        queue, seen, ok = deque([root]), set(), True
        while queue:
            v = queue.popleft()
            for w, i in adj[v]:
                seen.add(i)
                if w not in colour:
                    colour[w] = 1 - colour[v]
                    queue.append(w)
                elif colour[w] == colour[v]:
                    ok = False
        out.append((len(seen), ok))
    return out


def _live_faces(pf):
    fs = pf.fr.fs
    nf = int(fs.meta[fk.M_NF])
    alive = np.flatnonzero(fs.falive[:nf] == 1)
    return [(int(fs.face[f, 0]), int(fs.face[f, 1])) for f in alive if fs.face[f, 0] != fs.face[f, 1]]


def _min_scaled_jacobian(xy, quads) -> float:
    worst = 1.0
    for q in quads:
        for k in range(4):
            p, c, n = xy[q[k - 1]], xy[q[k]], xy[q[(k + 1) % 4]]
            ux, uy = n[0] - c[0], n[1] - c[1]
            wx, wy = p[0] - c[0], p[1] - c[1]
            worst = min(worst, (ux * wy - uy * wx) / (math.hypot(ux, uy) * math.hypot(wx, wy)))
    return worst


def _check_all_quad(mesh):
    """Every quad strictly convex (exact), conforming (each interior edge twice, opposite
    ways), every boundary edge a line cell."""
    xy, quads = mesh.points, mesh.cells["quad"]
    assert "triangle" not in mesh.cells
    assert all(all(_cross(xy[q[k - 1]], xy[q[k]], xy[q[(k + 1) % 4]]) > 0 for k in range(4)) for q in quads)
    directed = set()
    for q in quads.tolist():
        for k in range(4):
            e = (q[k], q[(k + 1) % 4])
            assert e not in directed
            directed.add(e)
    boundary = {e for e in directed if (e[1], e[0]) not in directed}
    lines = {tuple(e) for e in mesh.cells["line"].tolist()}
    # Boundary edges are line cells; the other line cells are interior segments, used by
    # quads on both sides.
    assert boundary <= lines
    assert all((b, a) in directed and (a, b) in directed for a, b in lines - boundary)


def _classified(dom, size):
    """The classified constrained triangulation pair_domain starts from, and its field."""
    field = as_size_field(size)
    disc, _ = make_loops_even(dom, dom.discretize(field))
    ct = cdt_build(disc.points, disc.segments, seed=0, curves=SegmentCurves.from_domain(dom, disc))
    ct.classify(segment_sides=np.where(dom.curve_loop[disc.segment_curve] >= 0, 1, 0), holes=disc.holes, regions=[])
    return ct, field


# ------------------------------------------------------------------ parity


def test_two_colour_alternates_on_even_loops_and_refuses_an_odd_one():
    square = np.array([[0, 1], [1, 2], [2, 3], [3, 0]], dtype=np.int32)
    hexagon = np.array([[4 + k, 4 + (k + 1) % 6] for k in range(6)], dtype=np.int32)
    col = two_colour(np.vstack([square, hexagon]), 12)
    faces = np.vstack([square, hexagon])
    assert (col[faces[:, 0]] != col[faces[:, 1]]).all()
    assert (col[10:] == -1).all()
    assert two_colour(np.array([[0, 1], [1, 2], [2, 0]], dtype=np.int32), 3) is None
    # Two even loops sharing nodes through an odd path: an odd cycle across them.
    assert two_colour(np.array([[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]], dtype=np.int32), 4) is None


def test_two_colour_matches_brute_force_on_small_graphs():
    """Random small face sets: a colouring is returned exactly when one of the 2^k
    colourings of the used nodes (enumerated here) is proper, and then it is proper, gives
    each connected piece's smallest node 0 and leaves unused nodes at -1."""
    rng = np.random.default_rng(12)
    for _ in range(200):
        n = int(rng.integers(2, 10))
        faces = rng.integers(0, n, size=(int(rng.integers(1, 12)), 2)).astype(np.int32)
        faces = faces[faces[:, 0] != faces[:, 1]]
        used = sorted(set(faces.ravel().tolist()))
        proper = any(
            all(((bits >> used.index(a)) & 1) != ((bits >> used.index(b)) & 1) for a, b in faces.tolist())
            for bits in range(2 ** len(used))
        )
        col = two_colour(faces, n)
        assert (col is not None) == proper
        if col is None:
            continue
        assert (col[faces[:, 0]] != col[faces[:, 1]]).all()
        assert all(col[v] == -1 for v in range(n) if v not in used)
        piece = list(range(n))
        def root(v):
            while piece[v] != v:
                v = piece[v]
            return v
        for a, b in faces.tolist():
            piece[max(root(a), root(b))] = min(root(a), root(b))
        assert all(col[v] == 0 for v in used if root(v) == v)


def test_every_sub_front_stays_even_after_each_quad_and_both_figure_cases_occur():
    """Paused after every pair: the live front is closed loops, each piece even and
    two-colourable (every loop even); over the run a pair made a new node D without
    splitting the front (Figure 18.5.1a) and a pair split it into more pieces (18.5.1b)."""
    dom = circles(centers=[(0.5, 0.5)], radii=[0.2], box=(0, 0, 1, 1))
    ct, field = _classified(dom, 0.12)
    pf = PairFront(ct, field)
    assert pf.coloured
    new_node = split = False
    pieces = _pieces(_live_faces(pf))
    assert all(n % 2 == 0 and ok for n, ok in pieces)
    for _ in range(2000):
        fs = pf.fr.fs
        nt, n_nodes = int(fs.meta[fk.M_NT]), int(fs.meta[fk.M_NP])
        code = pf.run(max_tris=nt + 2)
        if not pf.pairing:
            break
        assert int(fs.meta[fk.M_NT]) == nt + 2 and pf.tpair[nt] == 1
        a, b, c = pf.fr.fs.tri[nt].tolist()
        t2 = pf.fr.fs.tri[nt + 1].tolist()
        assert len({a, b, c} & set(t2)) == 2, "the two triangles of a pair share a side"
        after = _pieces(_live_faces(pf))
        assert all(n % 2 == 0 and ok for n, ok in after), f"an odd sub-front after pair {nt // 2}"
        new_node |= int(pf.fr.fs.meta[fk.M_NP]) > n_nodes and len(after) == len(pieces)
        split |= len(after) > len(pieces)
        pieces = after
    else:
        pytest.fail("the pair front did not finish in 2000 pairs")
    assert code == fk.R_DONE
    assert new_node and split


def test_scratch_smaller_than_the_faces_is_refused_not_outgrown():
    """The kernel's search never replaces its scratch (its arrays stay the caller's): scratch
    without room for every face is an error before any pair is made."""
    dom = circles(centers=[(0.5, 0.5)], radii=[0.2], box=(0, 0, 1, 1))
    ct, field = _classified(dom, 0.12)
    pf = PairFront(ct, field)
    fs = pf.fr.fs
    pf.scratch = zk.new_scratch(fs.qmeta[zk.Q_DEPTH], len(fs.face) - 1)
    with pytest.raises(MeshingError, match="scratch"):
        pf.run()
    assert int(fs.meta[fk.M_NT]) == 0


def test_pairs_tile_the_domain_exactly():
    dom = polygon([(0, 0), (1, 0), (1, 1), (0, 1)], holes=[[(0.3, 0.3), (0.3, 0.6), (0.6, 0.6), (0.6, 0.3)]])
    ct, field = _classified(dom, 0.07)
    pts, tris, pairs, report = zhu_front(ct, field)
    # Counter-clockwise (exact), no directed edge twice, the edges used once exactly the
    # segments: the triangles tile the region the segments bound.
    assert all(_cross(pts[a], pts[b], pts[c]) > 0 for a, b, c in tris.tolist())
    directed = set()
    for t in tris.tolist():
        for k in range(3):
            e = (t[k], t[(k + 1) % 3])
            assert e not in directed
            directed.add(e)
    boundary = {tuple(sorted(e)) for e in directed if (e[1], e[0]) not in directed}
    assert boundary == {tuple(sorted(e)) for e in ct.segments()[0].tolist()}
    area = sum(_cross(pts[a], pts[b], pts[c]) for a, b, c in tris.tolist()) / 2
    assert float(area) == pytest.approx(1 - 0.3**2, rel=1e-12)
    used = pairs.ravel()
    assert len(np.unique(used)) == len(used)
    for t, s in pairs.tolist():
        assert s == t + 1 and len(set(tris[t].tolist()) & set(tris[s].tolist())) == 2
    assert report.coloured and report.pairs == len(pairs)
    assert report.triangles == len(tris) - 2 * len(pairs)


# ------------------------------------------------------------------ left faces, odd faces


def test_faces_left_by_the_pair_front_are_closed_by_the_triangle_front_and_paired():
    dom = airfoil_in_farfield("0012")
    size = gradation(naca_loop("0012")[0].evaluate(np.linspace(0.0, 2.0 * np.pi, 400)), 0.03, 1.3, 2.5)
    ct, field = _classified(dom, size)
    pts, tris, pairs, report = zhu_front(ct, field)
    assert report.stuck > 0 and report.triangles > 0, "this case is meant to leave faces"
    fill, rep = pair_domain(dom, size, front="pairs", all_quad=False)
    assert rep.triangles_left == len(fill.triangles)
    mesh = quadrangulate(dom, size, method="zhu")
    mesh.validate()
    _check_all_quad(mesh)
    assert _min_scaled_jacobian(mesh.points, mesh.cells["quad"]) > 0.2


def test_a_face_closed_odd_by_segments_is_left_to_the_triangle_front():
    # The wall from (0.75, 0) to (1, 1) closes a face of three segments (bottom, right
    # side, wall), though the outer loop has ten.
    dom = polygon(
        [(0, 0), (0.25, 0), (0.5, 0), (0.75, 0), (1, 0), (1, 1), (0.75, 1), (0.5, 1), (0.25, 1), (0, 1)],
        segments=[[(0.75, 0), (1, 1)]],
    )
    ct, field = _classified(dom, 2.0)
    assert len(ct.points) == 10
    pf = PairFront(ct, field)
    assert not pf.coloured
    pf.run()
    pts, tris, pairs, report = pf.result()
    assert not report.coloured and len(pairs) == 0 and report.triangles == len(tris)
    mesh = quadrangulate(dom, 2.0, method="zhu")
    mesh.validate()
    _check_all_quad(mesh)


def test_a_paired_ear_is_left_alone():
    xy = np.array([[0, -0.05], [1, 0], [-1, 0], [0.0, 1.0]], dtype=np.float64)
    tris = np.array([[0, 1, 2], [2, 1, 3], [0, 0, 0], [0, 0, 0]], dtype=np.int32)
    nbr = np.array([[1, -1, -1], [2, 3, 0], [-1, -1, -1], [-1, -1, -1]], dtype=np.int32)
    mate = np.array([1, 0, -1, -1], dtype=np.int32)
    out_xy, out_t, changed = _open_ears(xy, tris.copy(), nbr, mate)
    assert changed == 0 and (out_t == tris).all()


# ------------------------------------------------------------------ whole meshes


NACA = airfoil_in_farfield("0012")
NACA_SIZE = gradation(naca_loop("0012")[0].evaluate(np.linspace(0.0, 2.0 * np.pi, 400)), 0.03, 1.3, 2.5)
CASES = {
    "disk uniform": (circle(), 0.1),
    "disk graded": (circle(), lambda p: 0.03 + 0.1 * np.hypot(p[:, 0] - 0.5, p[:, 1])),
    "square with hole": (circles(centers=[(0.5, 0.5)], radii=[0.2], box=(0, 0, 1, 1)), 0.06),
    "square with square hole graded": (
        polygon([(0, 0), (1, 0), (1, 1), (0, 1)], holes=[[(0.3, 0.3), (0.3, 0.6), (0.6, 0.6), (0.6, 0.3)]]),
        lambda p: 0.03 + 0.05 * p[:, 0],
    ),
    "naca 0012 far field graded": (NACA, NACA_SIZE),
    "hole, segment, points": (
        polygon(
            [(0, 0), (2, 0), (2, 1), (0, 1)], holes=[[(1.4, 0.3), (1.4, 0.7), (1.7, 0.7), (1.7, 0.3)]],
            segments=[[(0.3, 0.2), (0.9, 0.8)]], points=[(0.5, 0.7), (1.2, 0.15)],
        ),
        0.08,
    ),
}


@pytest.mark.parametrize("name", list(CASES))
def test_all_quad_conforming_with_scaled_jacobian_above_0_2(name):
    dom, size = CASES[name]
    mesh = quadrangulate(dom, size, method="zhu")
    mesh.validate()
    _check_all_quad(mesh)
    assert _min_scaled_jacobian(mesh.points, mesh.cells["quad"]) > 0.2
    assert mesh.area() == pytest.approx(abs(dom.area()), rel=2e-2)


# ------------------------------------------------------------------ doors


def test_registry_entry_and_doors():
    m = QUAD_METHODS["zhu"]
    assert m.segments and m.points and m.regions and m.smooths and not m.reports_progress
    with pytest.raises(InputError, match="front"):
        pair_domain(circle(), 0.2, front="quads")
    with pytest.raises(InputError, match="progress"):
        quadrangulate(circle(), 0.2, method="zhu", progress=True)


def test_an_odd_loop_with_fixed_nodes_is_the_parity_error_naming_it():
    tri = polygon([(0, 0), (1, 0), (0, 1)])
    with pytest.raises(ParityError, match="outer loop"):
        pair_domain(tri, 2.0, front="pairs", fixed_boundary=True)
