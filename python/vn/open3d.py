"""Open3D helpers: vn's normals written into an ``open3d.geometry.TriangleMesh``.

Open3D itself is not imported here: the mesh brings its own types.
"""

import numpy as np

from . import vertex_normals


def set_normals(mesh, method="mwa", *, threads=0):
    """Computes a TriangleMesh's vertex normals with vn and stores them.

    Replaces ``mesh.compute_vertex_normals()`` (area weighted, single
    precision) with any of vn's schemes, computed in double precision.

    Parameters
    ----------
    mesh : open3d.geometry.TriangleMesh
    method : str, default "mwa"
        A name from `vn.methods`.
    threads : int, default 0
        As for `vn.vertex_normals`.

    Returns
    -------
    open3d.geometry.TriangleMesh
        `mesh`, whose ``vertex_normals`` now hold the result.

    Examples
    --------
    >>> mesh = open3d.io.read_triangle_mesh("bunny.ply")
    >>> vn.open3d.set_normals(mesh, "mwselr").has_vertex_normals()
    True
    """
    normals = vertex_normals(np.asarray(mesh.vertices), np.asarray(mesh.triangles), method, threads=threads)
    mesh.vertex_normals = type(mesh.vertices)(normals)
    return mesh
