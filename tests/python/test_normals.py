"""vn.vertex_normals, corner_normals, weld and methods: hand-computed
results, vn's C results bit for bit, every input layout, and errors."""

import ctypes
import math
import re
import threading

import numpy as np
import pytest

import vn
from conftest import c_normals, grid

METHODS = ["mwe", "mwa", "mwselr", "mwaat", "mwelr", "mwrelr", "mewcsa", "smewcsa", "quadric", "jet", "adaptive"]
# A tetrahedron's corner at the origin: three right-angled faces, outward.
TETRA_P = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.]])
TETRA_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


def test_methods_listed_in_vnconvert_order():
    ms = vn.methods()
    assert [m.name for m in ms] == METHODS
    assert ms[1].description == "mean weighted by angle: face normals times the corner angle"
    assert ms[1].reference == "Thurmer & Wuthrich 1998; Jin et al. 2005 eq. 2"
    assert all(m.description and m.reference for m in ms)


def test_method_given_as_an_entry_of_methods():
    # vn.methods() lists Method tuples: one passes as its name.
    for m in vn.methods():
        np.testing.assert_array_equal(vn.vertex_normals(TETRA_P, TETRA_F, m),
                                      vn.vertex_normals(TETRA_P, TETRA_F, m.name))


@pytest.mark.parametrize("method", METHODS)
def test_tetrahedron_corner_by_hand(method):
    # Three faces of equal angle (90 degrees), area and edges at the origin:
    # every scheme gives the mean of their normals -x, -y, -z.
    n = vn.vertex_normals(TETRA_P, TETRA_F, method)
    np.testing.assert_allclose(n[0], -np.ones(3) / math.sqrt(3), rtol=0, atol=1e-15)


def test_tetrahedron_vertex_x_by_hand():
    # At (1, 0, 0): faces -z and -y with 45-degree corners, the slanted face
    # (1, 1, 1)/sqrt(3) with a 60-degree corner.
    s = 1 / math.sqrt(3)
    mwe = unit([s, s - 1, s - 1])
    mwa = unit([math.pi / 3 * s, math.pi / 3 * s - math.pi / 4, math.pi / 3 * s - math.pi / 4])
    np.testing.assert_allclose(vn.vertex_normals(TETRA_P, TETRA_F, "mwe")[1], mwe, rtol=0, atol=1e-15)
    np.testing.assert_allclose(vn.vertex_normals(TETRA_P, TETRA_F, "MWA")[1], mwa, rtol=0, atol=1e-15)
    assert np.allclose(mwe, [0.69475, -0.50859, -0.50859], atol=1e-5)


def test_quad_by_hand():
    p = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]], dtype=np.float32)
    # (not MEWCSA: the cotangent weights do not give a normal on a boundary)
    for faces in ([[0, 1, 2, 3]], (np.array([0, 1, 2, 3]), np.array([0, 4])), [[0, 1, 2], [0, 2, 3]]):
        for method in [m for m in METHODS if m != "mewcsa"]:
            assert vn.vertex_normals(p, faces, method).tolist() == [[0, 0, 1]] * 4
    # a quad is upside down when its corners run clockwise
    assert vn.corner_normals(p, [[3, 2, 1, 0]]).tolist() == [[[0, 0, -1]] * 4]


@pytest.mark.parametrize("method", METHODS)
def test_vertex_normals_match_c_bit_for_bit(method, torus, sphere_quads):
    for p, faces in (torus, sphere_quads, grid(60, jitter=0.003)):
        got = vn.vertex_normals(p, faces, method)
        assert got.dtype == np.float64 and got.shape == p.shape
        assert np.array_equal(got, c_normals("vertex", method, p, faces))
        # float32 positions: C sees the same values widened to double
        p32 = p.astype(np.float32)
        assert np.array_equal(vn.vertex_normals(p32, faces, method), c_normals("vertex", method, p32, faces))


@pytest.mark.parametrize("method", METHODS)
def test_corner_normals_match_c_bit_for_bit(method, torus, sphere_quads):
    for (p, faces), crease in ((torus, 0.5), (sphere_quads, 0.3), (grid(40, jitter=0.01), None)):
        got = vn.corner_normals(p, faces, method, crease_angle=crease)
        flat = got.reshape(-1, 3)
        assert np.array_equal(flat, c_normals("corner", method, p, faces, math.pi if crease is None else crease))
        if not isinstance(faces, tuple):
            assert got.shape == (len(faces), 3, 3)


