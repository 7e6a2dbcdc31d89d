"""vn.Plan: the results of vertex_normals and corner_normals (bit for bit
in float64 but MWA on triangles within 1e-9 degrees, within 1e-4 degrees in
float32), the same for any thread count, positions read in place, and
errors at construction and per call."""

import re
import threading
import types

import numpy as np
import pytest

import vn
from conftest import grid

METHODS = ["mwe", "mwa", "mwselr", "mwaat", "mwelr", "mwrelr", "mewcsa", "smewcsa", "quadric", "jet", "adaptive"]
# the schemes vn.h's plan computes in float arithmetic on triangles
FAST = METHODS[:6]


def angles_deg(a, b):
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), (a * b).sum(axis=1)))


def like_vertex_normals(got, ref, method, faces):
    """float64 plan normals against vertex_normals': the same bits, but MWA
    on triangles (the plan's polynomial atan2) within 1e-9 degrees."""
    if method == "mwa" and not isinstance(faces, tuple) and np.shape(faces)[1] == 3:
        return angles_deg(got, ref).max() < 1e-9
    return np.array_equal(got, ref)


def meshes(torus, sphere_quads):
    return [("torus", torus), ("sphere of quads", sphere_quads), ("jittered grid", grid(60, jitter=0.003))]


@pytest.mark.parametrize("method", METHODS)
def test_float64_equals_vertex_normals_bit_for_bit(method, torus, sphere_quads):
    for label, (p, faces) in meshes(torus, sphere_quads):
        with vn.Plan(faces, len(p)) as plan:
            got = plan.normals(p, method)
            again = plan.normals(p, method)
        assert got.dtype == np.float64 and got.shape == p.shape, label
        assert like_vertex_normals(got, vn.vertex_normals(p, faces, method), method, faces), label
        assert np.array_equal(again, got), label


@pytest.mark.parametrize("method", METHODS)
def test_float32_within_1e4_degrees_of_double_on_the_same_positions(method, torus, sphere_quads):
    for label, (p, faces) in meshes(torus, sphere_quads):
        p32 = p.astype(np.float32)
        got = vn.Plan(faces, len(p)).normals(p32, method)
        assert got.dtype == np.float32 and got.shape == p.shape, label
        if method in FAST and not isinstance(faces, tuple) and faces.shape[1] == 3:
            # float arithmetic: compared with double from the same float32 positions
            ref = vn.vertex_normals(p32, faces, method)
            d = angles_deg(got, ref)
            assert d.max() < 1e-4 and (np.linalg.norm(ref, axis=1) > 0.5).all(), (label, d.max())
        else:  # vertex_normals' own double computation, rounded to float32
            assert np.array_equal(got, vn.vertex_normals(p32, faces, method, out=np.empty(p.shape, np.float32))), label


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_any_thread_count_gives_the_same_bits(dtype):
    p, f = grid(120, jitter=0.004)  # 28,322 triangles: several chunks a thread
    p = p.astype(dtype)
    for method in FAST + ["mewcsa"]:
        results = [vn.Plan(f, threads=t).normals(p, method) for t in (1, 2, 3, 7)]
        assert all(np.array_equal(r, results[0]) for r in results[1:]), method
        if dtype == np.float64:
            assert like_vertex_normals(results[0], vn.vertex_normals(p, f, method, threads=1), method, f), method


def recorded(monkeypatch, name):
    """Calls of vn_plan_<name>: (positions struct, vectors struct) of each."""
    lib = vn.library()._lib
    real, calls = getattr(lib, name), []

    def record(plan, pos, *rest):
        calls.append((pos._obj, rest[-2]._obj))
        return real(plan, pos, *rest)

    monkeypatch.setattr(lib, name, record)
    return calls


def test_positions_and_out_are_read_and_written_in_place(monkeypatch):
    p, f = grid(30, jitter=0.01)
    plan = vn.Plan(f)
    calls = recorded(monkeypatch, "vn_plan_normals")
    for dtype, code in ((np.float32, 0), (np.float64, 1)):
        a = np.ascontiguousarray(p, dtype=dtype)
        n = plan.normals(a, "mwa")
        pos, vec = calls[-1]
        assert (pos.data, pos.count, pos.stride, pos.type) == (a.ctypes.data, len(a), 3 * a.itemsize, code)
        assert (vec.data, vec.stride, vec.type) == (n.ctypes.data, 3 * a.itemsize, code)
    # an interleaved vertex buffer: position, normal and uv in 8 floats a vertex
    buffer = np.zeros((len(p), 8), dtype=np.float32)
    buffer[:, :3] = p
    n = plan.normals(buffer[:, :3], "mwa", out=buffer[:, 3:6])
    pos, vec = calls[-1]
    assert (pos.data, pos.stride, vec.data, vec.stride) == (buffer.ctypes.data, 32, buffer.ctypes.data + 12, 32)
    assert n.base is buffer and np.array_equal(buffer[:, 3:6], plan.normals(p.astype(np.float32), "mwa"))
    assert not buffer[:, 6:].any()
    # float64 written into float32 out, and float32 into float64
    out = np.empty((len(p), 3), dtype=np.float32)
    assert plan.normals(p, "mwe", out=out) is out
    assert np.array_equal(out, vn.vertex_normals(p, f, "mwe").astype(np.float32))


