"""vn for Blender: recompute custom split normals with any of the weighting
schemes of Jin, Lewis & West 2005 or the local fits beyond them, computed by
vn's C library (ctypes)."""

bl_info = {
    "name": "vn: Vertex Normals",
    "author": "vn",
    "version": (0, 2, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Object > Recompute Normals; Edit Mode > Mesh > Normals > Recompute Normals; "
                "Properties > Object Data > vn Live Normals",
    "description": "Recompute custom split normals with the weighting schemes of Jin, Lewis & West 2005 "
                   "or the local fits beyond them",
    "category": "Mesh",
}

import hashlib
import math
import sys
import time
import traceback

if "bpy" in locals():
    import importlib
    importlib.reload(binding)  # noqa: F821
    importlib.reload(mesh_io)  # noqa: F821

import bmesh
import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, PointerProperty, StringProperty

from . import binding, mesh_io

# vn's schemes, in vn_method order: (identifier, label, the library's
# vn_method_description, vn_method_reference). Kept here so that menus and the
# Method list never depend on loading the library; the tests check them
# against the library's own list.
METHODS = (
    ("MWE", "Equal weights (MWE)", "mean weighted equally: sum of unit face normals",
     "Gouraud 1971; Jin et al. 2005 eq. 1"),
    ("MWA", "Angle weighted (MWA)", "mean weighted by angle: face normals times the corner angle",
     "Thurmer & Wuthrich 1998; Jin et al. 2005 eq. 2"),
    ("MWSELR", "Sine and edge length reciprocals (MWSELR)",
     "mean weighted by sine and edge length reciprocals: sin(a) / (|E||E'|)", "Max 1999; Jin et al. 2005 eq. 4"),
    ("MWAAT", "Area weighted (MWAAT)", "mean weighted by areas of adjacent triangles: |E x E'|",
     "Max 1999; Jin et al. 2005 eq. 5"),
    ("MWELR", "Edge length reciprocals (MWELR)", "mean weighted by edge length reciprocals: 1 / (|E||E'|)",
     "Max 1999; Jin et al. 2005 eq. 6"),
    ("MWRELR", "Square root of edge length reciprocals (MWRELR)",
     "mean weighted by square root of edge length reciprocals: 1 / sqrt(|E||E'|)", "Max 1999; Jin et al. 2005 eq. 7"),
    ("MEWCSA", "Cotangent weights (MEWCSA)",
     "mean edge weighted by cotangents of subtended angles (area gradient; sign not corrected)",
     "Desbrun et al. 1999; Jin et al. 2005 eq. 9"),
    ("SMEWCSA", "Sign-correct cotangent weights (SMEWCSA)",
     "sign-correct MEWCSA: oriented by MWSELR, which it falls back to where mean curvature is about zero",
     "Desbrun et al. 1999; Meyer et al. 2003"),
    ("QUADRIC", "Quadric fit on the 1-ring (QUADRIC)",
     "weighted least-squares quadric z = f(x, y) on the 1-ring, in MWA's tangent frame, refitted once",
     "beyond Jin et al. 2005; O(h^2)"),
    ("JET", "Cubic jet fit on the 2-ring (JET)",
     "weighted least-squares cubic jet on the 2-ring, in MWA's tangent frame, refitted once",
     "Cazals & Pouget 2003; O(h^3)"),
    ("ADAPTIVE", "Adaptive: fits where smooth, else MWA or MWAAT (ADAPTIVE)",
     "the 2-ring jet, or a Gaussian-weighted 5-ring fit that averages noise out, by GCV score; MWSELR on spheres and where the jet agrees with it; where rough, MWAAT on a lattice height field, else MWA: the choice when unsure",
     "beyond Jin et al. 2005; Craven & Wahba 1979 (GCV)"),
)
# MEWCSA turns 28.5% of Suzanne's corners by more than 90 degrees.
_NOT_FOR_SHADING = {"MEWCSA": " Not for shading: it points inward where the surface is concave or saddle-shaped."}
# Edge attribute listing the edges this add-on marked sharp (and will clear).
OWN_SHARP = "vn_marked_sharp"


def _preferences(context=None):
    context = context or bpy.context
    addon = context.preferences.addons.get(__package__)
    return addon.preferences if addon else None


def _library(context=None):
    prefs = _preferences(context)
    return binding.load_configured(bpy.path.abspath(prefs.library_path) if prefs else "")


class VN_AddonPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    library_path: StringProperty(
        name="vn library",
        description="Path of libvn.so to use instead of the bundled copy "
                    "(the VN_LIBRARY environment variable overrides both)",
        subtype="FILE_PATH",
    )

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "library_path")
        try:
            lib = binding.load_configured(bpy.path.abspath(self.library_path))
            layout.label(text="Using vn %s: %s" % (lib.version, lib.path), icon="CHECKMARK")
        except binding.Error as e:
            layout.label(text=str(e), icon="ERROR")