def test_sphere_as_quads_array_and_polygons_agree(sphere_quads):
    p, (idx, off) = sphere_quads
    quads = np.flatnonzero(np.diff(off) == 4)
    rows = np.stack([idx[off[f]:off[f] + 4] for f in quads])
    n = vn.vertex_normals(p, rows)
    m = vn.vertex_normals(p, (np.ravel(rows), np.arange(len(rows) + 1) * 4))
    assert np.array_equal(n, m)
    assert np.array_equal(vn.corner_normals(p, rows).reshape(-1, 3),
                          vn.corner_normals(p, (np.ravel(rows), np.arange(len(rows) + 1) * 4)))


def test_faces_of_mixed_sizes_one_by_one(sphere_quads):
    # A list of lists (triangles at the poles, quads elsewhere) is read as
    # (indices, offsets): the same bits.
    p, (idx, off) = sphere_quads
    assert len(set(np.diff(off))) == 2
    faces = [idx[off[f]:off[f + 1]].tolist() for f in range(len(off) - 1)]
    assert np.array_equal(vn.vertex_normals(p, faces, method="jet"), vn.vertex_normals(p, (idx, off), method="jet"))
    assert np.array_equal(vn.corner_normals(p, faces, crease_angle=0.5), vn.corner_normals(p, (idx, off), crease_angle=0.5))


def test_input_layouts_all_give_the_same_bits(torus):
    p, f = torus
    ref = vn.vertex_normals(p, f)
    wide = np.zeros((len(p), 7))
    wide[:, 2:5] = p
    strided = wide[:, 2:5]  # rows 56 bytes apart: read in place
    assert not strided.flags.c_contiguous
    fortran = np.asfortranarray(p)
    rev = p[::-1]
    layouts = [strided, fortran, p.tolist(), p.astype(np.float64).copy(order="C")]
    for q in layouts:
        assert np.array_equal(vn.vertex_normals(q, f), ref)
    assert np.array_equal(vn.vertex_normals(rev, len(p) - 1 - f)[::-1], ref)
    for dt in (np.int8 if len(p) < 128 else np.int16, np.int32, np.int64, np.uint16, np.uint32, np.uint64, np.intp):
        assert np.array_equal(vn.vertex_normals(p, f.astype(dt)), ref), dt
    assert np.array_equal(vn.vertex_normals(p, np.asfortranarray(f)), ref)
    assert np.array_equal(vn.vertex_normals(p, f.tolist()), ref)
    # integer positions are converted to float64
    assert vn.vertex_normals(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), [[0, 1, 2]]).tolist() == [[0, 0, 1]] * 3


def test_out(torus):
    p, f = torus
    ref = vn.vertex_normals(p, f, "mwselr")
    out = np.full((len(p), 3), 7.0)
    assert vn.vertex_normals(p, f, "mwselr", out=out) is out and np.array_equal(out, ref)
    out32 = np.empty((len(p), 3), dtype=np.float32)
    vn.vertex_normals(p, f, "mwselr", out=out32)
    assert np.array_equal(out32, ref.astype(np.float32))
    wide = np.full((len(p), 6), 5.0)
    vn.vertex_normals(p, f, "mwselr", out=wide[:, 3:])
    assert np.array_equal(wide[:, 3:], ref) and (wide[:, :3] == 5).all()
    for bad in (np.empty((len(p), 3), dtype=np.int32), np.empty((len(p) - 1, 3)), np.empty((len(p), 3))[:, ::-1],
                np.empty((len(p), 4))):
        with pytest.raises(vn.Error, match="out must be a writable"):
            vn.vertex_normals(p, f, out=bad)
    ro = np.zeros((len(p), 3))
    ro.flags.writeable = False
    with pytest.raises(vn.Error, match="out must be a writable"):
        vn.vertex_normals(p, f, out=ro)


def test_float64_contiguous_positions_are_not_copied(monkeypatch, torus):
    p, f = torus
    seen = []
    real = vn._binding.Library._positions
    monkeypatch.setattr(vn._binding.Library, "_positions",
                        staticmethod(lambda co: seen.append(real(co)) or seen[-1]))
    vn.vertex_normals(p, f)
    assert seen[0][0] is p or np.shares_memory(seen[0][0], p)
    wide = np.zeros((len(p), 4))
    vn.vertex_normals(wide[:, :3], f)
    assert np.shares_memory(seen[1][0], wide) and seen[1][1].stride == 32