@pytest.mark.parametrize("method", METHODS)
def test_corner_normals_equal_vn_corner_normals(method, torus, sphere_quads):
    for (label, (p, faces)), crease in zip(meshes(torus, sphere_quads), (0.5, 0.3, None)):
        plan = vn.Plan(faces, len(p))
        got = plan.corner_normals(p, method, crease_angle=crease)
        ref = vn.corner_normals(p, faces, method, crease_angle=crease)
        assert got.dtype == np.float64 and np.array_equal(got, ref), label
        got32 = plan.corner_normals(p.astype(np.float32), method, crease_angle=crease)
        ref32 = vn.corner_normals(p.astype(np.float32), faces, method, crease_angle=crease)
        assert got32.dtype == np.float32 and np.array_equal(got32, ref32.astype(np.float32)), label


def test_corner_normals_sharp_edges_shapes_and_out():
    p, f = grid(12, jitter=0.01)
    sharp = np.random.default_rng(3).random(f.shape) < 0.2
    plan = vn.Plan(f)
    got = plan.corner_normals(p, "mwselr", sharp_edges=sharp)
    assert got.shape == f.shape + (3,)
    assert np.array_equal(got, vn.corner_normals(p, f, "mwselr", sharp_edges=sharp))
    assert np.array_equal(plan.corner_normals(p, "mwselr", sharp_edges=sharp.ravel().astype(np.uint8)), got)
    out = np.empty((f.size, 3), dtype=np.float32)
    assert plan.corner_normals(p, "mwselr", sharp_edges=sharp, out=out) is out
    assert np.array_equal(out, got.reshape(-1, 3).astype(np.float32))
    # polygons as (indices, offsets): one row per index
    idx, off = np.array([0, 1, 13, 12, 1, 2, 14, 13]), np.array([0, 4, 8])
    poly = vn.Plan((idx, off), len(p)).corner_normals(p, "mwa", crease_angle=0.2)
    assert poly.shape == (8, 3) and np.array_equal(poly, vn.corner_normals(p, (idx, off), "mwa", crease_angle=0.2))


def test_degenerate_faces_nan_positions_and_isolated_vertices():
    p, f = grid(20)
    p[5] = [np.nan, 0, 0]
    p[50] = [0, np.inf, 0]
    f = np.concatenate([f, [[7, 7, 8], [30, 31, 32]]])  # a repeated index; a line of three collinear points
    p = np.concatenate([p, np.zeros((2, 3))])  # two vertices no face uses
    for dtype in (np.float64, np.float32):
        plan = vn.Plan(f, len(p))
        for method in METHODS:
            n = plan.normals(p.astype(dtype), method)
            ref = vn.vertex_normals(p.astype(dtype), f, method)
            zero = np.linalg.norm(ref, axis=1) == 0
            assert np.isfinite(n).all() and (n[zero] == 0).all() and zero[[5, 50, -2, -1]].all(), method
            assert (np.linalg.norm(n[~zero], axis=1) > 0.999).all(), method


def test_a_mesh_object_gives_faces_and_vertex_count():
    p, f = grid(5)
    p = np.concatenate([p, [[9.0, 9.0, 9.0]]])  # the last vertex in no face
    mesh = types.SimpleNamespace(vertices=p, faces=f)
    plan = vn.Plan(mesh)
    assert (plan.vertex_count, plan.face_count) == (26, 32)
    assert like_vertex_normals(plan.normals(mesh), vn.vertex_normals(mesh), "mwa", f)
    assert vn.Plan(f).vertex_count == 25  # from the faces: the largest index + 1


def test_one_call_at_a_time_from_many_threads():
    p, f = grid(40, jitter=0.01)
    plan = vn.Plan(f, threads=2)
    frames = [p * (1 + 0.1 * k) + 0.01 * k for k in range(4)]
    refs = [vn.Plan(f).normals(q, "mwa") for q in frames]
    wrong = []

    def run(k):
        for _ in range(25):
            if not np.array_equal(plan.normals(frames[k], "mwa"), refs[k]):
                wrong.append(k)

    workers = [threading.Thread(target=run, args=(k,)) for k in range(4)]
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    assert wrong == []