def _candidates(context):
    if context.mode == "EDIT_MESH":
        return [o for o in context.objects_in_mode_unique_data if o.type == "MESH"]
    return [o for o in context.selected_objects if o.type == "MESH"]


def _not_editable(obj):
    """Why the object's mesh cannot keep new normals, or "" when it can."""
    mesh = obj.data
    fix = "make it local: Object > Relations > Make Local > Selected Objects and Data"
    if mesh.library is not None:
        return "its mesh %r is linked from %s (%s)" % (mesh.name, bpy.path.basename(mesh.library.filepath), fix)
    if mesh.override_library is not None:
        # Blender saves an override's property changes, not its geometry: the
        # mesh is read again from its library when the file opens.
        return "its mesh %r is a library override, whose normals Blender does not save (%s)" % (mesh.name, fix)
    return ""


def _subsurf_warnings(obj):
    """Live Subdivision Surface modifiers that throw custom normals away."""
    return ["%s: modifier %r discards custom normals; tick its Advanced > Use Custom Normals "
            "(use_custom_normals)" % (obj.name, m.name)
            for m in obj.modifiers
            if m.type == "SUBSURF" and m.show_viewport and not m.use_custom_normals]


def _method_items():
    return [(i, label, "%s (%s).%s" % (d, r, _NOT_FOR_SHADING.get(i, ""))) for i, label, d, r in METHODS]


def _settings(update=None):
    """The properties a run's normals depend on, by name: the operator's, and
    the copy a live mesh keeps (update: called when that copy changes)."""
    return {
        "method": EnumProperty(name="Method", items=_method_items(), default="MWA",
                               description="Weighting scheme", update=update),
        "keep_sharp": BoolProperty(
            name="Keep Sharp Edges", default=True, update=update,
            description="Marked sharp edges and flat-shaded faces split the normals, as Blender's own normals do"),
        "use_crease": BoolProperty(
            name="Crease", default=False, update=update,
            description="Also split where two faces meet at more than the crease angle (marks those edges sharp)"),
        "crease_angle": FloatProperty(
            name="Crease Angle", subtype="ANGLE", default=math.radians(30.0), min=0.0, max=math.pi, update=update),
        "weld": BoolProperty(
            name="Weld by Position", default=False, update=update,
            description="Treat vertices at the same position as one (meshes imported in split chunks)"),
        "weld_distance": FloatProperty(
            name="Weld Distance", subtype="DISTANCE", default=1e-5, min=0.0, precision=6, update=update,
            description="Vertices this close in every coordinate count as one"),
        "weld_keep_hard": BoolProperty(
            name="Keep Hard Edges", default=True, update=update,
            description="Weld: vertices whose current normals differ by more than the crease angle stay apart "
                        "(the hard edges of imported files)"),
        # the Weighted Normal modifier's options, with its names, descriptions and meaning
        "use_face_influence": BoolProperty(
            name="Face Influence", default=False, update=update, description="Use influence of face for weighting"),
        "vertex_group": StringProperty(
            name="Vertex Group", update=update, description="Vertex group name for modifying the selected areas"),
        "invert_vertex_group": BoolProperty(
            name="Invert", default=False, update=update, description="Invert vertex group influence"),
    }


SETTINGS = tuple(_settings())


