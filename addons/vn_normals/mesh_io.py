"""Mesh data in and out of Blender with foreach_get/foreach_set and numpy.

Every difference between Blender versions is here: 3.4-4.0 store custom
normals only with use_auto_smooth and give corner normals through
calc_normals_split() and loop.normal; 4.1+ have mesh.corner_normals and
store positions, corners and sharp flags as attributes, whose foreach_get
is a plain copy (the MeshVertex/MeshLoop properties call a getter per item).
Before 4.1 (and in Edit Mode) the collections are read, unsigned properties
into uint32 arrays (into int32, Blender converts item by item: 10x slower).
Arrays are read in the dtypes the library takes, so nothing is converted.
"""

import functools
import math

import bpy
import numpy as np

HAS_CORNER_NORMALS = bpy.app.version >= (4, 1, 0)
# The face attribute Bevel's Harden Normals and Set Face Strength write and
# the Weighted Normal modifier's Face Influence reads (3.4 to 4.3):
# -16384 weak, 0 medium, 16384 strong.
FACE_STRENGTH = "__mod_weightednormals_faceweight"


def _get(seq, attr, n, dtype, width=1):
    a = np.empty(n * width, dtype=dtype)
    if n:
        seq.foreach_get(attr, a)
    return a.reshape(-1, width) if width > 1 else a


def _attribute(mesh, name, prop, n, dtype, width=1):
    """An attribute's values, or None when the mesh has no such attribute."""
    attr = mesh.attributes.get(name)
    return None if attr is None else _get(attr.data, prop, n, dtype, width)


class MeshArrays:
    """The arrays vn needs, read from a Mesh (object mode data). Those only
    some options need (corner_edge, face_of_corner, prev_corner) are read or
    computed on first use."""

    def __init__(self, mesh):
        self.mesh = mesh
        nv, nl, nf = len(mesh.vertices), len(mesh.loops), len(mesh.polygons)
        self.edge_count = len(mesh.edges)
        offsets = np.empty(nf + 1, dtype=np.uint32)
        if nf:
            mesh.polygons.foreach_get("loop_start", offsets[:-1])
        offsets[-1] = nl
        self.order = None
        # In Edit Mode mesh.attributes are the BMesh's: read the Mesh's
        # collections then.
        self.use_attributes = HAS_CORNER_NORMALS and not mesh.is_editmode
        if self.use_attributes:
            # faces are offsets into the corner arrays: in order, no gaps
            self.co = _attribute(mesh, "position", "vector", nv, np.float32, 3)
            self.corner_vert = _attribute(mesh, ".corner_vert", "value", nl, np.int32).view(np.uint32)
            self.face_size = np.diff(offsets)
            sharp_face = _attribute(mesh, "sharp_face", "value", nf, bool)
            self.face_smooth = np.ones(nf, dtype=bool) if sharp_face is None else ~sharp_face
            edge_sharp = _attribute(mesh, "sharp_edge", "value", self.edge_count, bool)
            self.edge_sharp = np.zeros(self.edge_count, dtype=bool) if edge_sharp is None else edge_sharp
        else:
            self.co = _get(mesh.vertices, "co", nv, np.float32, 3)
            self.corner_vert = _get(mesh.loops, "vertex_index", nl, np.uint32)
            start = offsets[:-1].copy()
            self.face_size = _get(mesh.polygons, "loop_total", nf, np.uint32)
            np.cumsum(self.face_size, out=offsets[1:])
            offsets[0] = 0
            # order[k]: the loop that is corner k of vn's face-ordered corner
            # list (None: the identity, faces storing their loops in order)
            if nf and not (np.array_equal(start, offsets[:-1]) and offsets[-1] == nl):
                self.order = (np.repeat(start.astype(np.int64) - offsets[:-1], self.face_size)
                              + np.arange(offsets[-1]))
                self.corner_vert = self.corner_vert[self.order]
            self.face_smooth = _get(mesh.polygons, "use_smooth", nf, bool)
            self.edge_sharp = _get(mesh.edges, "use_edge_sharp", self.edge_count, bool)
        self.face_offsets = offsets

    @functools.cached_property
    def corner_edge(self):
        nl = self.corner_vert.size
        if self.use_attributes:
            return _attribute(self.mesh, ".corner_edge", "value", nl, np.int32)
        corner_edge = _get(self.mesh.loops, "edge_index", nl, np.uint32)
        return corner_edge if self.order is None else corner_edge[self.order]

    @functools.cached_property
    def face_strength(self):
        """Blender's face strengths (int32 per face), or None when the mesh has none."""
        attr = self.mesh.attributes.get(FACE_STRENGTH)
        if attr is None or attr.domain != "FACE" or attr.data_type != "INT":
            return None
        return _get(attr.data, "value", len(self.face_size), np.int32)

    @functools.cached_property
    def face_select(self):
        return _get(self.mesh.polygons, "select", len(self.face_size), bool)

    @functools.cached_property
    def face_of_corner(self):
        return np.repeat(np.arange(self.face_size.size, dtype=np.uint32), self.face_size)

    @functools.cached_property
    def prev_corner(self):
        """prev_corner[k]: the corner before k in its face."""
        offsets = self.face_offsets.astype(np.int64)
        prev = np.arange(-1, offsets[-1] - 1)
        nonempty = self.face_size > 0
        prev[offsets[:-1][nonempty]] = offsets[1:][nonempty] - 1
        return prev

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
        if not flat_face.any() and not self.edge_sharp.any():
            return None  # corner_edge is not even read
        flags = np.repeat(flat_face, self.face_size)
        if self.edge_sharp.any():
            flags |= self.edge_sharp[self.corner_edge]
        return flags

    def vertex_normals(self, normals):
        """One row per vertex when every corner of each vertex has exactly the
        same normal (then Blender can store them per vertex), else None."""
        rows = np.ascontiguousarray(normals, dtype=np.float32)
        row = np.dtype((np.void, 12))  # a float32 triple moved as one item
        per_vertex = np.zeros(self.co.shape[0], dtype=row)
        per_vertex[self.corner_vert] = rows.view(row).ravel()
        if not np.array_equal(per_vertex[self.corner_vert].view(np.float32).reshape(-1, 3), rows):
            return None
        return per_vertex.view(np.float32).reshape(-1, 3)

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