def test_close_frees_once(monkeypatch):
    lib = vn.library()._lib
    real, freed = lib.vn_plan_destroy, []
    monkeypatch.setattr(lib, "vn_plan_destroy", lambda h: freed.append(h) or real(h))
    p, f = grid(4)
    with vn.Plan(f) as plan:
        assert not plan.closed
    assert plan.closed and len(freed) == 1
    plan.close()
    assert len(freed) == 1
    with pytest.raises(vn.Error, match="this plan is closed"):
        plan.normals(p)
    with pytest.raises(vn.Error, match="this plan is closed"):
        plan.corner_normals(p)
    plan = vn.Plan(f)
    del plan  # garbage: freed
    assert len(freed) == 2


@pytest.mark.parametrize("faces, kwargs, message", [
    ([[0, 1, 9]], dict(vertex_count=4), "faces: index 9 out of range for 4 vertices"),
    ([[0, 1, 2, 4]], dict(vertex_count=4), "faces: index 4 out of range for 4 vertices"),
    ([[0, 1, -1]], {}, "faces: index out of range (-1)"),
    ([[0.0, 1.0, 2.0]], {}, "faces must be integers, not float64"),
    ([0, 1, 2], {}, "faces must be an (m, k) integer array or (indices, offsets), not of shape (3,)"),
    (([0, 1, 2, 3], [0, 3]), {}, "face offsets must end at the number of corners (4)"),
    (([0, 1, 2, 3, 1, 2], [0, 4, 3, 6]), {}, "face offsets must not decrease"),
    ([[0, 1, 2]], dict(vertex_count=-1), "vertex count -1: must be an integer from 0 to 4294967295"),
    ([[0, 1, 2]], dict(vertex_count=2 ** 32), "vertex count 4294967296: must be an integer"),
])
def test_bad_faces_are_refused_at_construction(faces, kwargs, message):
    with pytest.raises(vn.Error, match=re.escape(message)):
        vn.Plan(faces, **kwargs)


def test_bad_calls_write_nothing():
    p, f = grid(4)
    plan = vn.Plan(f)
    out = np.full((16, 3), 3.0)
    for args, kwargs, message in [
            ((p[:15],), {}, "positions: 15 vertices; this plan's faces are over 16"),
            ((np.zeros((17, 3), dtype=np.float32),), {}, "positions: 17 vertices; this plan's faces are over 16"),
            ((p[:, :2],), {}, "positions must be an (n, 3) array, not of shape (16, 2)"),
            ((p, "mwq"), {}, "method 'mwq': unknown method"),
            ((p,), dict(out=np.zeros((15, 3))), "out must be a writable (16, 3) float32 or float64 array")]:
        with pytest.raises(vn.Error, match=re.escape(message)):
            plan.normals(*args, out=kwargs.get("out", out))
    assert (out == 3).all()
    with pytest.raises(vn.Error, match=re.escape("crease angle -0.1: must be 0 or more radians")):
        plan.corner_normals(p, crease_angle=-0.1)
    with pytest.raises(vn.Error, match=re.escape("one sharp-edge flag per corner is needed: 3 flags, 54 corners")):
        plan.corner_normals(p, sharp_edges=[1, 0, 0])


def test_binding_plan_face_strength_is_read_at_each_call():
    # The Blender add-on's Face Influence: strengths owned by the plan, changed in place.
    p, f = grid(6, jitter=0.02)
    lib = vn.library()
    strength = np.zeros(len(f), dtype=np.int32)
    strength[::3] = 16384
    given = np.zeros(len(f), dtype=np.int32)
    plan = lib.plan(f, None, len(p), face_strength=given)
    given[:] = 16384  # the plan's own copy: not this array
    assert not plan.face_strength.any()
    plan.face_strength[:] = strength
    got = plan.corner_normals(p, "mwa", dtype=np.float32)[0]
    ref = lib.corner_normals(p, f, None, "mwa", dtype=np.float32, face_strength=strength)[0]
    assert np.array_equal(got, ref)
    assert not np.array_equal(got, lib.corner_normals(p, f, None, "mwa", dtype=np.float32)[0])
    with pytest.raises(vn.Error, match=re.escape("one face strength per face is needed: 2 strengths, 50 faces")):
        lib.plan(f, None, len(p), face_strength=[0, 1])