def _draw_settings(layout, s, obj):
    layout.use_property_split = True
    layout.prop(s, "method")
    layout.prop(s, "keep_sharp")
    row = layout.row(heading="Crease")
    row.prop(s, "use_crease", text="")
    sub = row.row()
    sub.active = s.use_crease
    sub.prop(s, "crease_angle", text="")
    row = layout.row(heading="Weld")
    row.prop(s, "weld", text="")
    sub = row.row()
    sub.active = s.weld
    sub.prop(s, "weld_distance", text="")
    sub = layout.row()
    sub.active = s.weld
    sub.prop(s, "weld_keep_hard")
    layout.prop(s, "use_face_influence")
    # as the modifier draws its vertex group: a search of the object's groups, invert beside it
    row = layout.row(align=True)
    if obj is not None and obj.type == "MESH":
        row.prop_search(s, "vertex_group", obj, "vertex_groups")
    else:
        row.prop(s, "vertex_group")
    sub = row.row(align=True)
    sub.active = bool(s.vertex_group)
    sub.prop(s, "invert_vertex_group", text="", icon="ARROW_LEFTRIGHT")


class MESH_OT_vn_recompute_normals(bpy.types.Operator):
    """Recompute custom split normals with one of vn's weighting schemes"""

    bl_idname = "mesh.vn_recompute_normals"
    bl_label = "Recompute Normals"
    bl_options = {"REGISTER", "UNDO"}

    __annotations__ = {
        **_settings(),
        "selected_only": BoolProperty(
            name="Selected Only", default=False,
            description="Edit mode: change only the corners of selected faces; the others keep their normals "
                        "(not with Live, which recomputes whole meshes)"),
        # not remembered for the next run: a mesh goes live only when asked
        "live": BoolProperty(
            name="Live", default=False, options={"SKIP_SAVE"},
            description="Keep these normals up to date: recompute them with these settings after each edit of "
                        "the mesh (leaving Edit Mode, a change of its data in Object Mode). Stored in the mesh"),
    }

    @classmethod
    def poll(cls, context):
        objects = _candidates(context)
        why = ("No mesh object selected" if not objects else
               "" if any(not _not_editable(o) for o in objects) else
               "%s: %s" % (objects[0].name, _not_editable(objects[0])))
        if why:
            cls.poll_message_set(why)
        return not why

    def draw(self, context):
        layout = self.layout
        _draw_settings(layout, self, context.active_object)
        layout.prop(self, "live")
        if context.mode == "EDIT_MESH":
            row = layout.row()
            row.active = not self.live
            row.prop(self, "selected_only")

    def invoke(self, context, event):
        # Run again on a live mesh (the active object's first): start from its
        # settings, Live ticked, so that changing the method keeps it live.
        objects = sorted(_candidates(context), key=lambda o: o != context.active_object)
        live = next((o.data.vn_live for o in objects if _is_live(o.data)), None)
        if live is not None:
            for name in SETTINGS + ("live",):
                if not self.properties.is_property_set(name):
                    setattr(self, name, getattr(live, name))
        return self.execute(context)

    def execute(self, context):
        global _busy
        _busy = True  # its mode switches and writes are no edits for live meshes to follow
        try:
            return self._run(context)
        finally:
            _busy = False

    def _run(self, context):
        objects, skipped = [], []
        for o in _candidates(context):
            why = _not_editable(o)
            if why:
                skipped.append("%s: %s" % (o.name, why))
            else:
                objects.append(o)
        if skipped:
            self.report({"WARNING"}, "vn: skipped " + "; ".join(skipped))
        if not objects:
            return {"CANCELLED"}
        try:
            lib = _library(context)
        except binding.Error as e:
            self.report({"ERROR"}, "vn: %s" % e)
            return {"CANCELLED"}
        # objects sharing a mesh: computed once (their vertex groups are the mesh's)
        owners = {}
        for o in objects:
            owners.setdefault(o.data.name_full, o)
        edit = context.mode == "EDIT_MESH"
        # Live recomputes whole meshes: this run does too, so that it gives what they will
        selected_only = self.selected_only and edit and not self.live
        # Edit Mode: the work is done on a Mesh. A copy of each edit mesh, read
        # back into it, costs a third of leaving and re-entering Edit Mode.
        copies = edit and all(_reloadable(o.data) for o in owners.values())
        t0 = time.perf_counter()
        meshes = corners = marked = 0
        no_group = []
        if edit and not copies:
            bpy.ops.object.mode_set(mode="OBJECT")
        try:
            for obj in owners.values():
                work = _edit_copy(obj) if copies else obj.data
                try:
                    members = _group_members(obj, work, self)
                    if members is not None and not members.any():
                        no_group.append(obj.name)
                        continue
                    c, m = _compute(lib, work, self, selected_only, members=members, owner=obj.data)
                    _store_live(obj.data, self, work)
                    if copies:
                        _load_edit_mesh(obj.data, work)
                finally:
                    if copies:
                        obj.to_mesh_clear()
                meshes += 1
                corners += c
                marked += m
        except binding.Error as e:
            self.report({"ERROR"}, "vn: %s" % e)
            return {"CANCELLED"}
        finally:
            if edit and not copies:
                bpy.ops.object.mode_set(mode="EDIT")
        if no_group:
            self.report({"WARNING"}, "vn: skipped %s: no vertex to change in group %r%s" % (
                ", ".join(no_group), self.vertex_group, " (inverted)" if self.invert_vertex_group else ""))
        if not meshes:
            return {"CANCELLED"}
        ms = (time.perf_counter() - t0) * 1e3
        msg = "vn %s: %d mesh%s, %d corners, %.1f ms" % (
            self.method, meshes, "" if meshes == 1 else "es", corners, ms)
        if marked:
            msg += " (%d edges marked sharp)" % marked
        if self.live:
            msg += ", live"
        self.report({"INFO"}, msg)
        for o in objects:
            for w in _subsurf_warnings(o):
                self.report({"WARNING"}, "vn: " + w)
        return {"FINISHED"}


