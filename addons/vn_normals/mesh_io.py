"""Mesh data in and out of Blender with foreach_get/foreach_set and numpy.

Every difference between Blender versions is here: 3.4-4.0 store custom
normals only with use_auto_smooth and give corner normals through
calc_normals_split() and loop.normal; 4.1+ have mesh.corner_normals and the
sharp_edge / sharp_face attributes (still reachable as use_edge_sharp /
use_smooth, which this module uses in every version).
"""

import math

import bpy
import numpy as np

HAS_CORNER_NORMALS = bpy.app.version >= (4, 1, 0)


def _get(seq, attr, n, dtype, width=1):
    a = np.empty(n * width, dtype=dtype)
    if n:
        seq.foreach_get(attr, a)
    return a.reshape(-1, width) if width > 1 else a


class MeshArrays:
    """The arrays vn needs, read from a Mesh (object mode data)."""

    def __init__(self, mesh):
        nv, nl, ne, nf = len(mesh.vertices), len(mesh.loops), len(mesh.edges), len(mesh.polygons)
        self.co = _get(mesh.vertices, "co", nv, np.float32, 3)
        self.corner_vert = _get(mesh.loops, "vertex_index", nl, np.int32).astype(np.uint32)
        self.corner_edge = _get(mesh.loops, "edge_index", nl, np.int32)
        start = _get(mesh.polygons, "loop_start", nf, np.int32).astype(np.int64)
        total = _get(mesh.polygons, "loop_total", nf, np.int32).astype(np.int64)
        self.face_smooth = _get(mesh.polygons, "use_smooth", nf, bool)
        self.face_select = _get(mesh.polygons, "select", nf, bool)
        self.edge_sharp = _get(mesh.edges, "use_edge_sharp", ne, bool)
        self.edge_count = ne
        offsets = np.zeros(nf + 1, dtype=np.int64)
        np.cumsum(total, out=offsets[1:])
        # order[k]: the loop that is corner k of vn's face-ordered corner list
        # (the identity when faces store their loops in order, as usual).
        if nf == 0 or (np.array_equal(start, offsets[:-1]) and offsets[-1] == nl):
            self.order = None
        else:
            self.order = np.repeat(start - offsets[:-1], total) + np.arange(offsets[-1])
            self.corner_vert = self.corner_vert[self.order]
            self.corner_edge = self.corner_edge[self.order]
        self.face_offsets = offsets.astype(np.uint32)
        self.face_of_corner = np.repeat(np.arange(nf), total)
        # prev_corner[k]: the corner before k in its face
        prev = np.arange(offsets[-1]) - 1
        nonempty = total > 0
        prev[offsets[:-1][nonempty]] = offsets[1:][nonempty] - 1
        self.prev_corner = prev

    def to_loops(self, per_corner):
        """Per-corner rows in Blender's loop order."""
        if self.order is None:
            return per_corner
        out = np.empty_like(per_corner)
        out[self.order] = per_corner
        return out

    def from_loops(self, per_loop):
        return per_loop if self.order is None else per_loop[self.order]

    def sharp_corner_flags(self, keep_sharp):
        """vn's sharp_edges: a corner's edge is sharp when marked sharp or when
        either face is flat-shaded (Blender's own rule). None when nothing is."""
        if not keep_sharp:
            return None
        flat_face = ~self.face_smooth
        flags = self.edge_sharp[self.corner_edge] | flat_face[self.face_of_corner]
        return flags.astype(np.uint8) if flags.any() else None

    def edges_where_normals_differ(self, normals, tolerance=1e-6):
        """Boolean per edge: the two corners meeting at one of its ends from
        its two sides have different normals (so Blender must split there)."""
        nc = self.corner_vert.size
        corners = np.concatenate([np.arange(nc), np.arange(nc)])
        edges = np.concatenate([self.corner_edge, self.corner_edge[self.prev_corner]]).astype(np.int64)
        verts = np.concatenate([self.corner_vert, self.corner_vert]).astype(np.int64)
        key = edges * (int(verts.max(initial=0)) + 1) + verts
        s = np.argsort(key, kind="stable")
        key, corners, edges = key[s], corners[s], edges[s]
        same = key[:-1] == key[1:]
        a, b = normals[corners[:-1][same]], normals[corners[1:][same]]
        differ = np.abs(a - b).max(axis=1) > tolerance
        out = np.zeros(self.edge_count, dtype=bool)
        out[edges[:-1][same][differ]] = True
        return out


def corner_normals(mesh):
    """Blender's current per-loop normals, float32 (n, 3), in loop order."""
    nl = len(mesh.loops)
    a = np.empty(nl * 3, dtype=np.float32)
    if HAS_CORNER_NORMALS:
        if nl:
            mesh.corner_normals.foreach_get("vector", a)
    else:
        mesh.calc_normals_split()
        if nl:
            mesh.loops.foreach_get("normal", a)
    return a.reshape(-1, 3)


def auto_smooth_angle(mesh):
    """The angle above which Blender 3.4-4.0's Auto Smooth splits the normals
    (pi when it is off, and in 4.1+ where sharp edges carry it)."""
    return mesh.auto_smooth_angle if not HAS_CORNER_NORMALS and mesh.use_auto_smooth else math.pi


def mark_sharp(mesh, edge_mask):
    """Marks the edges in edge_mask sharp (keeping those already marked)."""
    if not edge_mask.any():
        return
    cur = _get(mesh.edges, "use_edge_sharp", len(mesh.edges), bool)
    mesh.edges.foreach_set("use_edge_sharp", cur | edge_mask)


def set_custom_normals(mesh, loop_normals):
    """Stores per-loop custom split normals (rows in loop order; a zero row
    keeps Blender's automatic normal there)."""
    if not HAS_CORNER_NORMALS:
        # 3.4-4.0: custom normals need auto smooth; its angle would split the
        # fans further, which a fan of equal normals does not mind.
        if not mesh.use_auto_smooth:
            mesh.use_auto_smooth = True
            mesh.auto_smooth_angle = math.pi
    mesh.normals_split_custom_set(np.ascontiguousarray(loop_normals, dtype=np.float32))
    mesh.update()