def test_int32_faces_are_not_copied(monkeypatch, torus):
    """Open3D's int32 triangles are read in place (after the range check);
    int64 is copied once to the library's uint32."""
    p, f = torus
    seen = []
    real = vn._binding._indices
    monkeypatch.setattr(vn._binding, "_indices", lambda a, what: seen.append(real(a, what)) or seen[-1])
    f32, f64 = f.astype(np.int32), f.astype(np.int64)
    assert np.array_equal(vn.vertex_normals(p, f32), vn.vertex_normals(p, f64))
    assert np.shares_memory(seen[0], f32) and seen[0].dtype == np.uint32
    assert not np.shares_memory(seen[1], f64)


def test_workspace_kept_per_thread(torus, sphere_quads):
    """A thread's work memory is kept from call to call (no allocation in
    the library) and grown for a larger mesh; results are unchanged."""
    lib = vn.library()
    p, f = torus
    first = vn.vertex_normals(p, f, "mwa", threads=1)
    buffer = lib._workspaces.buffer
    assert buffer.size >= lib._lib.vn_workspace_size(len(p), ctypes.byref(lib._options(1)))
    assert np.array_equal(vn.vertex_normals(p, f, "mwa", threads=1), first)
    assert lib._workspaces.buffer is buffer
    big = grid(200)
    vn.vertex_normals(*big, threads=1)
    assert lib._workspaces.buffer is not buffer and lib._workspaces.buffer.size > buffer.size
    assert np.array_equal(vn.vertex_normals(p, f, "mwa", threads=1), first)
    other = {}
    t = threading.Thread(target=lambda: other.update(n=vn.vertex_normals(p, f, "mwa", threads=1),
                                                     b=lib._workspaces.buffer))
    t.start()
    t.join()
    assert np.array_equal(other["n"], first) and other["b"] is not lib._workspaces.buffer


def test_threads_give_identical_results():
    p, f = grid(300, jitter=0.001)  # 90000 vertices: several threads' worth
    for method in ("mwa", "mewcsa"):
        one = vn.vertex_normals(p, f, method, threads=1)
        for t in (2, 3, 0):
            assert np.array_equal(vn.vertex_normals(p, f, method, threads=t), one)
        c1 = vn.corner_normals(p, f, method, crease_angle=0.2, threads=1)
        assert np.array_equal(vn.corner_normals(p, f, method, crease_angle=0.2, threads=2), c1)


def test_sharp_edges_split_corners():
    # two triangles folded 90 degrees along edge 0-2
    p = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1.]])
    f = np.array([[0, 1, 2], [0, 2, 3]])
    smooth = vn.corner_normals(p, f, "mwe")
    np.testing.assert_allclose(smooth[0, 0], [0.5, -0.5, math.sqrt(0.5)], atol=1e-15)
    sharp = np.zeros((2, 3), dtype=bool)
    sharp[0, 2] = True  # corner 2 of face 0: its edge 2 -> 0
    split = vn.corner_normals(p, f, "mwe", sharp_edges=sharp)
    assert split[0].tolist() == [[0, 0, 1]] * 3
    np.testing.assert_allclose(split[1], [unit([1, -1, 0])] * 3, atol=1e-15)
    assert np.array_equal(vn.corner_normals(p, f, "mwe", sharp_edges=sharp.ravel().astype(np.uint8)), split)
    assert np.array_equal(vn.corner_normals(p, f, "mwe", crease_angle=math.radians(89)), split)
    assert np.array_equal(vn.corner_normals(p, f, "mwe", crease_angle=math.radians(91)), smooth)


def test_weld():
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 0, 0], [1, 1e-9, 0], [np.nan, 0, 0], [np.nan, 0, 0], [-0.0, 0, 0]])
    assert vn.weld(p).tolist() == [0, 1, 0, 3, 4, 5, 0]
    assert vn.weld(p, 1e-6).tolist() == [0, 1, 0, 1, 4, 5, 0]
    assert vn.weld(p.astype(np.float32)).dtype == np.uint32
    for eps in (-1, np.nan, np.inf):
        with pytest.raises(vn.Error, match="weld epsilon"):
            vn.weld(p, eps)


def test_nan_and_inf_never_give_nan():
    p, f = grid(20)
    p[5] = [np.nan, 0, 0]
    p[50] = [0, np.inf, 0]
    for method in METHODS:
        n = vn.vertex_normals(p, f, method)
        assert np.isfinite(n).all()
        assert n[5].tolist() == [0, 0, 0] and n[50].tolist() == [0, 0, 0]
        lengths = np.linalg.norm(n, axis=1)
        assert ((np.abs(lengths - 1) < 1e-12) | (lengths == 0)).all()
        c = vn.corner_normals(p, f, method, crease_angle=0.5)
        assert np.isfinite(c).all()
    assert np.isfinite(vn.vertex_normals(np.full((3, 3), np.nan), [[0, 1, 2]])).all()