def _weld(lib, a, mesh, s):
    """remap[v]: the vertex v counts as; with weld_keep_hard, vertices at one
    place whose current normals differ by more than the crease angle stay apart."""
    remap = lib.weld_positions(a.co, s.weld_distance)
    if not s.weld_keep_hard:
        return remap
    n = np.zeros((len(a.co), 3))
    np.add.at(n, a.corner_vert, a.from_loops(mesh_io.corner_normals(mesh)))
    n /= np.maximum(np.linalg.norm(n, axis=1), 1e-30)[:, None]
    cos_limit = math.cos(s.crease_angle)
    bad = np.flatnonzero((n * n[remap]).sum(axis=1) < cos_limit)
    groups = {}  # representative -> the vertices kept apart from it
    for v in bad:
        kept = groups.setdefault(remap[v], [])
        remap[v] = next((k for k in kept if n[k] @ n[v] >= cos_limit), v)
        if remap[v] == v:
            kept.append(v)
    return remap


def _group_members(obj, mesh, s):
    """Per vertex of mesh (obj's mesh, or Edit Mode's copy of it): whether
    the settings s change it (in the vertex group, or not in it with Invert),
    or None for every vertex. As the Weighted Normal modifier: membership
    counts, not weight. A mesh without the group has no member. The group
    names are the mesh's (3.0+), reached through an object using it."""
    if not s.vertex_group:
        return None
    index = obj.vertex_groups.find(s.vertex_group)
    members = (mesh_io.vertex_group_members(mesh, index) if index >= 0
               else np.zeros(len(mesh.vertices), dtype=bool))
    if s.invert_vertex_group:
        members = ~members
    return None if members.all() else members


