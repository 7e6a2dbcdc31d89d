"""Meshes of other libraries: any object with .vertices and .faces, the
real Open3D and meshio of Debian."""

import math
import types

import numpy as np
import pytest

import vn
from conftest import grid


def test_object_with_vertices_and_faces(torus):
    p, f = torus
    mesh = types.SimpleNamespace(vertices=p, faces=f)  # trimesh's attributes
    assert np.array_equal(vn.vertex_normals(mesh, method="mwelr"), vn.vertex_normals(p, f, "mwelr"))
    assert np.array_equal(vn.corner_normals(mesh, crease_angle=0.4), vn.corner_normals(p, f, crease_angle=0.4))
    assert np.array_equal(vn.weld(mesh), vn.weld(p))


def test_open3d(torus):
    o3d = pytest.importorskip("open3d")
    p, f = torus
    mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(p), o3d.utility.Vector3iVector(f))
    expected = vn.vertex_normals(p, f, "mwselr")
    assert np.array_equal(vn.vertex_normals(mesh, method="mwselr"), expected)
    assert vn.open3d.set_normals(mesh, "mwselr") is mesh and mesh.has_vertex_normals()
    assert np.array_equal(np.asarray(mesh.vertex_normals), expected)
    # Open3D's own normals are area weighted: vn's MWAAT
    theirs = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(p), o3d.utility.Vector3iVector(f))
    theirs.compute_vertex_normals()
    a, b = np.asarray(theirs.vertex_normals), vn.vertex_normals(p, f, "mwaat")
    angles = np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), (a * b).sum(axis=1)))
    assert angles.max() < 1e-5, angles.max()
    sphere = o3d.geometry.TriangleMesh.create_sphere(radius=2.0, resolution=30)
    n = np.asarray(vn.open3d.set_normals(sphere, "mwa", threads=2).vertex_normals)
    v = np.asarray(sphere.vertices)
    assert np.allclose(n, v / 2, atol=0.01)


def test_meshio(tmp_path, sphere_quads):
    meshio = pytest.importorskip("meshio")
    p, (idx, off) = sphere_quads
    sizes = np.diff(off)
    tris = np.stack([idx[o:o + 3] for o in off[:-1][sizes == 3]])
    quads = np.stack([idx[o:o + 4] for o in off[:-1][sizes == 4]])
    mesh = meshio.Mesh(p, [("triangle", tris), ("quad", quads), ("line", np.array([[0, 1]]))])
    # the same faces in meshio's order: triangles first, then quads
    faces = (np.concatenate([tris.ravel(), quads.ravel()]),
             np.concatenate([[0], np.cumsum([3] * len(tris) + [4] * len(quads))]))
    for method in ("mwa", "mwaat"):
        assert np.array_equal(vn.vertex_normals(mesh, method=method), vn.vertex_normals(p, faces, method))
    assert np.array_equal(vn.corner_normals(mesh, crease_angle=math.radians(30)),
                          vn.corner_normals(p, faces, crease_angle=math.radians(30)))
    # a file written and read back by meshio
    q, f = grid(12)
    meshio.write(tmp_path / "g.obj", meshio.Mesh(q, [("triangle", f)]))
    back = meshio.read(tmp_path / "g.obj")
    assert np.array_equal(vn.vertex_normals(back), vn.vertex_normals(np.asarray(back.points), f))
    with pytest.raises(vn.Error, match="no triangle, quad or polygon cells"):
        vn.vertex_normals(meshio.Mesh(p, [("line", np.array([[0, 1]]))]))