def test_empty_meshes():
    assert vn.vertex_normals(np.zeros((0, 3)), np.zeros((0, 3), dtype=int)).shape == (0, 3)
    assert vn.vertex_normals(np.ones((2, 3)), np.zeros((0, 3), dtype=int)).tolist() == [[0, 0, 0]] * 2
    assert vn.corner_normals(np.ones((2, 3)), np.zeros((0, 4), dtype=int)).shape == (0, 4, 3)
    assert vn.weld(np.zeros((0, 3))).shape == (0,)


@pytest.mark.parametrize("args, kwargs, message", [
    ((TETRA_P, [[0, 1, 4]]), {}, "vn_triangle_normals: index out of range"),
    ((TETRA_P, [[0, 1, 2, 4]]), {}, "vn_polygon_normals: index out of range"),
    ((TETRA_P, [[0, 1, -1]]), {}, "faces: index out of range (-1)"),
    ((TETRA_P, np.array([[0, 1, 2 ** 32]])), {}, "faces: index out of range (4294967296)"),
    ((TETRA_P, np.array([[0, 1, -2]], dtype=np.int32)), {}, "faces: index out of range (-2)"),  # read in place else
    ((TETRA_P, np.array([[0, 1, 2 ** 63]], dtype=np.uint64)), {}, "faces: index out of range (9223372036854775808)"),
    ((TETRA_P, np.array([[0, -2 ** 63, 1]], dtype=np.int64)), {}, "faces: index out of range (-9223372036854775808)"),
    ((TETRA_P, [[0, 1, 2]], "mwq"), {}, "method 'mwq': unknown method"),
    ((TETRA_P, [[0, 1, 2]], 11), {}, "method 11: unknown method"),
    ((TETRA_P, [[0, 1, 2]], (1, 2)), {}, "method (1, 2): unknown method"),
    ((TETRA_P[:, :2], [[0, 1, 2]]), {}, "positions must be an (n, 3) array, not of shape (4, 2)"),
    ((TETRA_P.ravel(), [[0, 1, 2]]), {}, "positions must be an (n, 3) array, not of shape (12,)"),
    ((np.array([["a", "b", "c"]]), [[0, 0, 0]]), {}, "positions must be numbers, not <U1"),
    ((TETRA_P, [0, 1, 2]), {}, "faces must be an (m, k) integer array or (indices, offsets), not of shape (3,)"),
    ((TETRA_P, np.zeros((1, 3, 1), dtype=int)), {}, "not of shape (1, 3, 1)"),
    ((TETRA_P, [[0.0, 1.0, 2.0]]), {}, "faces must be integers, not float64"),
    ((TETRA_P, [[0, 1, 2], [0, 1, 2, 3.5]]), {}, "faces must be integers, not float64"),
    ((TETRA_P, [[0, 1, 2], [[0, 1], [2, 3]]]), {}, "faces of mixed sizes must each be a sequence of corner indices"),
    ((TETRA_P, [[0, 1, 2], [0, 1, 5, 3]]), {}, "index out of range"),
    ((TETRA_P, ([0, 1, 2, 3], [0, 3])), {}, "face offsets must end at the number of corners (4)"),
    ((TETRA_P, ([0, 1, 2, 3, 1, 2], [0, 4, 3, 6])), {}, "vn_polygon_normals: invalid argument"),
    ((TETRA_P,), {}, "faces are missing"),
])
def test_errors_carry_the_message(args, kwargs, message):
    with pytest.raises(vn.Error, match=re.escape(message)):
        vn.vertex_normals(*args, **kwargs)


def test_error_is_a_value_error_and_nothing_is_written():
    out = np.full((4, 3), 3.0)
    with pytest.raises(ValueError):
        vn.vertex_normals(TETRA_P, [[0, 1, 2], [0, 1, 9]], out=out)
    assert (out == 3).all()


def test_corner_errors():
    with pytest.raises(vn.Error, match=re.escape("crease angle -0.1: must be 0 or more radians")):
        vn.corner_normals(TETRA_P, TETRA_F, crease_angle=-0.1)
    with pytest.raises(vn.Error, match="crease angle nan"):
        vn.corner_normals(TETRA_P, TETRA_F, crease_angle=float("nan"))
    with pytest.raises(vn.Error, match=re.escape("one sharp-edge flag per corner is needed: 3 flags, 12 corners")):
        vn.corner_normals(TETRA_P, TETRA_F, sharp_edges=[1, 0, 0])
    with pytest.raises(vn.Error, match="vn_corner_normals: index out of range"):
        vn.corner_normals(TETRA_P, [[0, 1, 5]])