def _compute(lib, mesh, s, selected_only=False, a=None, members=None, owner=None):
    """Computes and stores a mesh's normals with the settings s (the operator,
    or a live mesh's copy: the same names); a: its arrays when already read;
    members: per vertex, whether it changes (None: all); owner: the mesh in
    bpy.data that mesh is a copy of (Edit Mode), whose plan it uses.
    Returns (corners changed, edges marked sharp)."""
    if not mesh.loops:
        return 0, 0
    if a is None:
        a = mesh_io.MeshArrays(mesh)
    if selected_only and not a.face_select.any():
        return 0, 0
    a.edge_sharp &= ~_clear_own_sharp(mesh)
    corner_vert = a.corner_vert
    if s.weld:
        corner_vert = _weld(lib, a, mesh, s)[corner_vert]
    # Blender 3.4-4.0's Auto Smooth splits at its angle whatever the normals are
    crease = min(s.crease_angle if s.use_crease else math.pi, mesh_io.auto_smooth_angle(mesh))
    # Face Influence without face strengths on the mesh: all medium, no effect
    strength = a.face_strength if s.use_face_influence else None
    sharp = a.sharp_corner_flags(s.keep_sharp)
    if len(a.face_size) > PLAN_MIN_FACES:
        plan = _plan(lib, owner or mesh, a, corner_vert, strength)
        normals, stats = plan.corner_normals(a.co, s.method.lower(), crease, sharp, dtype=np.float32, stats=True)
    else:
        normals, stats = lib.corner_normals(a.co, corner_vert, a.face_offsets, s.method.lower(), crease, sharp,
                                            dtype=np.float32, face_strength=strength)
    has_zero_rows = stats["zero_normals"] > 0
    changed = None
    if selected_only:
        changed = a.face_select[a.face_of_corner]
    if members is not None:
        # a whole vertex changes or keeps its normals, so Blender's fans need no new split
        in_group = members[a.corner_vert]
        changed = in_group if changed is None else changed & in_group
    if changed is not None:
        current = a.from_loops(mesh_io.corner_normals(mesh))
        normals = np.where(changed[:, None], normals, current)
    split = np.zeros(len(mesh.edges), dtype=bool)
    if selected_only or s.use_crease:
        # Blender averages custom normals over each of its fans: split its
        # fans wherever the new normals differ across an edge.
        split = a.edges_where_normals_differ(normals) & ~a.edge_sharp
        mesh_io.mark_sharp(mesh, split)
    _set_own_sharp(mesh, split)
    mesh_io.set_custom_normals(mesh, a, normals, has_zero_rows)
    return int(changed.sum()) if changed is not None else len(normals), int(split.sum())


# ------------------------------------------------------------------ plans
# Meshes of more faces than this are computed through a vn plan (issue 20)
# kept per mesh, so that the next run on the same faces (a live recompute,
# the redo panel) finds the library's work memory allocated and mapped
# already. Below it the saving is not worth keeping the plan's memory
# (about 180 bytes a quad once used: what a call without a plan allocates
# and frees each time).
PLAN_MIN_FACES = 100_000
# Plans kept at most, for this many meshes (the least recently used is freed).
PLAN_CACHE_SIZE = 2
# mesh.as_pointer() -> (mesh name, library, plan, corner_vert, face_offsets),
# least recently used first. A plan depends on the faces only: one found
# under a pointer a freed mesh left to a new one serves it if they match.
_plans = {}
# Plans made since the add-on was loaded (the tests count them).
plan_stats = {"created": 0}


def _plan(lib, mesh, a, corner_vert, strength):
    """The plan of mesh's faces (corners corner_vert, a.face_offsets),
    made again when they changed, with the face strengths to use."""
    key = mesh.as_pointer()
    entry = _plans.pop(key, None)
    if entry is not None:
        _name, plan_lib, plan, plan_corner_vert, plan_offsets = entry
        if not (plan_lib is lib and plan.vertex_count == len(a.co) and
                (plan.face_strength is None) == (strength is None) and
                np.array_equal(plan_corner_vert, corner_vert) and np.array_equal(plan_offsets, a.face_offsets)):
            plan.close()
            entry = None
    if entry is None:
        plan = lib.plan(corner_vert, a.face_offsets, len(a.co), face_strength=strength)
        entry = (None, lib, plan, corner_vert.copy(), a.face_offsets.copy())
        plan_stats["created"] += 1
    elif strength is not None:
        plan.face_strength[:] = strength
    _plans[key] = (mesh.name,) + entry[1:]
    while len(_plans) > PLAN_CACHE_SIZE:
        _plans.pop(next(iter(_plans)))[2].close()
    return plan