def vertex_group_members(mesh, index):
    """Per vertex: whether it is in vertex group `index`, whatever its weight
    (0 too). Blender has no bulk read of vertex groups: a Python loop, 1.3 s
    a million vertices in 3.4, 0.5 s in 4.3."""
    return np.fromiter((any(g.group == index for g in v.groups) for v in mesh.vertices), bool,
                       len(mesh.vertices))


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


def set_custom_normals(mesh, arrays, normals, has_zero_rows):
    """Stores per-corner custom split normals (rows in vn's corner order; a
    zero row keeps Blender's automatic normal there). Returns "vertex" when
    they were stored per vertex, "corner" otherwise.

    Per vertex is Blender's cheaper path (no second pass to split fans), and
    exact when no vertex has two different corner normals: it gives every
    fan of a vertex that one normal, as per corner would. A zero row means
    the loop's automatic normal per corner but the vertex's per vertex, so
    those go per corner."""
    if not HAS_CORNER_NORMALS:
        # 3.4-4.0: custom normals need auto smooth; its angle would split the
        # fans further, which a fan of equal normals does not mind.
        if not mesh.use_auto_smooth:
            mesh.use_auto_smooth = True
            mesh.auto_smooth_angle = math.pi
    per_vertex = None if has_zero_rows else arrays.vertex_normals(normals)
    if per_vertex is not None:
        mesh.normals_split_custom_set_from_vertices(per_vertex)
    else:
        mesh.normals_split_custom_set(np.ascontiguousarray(arrays.to_loops(normals), dtype=np.float32))
    mesh.update()
    return "corner" if per_vertex is None else "vertex"