def _free_plans(every=False):
    """Frees the plans of meshes no longer in bpy.data under their name
    (every: all plans). A plan by name: no pass over every mesh."""
    for key, entry in list(_plans.items()):
        mesh = None if every else bpy.data.meshes.get(entry[0])
        if mesh is None or mesh.as_pointer() != key:
            _plans.pop(key)[2].close()


@bpy.app.handlers.persistent
def _on_load_pre(*_args):
    _free_plans(every=True)


def _own_sharp(mesh):
    """The edges this add-on marked sharp in its last run (listed in OWN_SHARP)."""
    attr = mesh.attributes.get(OWN_SHARP)
    own = np.zeros(len(mesh.edges), dtype=bool)
    if attr is not None:
        attr.data.foreach_get("value", own)
    return own


def _reloadable(mesh):
    """Whether mesh's edit BMesh may be emptied and read again in place
    (_load_edit_mesh). Not while a script holds a Python reference to it:
    BMesh.clear() unlinks the BMesh from that reference, which Blender then
    no longer invalidates when it frees the BMesh (a crash at exit). Not with
    shape keys either: only entering Edit Mode creates the key index layer
    that leaving it needs to carry edits into the keys."""
    if mesh.shape_keys is not None:
        return False
    bm = bmesh.from_edit_mesh(mesh)
    return sys.getrefcount(bm) <= 2  # bm and getrefcount's argument


def _edit_copy(obj):
    """A copy of obj's edit mesh as it is now (selection, hidden faces,
    attributes and all) as a Mesh outside bpy.data, freed by
    obj.to_mesh_clear(). Outside: a mesh added to bpy.data in Edit Mode would
    make the next undo reload the whole file."""
    obj.update_from_editmode()
    return obj.to_mesh()


def _load_edit_mesh(mesh, work):
    """Replaces mesh's edit BMesh with the Mesh work, as entering Edit Mode would."""
    bm = bmesh.from_edit_mesh(mesh)
    select_mode = bm.select_mode  # not a Mesh property: clear() resets it
    bm.clear()
    bm.from_mesh(work)
    bm.select_mode = select_mode
    if not mesh_io.HAS_CORNER_NORMALS:  # Mesh settings, not in the BMesh
        mesh.use_auto_smooth, mesh.auto_smooth_angle = work.use_auto_smooth, work.auto_smooth_angle
    bmesh.update_edit_mesh(mesh, loop_triangles=True, destructive=True)


def _clear_own_sharp(mesh):
    """Unmarks the edges this add-on marked sharp in an earlier run (so that
    only the user's marks remain); returns them."""
    own = _own_sharp(mesh)
    if own.any():
        sharp = np.empty(len(mesh.edges), dtype=bool)
        mesh.edges.foreach_get("use_edge_sharp", sharp)
        mesh.edges.foreach_set("use_edge_sharp", sharp & ~own)
    return own


def _set_own_sharp(mesh, own):
    attr = mesh.attributes.get(OWN_SHARP)
    if not own.any():
        if attr is not None:
            mesh.attributes.remove(attr)
        return
    if attr is None:
        attr = mesh.attributes.new(OWN_SHARP, "BOOLEAN", "EDGE")
    attr.data.foreach_set("value", own)


# ------------------------------------------------------------------ live normals
# A live mesh keeps the settings of the run that made it live (in its
# vn_live) and is recomputed with them after each edit of its data. The
# normals are the mesh's, so the setting is too: objects sharing a mesh share
# it, and it is computed once.

_busy = False  # the operator is running: its own mode switches and writes are no edits
# How many live meshes were checked for a change (read and digested) and how
# many were recomputed, since the add-on was loaded (the tests count them).
live_stats = {"checked": 0, "recomputed": 0}


def _is_live(mesh):
    # reading mesh.vn_live would add the (empty) settings to every mesh asked
    return mesh.is_property_set("vn_live") and mesh.vn_live.live


def _read(mesh):
    """(arrays, state) of a mesh with faces: its arrays as _compute reads them
    (edge_sharp without the add-on's own marks), and a digest of what the
    normals are computed from: positions, faces, the user's sharp edges and
    flat faces, face strengths, 3.4-4.0's Auto Smooth angle. Writing custom
    normals and the add-on's own marks leave the digest unchanged. Vertex
    group membership is not in it: Blender reads it one vertex at a time."""
    a = mesh_io.MeshArrays(mesh)
    a.edge_sharp &= ~_own_sharp(mesh)
    sharp = a.sharp_corner_flags(True)
    parts = (a.co, a.corner_vert, a.face_offsets,
             np.flatnonzero(sharp) if sharp is not None else np.empty(0, dtype=np.intp),
             a.face_strength if a.face_strength is not None else np.empty(0, dtype=np.int32),
             np.array([mesh_io.auto_smooth_angle(mesh)]))
    # to notice changes, not to resist attacks: SHA-1 is the fastest hashlib has (CPUs do it)
    h = hashlib.sha1(np.array([p.size for p in parts], dtype=np.int64), usedforsecurity=False)
    for p in parts:
        h.update(np.ascontiguousarray(p))
    return a, h.hexdigest()


def _store_live(mesh, s, data=None):
    """After a run with the settings s: the mesh follows edits with them
    (s.live), or no longer does. data: the Mesh the run computed, when not
    mesh itself (Edit Mode's copy)."""
    if not s.live:
        if _is_live(mesh):
            mesh.vn_live.live = False
        return
    live = mesh.vn_live
    for name in SETTINGS:
        setattr(live, name, getattr(s, name))
    live.live = True
    data = data or mesh
    live.state = _read(data)[1] if data.loops else ""
    live.error = ""


def _live_recompute(mesh):
    """Recomputes a live mesh with its settings when its data changed since
    its normals were computed. Not while an object edits, sculpts or paints it
    (in Edit Mode its data is not current; strokes come one by one): leaving
    the mode updates the mesh, which comes back here."""
    live = mesh.vn_live
    users = [o for o in bpy.data.objects if o.data == mesh]
    if (mesh.library is not None or not mesh.loops or any(o.mode != "OBJECT" for o in users)
            or (live.vertex_group and not users)):  # group names are reached through an object
        return
    live_stats["checked"] += 1
    a, state = _read(mesh)
    if state == live.state:
        return  # e.g. its own custom normals written, a shape key's value changed
    try:
        members = _group_members(users[0], mesh, live) if users else None
        if members is None or members.any():
            _compute(_library(), mesh, live, a=a, members=members)
    except Exception as e:  # a handler's exception would be printed on every update
        error = str(e) if isinstance(e, binding.Error) else "%s: %s" % (type(e).__name__, e)
        if error != live.error:  # once, not on every update (shown in the vn panel meanwhile)
            print("vn live: mesh %r not recomputed, its normals are stale: %s" % (mesh.name, error))
            if not isinstance(e, binding.Error):
                traceback.print_exc()
            live.error = error
        live.state = ""  # retried on the next update, whatever it is (a failure may have written a part)
        return
    live.state = state
    live.error = ""
    live_stats["recomputed"] += 1


def _live_changed(self, context):
    """A live mesh's settings or its Live tick changed (the vn panel, a
    script): recompute now, or on leaving Edit Mode."""
    if _busy:
        return  # the operator stores the settings of the normals it computes
    self.state = ""  # the normals are not those of these settings
    if self.live:
        _live_recompute(self.id_data)


@bpy.app.handlers.persistent
def _on_depsgraph_update(scene, depsgraph):
    """Live meshes whose data was updated: recomputed if it changed. Frame
    changes (animation, playback) do not come here, and neither does the
    update of what this writes (Blender's second evaluation pass runs no
    handlers)."""
    if _busy:
        return
    if _plans:  # a mesh removed: its plan goes too
        _free_plans()
    meshes = [u.id.original for u in depsgraph.updates
              if u.is_updated_geometry and isinstance(u.id, bpy.types.Mesh)]
    for mesh in meshes:
        if _is_live(mesh):
            _live_recompute(mesh)


class VN_LiveSettings(bpy.types.PropertyGroup):
    __annotations__ = {
        "live": BoolProperty(
            name="Live", default=False, update=_live_changed,
            description="Recompute this mesh's normals with these settings after each edit "
                        "(leaving Edit Mode, a change of its data in Object Mode)"),
        **_settings(update=_live_changed),
        # digest of the mesh data the normals were computed from (_read)
        "state": StringProperty(),
        # why the last live recompute failed ("" when it worked)
        "error": StringProperty(),
    }


class DATA_PT_vn_live(bpy.types.Panel):
    """Object Data properties, beside Blender's Normals: the mesh's live setting."""

    bl_label = "vn Live Normals"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "data"
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context):
        return context.mesh is not None

    def draw_header(self, context):
        self.layout.prop(context.mesh.vn_live, "live", text="")

    def draw(self, context):
        live = context.mesh.vn_live
        layout = self.layout
        if live.error:
            layout.label(text=live.error, icon="ERROR")
        col = layout.column()
        col.active = live.live
        _draw_settings(col, live, context.object)


def _draw_entry(layout, context):
    # Blender keeps the operator's last settings: the entry names the method it will use
    last = context.window_manager.operator_properties_last(MESH_OT_vn_recompute_normals.bl_idname)
    layout.operator(MESH_OT_vn_recompute_normals.bl_idname,
                    text="Recompute Normals (%s)" % (last.method if last else "MWA"))


class _AfterShadeFlat:
    """The Object menu's layout while Blender's own draw runs, adding the entry
    right after Shade Flat (menus take add-on entries only at their top or
    bottom)."""

    def __init__(self, layout, context):
        object.__setattr__(self, "_layout", layout)
        object.__setattr__(self, "_context", context)
        object.__setattr__(self, "placed", False)

    def operator(self, idname, *args, **kw):
        props = self._layout.operator(idname, *args, **kw)
        if idname == "object.shade_flat" and not self.placed:
            object.__setattr__(self, "placed", True)
            _draw_entry(self._layout, self._context)
        return props

    def __getattr__(self, name):
        return getattr(self._layout, name)

    def __setattr__(self, name, value):  # layout.operator_context = ...
        setattr(self._layout, name, value)


class _MenuWithLayout:
    def __init__(self, menu, layout):
        self._menu, self.layout = menu, layout

    def __getattr__(self, name):
        return getattr(self._menu, name)


def _object_menu(draw):
    """Blender's Object menu draw, with the entry after Shade Flat (or at the
    bottom, should a Blender version have no Shade Flat there)."""
    def draw_object_menu(self, context):
        layout = _AfterShadeFlat(self.layout, context)
        draw(_MenuWithLayout(self, layout), context)
        if not layout.placed:
            self.layout.separator()
            _draw_entry(self.layout, context)
    draw_object_menu.vn_wrapped = draw
    return draw_object_menu


def _normals_menu_entry(self, context):
    self.layout.separator()
    _draw_entry(self.layout, context)


def _menu_draws():
    # Blender's own list of a menu's draw functions (the class's draw first,
    # then those appended): the Object menu's own draw is wrapped in place.
    return bpy.types.VIEW3D_MT_object._dyn_ui_initialize()


_classes = (VN_AddonPreferences, VN_LiveSettings, MESH_OT_vn_recompute_normals, DATA_PT_vn_live)


def register():
    for c in _classes:
        bpy.utils.register_class(c)
    bpy.types.Mesh.vn_live = PointerProperty(type=VN_LiveSettings)
    draws = _menu_draws()
    draws[0] = _object_menu(draws[0])
    bpy.types.VIEW3D_MT_edit_mesh_normals.append(_normals_menu_entry)
    bpy.app.handlers.depsgraph_update_post.append(_on_depsgraph_update)
    bpy.app.handlers.load_pre.append(_on_load_pre)


def unregister():
    bpy.app.handlers.depsgraph_update_post.remove(_on_depsgraph_update)
    bpy.app.handlers.load_pre.remove(_on_load_pre)
    _free_plans(every=True)
    bpy.types.VIEW3D_MT_edit_mesh_normals.remove(_normals_menu_entry)
    draws = _menu_draws()
    for i, f in enumerate(draws):
        if hasattr(f, "vn_wrapped"):
            draws[i] = f.vn_wrapped
    del bpy.types.Mesh.vn_live
    for c in reversed(_classes):
        bpy.utils.unregister_class(c)
