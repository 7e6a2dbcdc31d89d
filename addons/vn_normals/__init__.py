"""vn for Blender: recompute custom split normals with any of the weighting
schemes of Jin, Lewis & West 2005, computed by vn's C library (ctypes)."""

bl_info = {
    "name": "vn: Vertex Normals",
    "author": "vn",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Object > Recompute Normals; Edit Mode > Mesh > Normals > Recompute Normals",
    "description": "Recompute custom split normals with the weighting schemes of Jin, Lewis & West 2005",
    "category": "Mesh",
}

import math
import sys
import time

if "bpy" in locals():
    import importlib
    importlib.reload(binding)  # noqa: F821
    importlib.reload(mesh_io)  # noqa: F821

import bmesh
import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, StringProperty

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
        except binding.VnError as e:
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


class MESH_OT_vn_recompute_normals(bpy.types.Operator):
    """Recompute custom split normals with one of vn's weighting schemes"""

    bl_idname = "mesh.vn_recompute_normals"
    bl_label = "Recompute Normals"
    bl_options = {"REGISTER", "UNDO"}

    method: EnumProperty(name="Method", items=_method_items(), default="MWA", description="Weighting scheme")
    keep_sharp: BoolProperty(
        name="Keep Sharp Edges", default=True,
        description="Marked sharp edges and flat-shaded faces split the normals, as Blender's own normals do")
    use_crease: BoolProperty(
        name="Crease", default=False,
        description="Also split where two faces meet at more than the crease angle (marks those edges sharp)")
    crease_angle: FloatProperty(
        name="Crease Angle", subtype="ANGLE", default=math.radians(30.0), min=0.0, max=math.pi)
    weld: BoolProperty(
        name="Weld by Position", default=False,
        description="Treat vertices at the same position as one (meshes imported in split chunks)")
    weld_distance: FloatProperty(
        name="Weld Distance", subtype="DISTANCE", default=1e-5, min=0.0, precision=6,
        description="Vertices this close in every coordinate count as one")
    weld_keep_hard: BoolProperty(
        name="Keep Hard Edges", default=True,
        description="Weld: vertices whose current normals differ by more than the crease angle stay apart "
                    "(the hard edges of imported files)")
    selected_only: BoolProperty(
        name="Selected Only", default=False,
        description="Edit mode: change only the corners of selected faces; the others keep their normals")

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
        layout.use_property_split = True
        layout.prop(self, "method")
        layout.prop(self, "keep_sharp")
        row = layout.row(heading="Crease")
        row.prop(self, "use_crease", text="")
        sub = row.row()
        sub.active = self.use_crease
        sub.prop(self, "crease_angle", text="")
        row = layout.row(heading="Weld")
        row.prop(self, "weld", text="")
        sub = row.row()
        sub.active = self.weld
        sub.prop(self, "weld_distance", text="")
        sub = layout.row()
        sub.active = self.weld
        sub.prop(self, "weld_keep_hard")
        if context.mode == "EDIT_MESH":
            layout.prop(self, "selected_only")

    def execute(self, context):
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
        except binding.VnError as e:
            self.report({"ERROR"}, "vn: %s" % e)
            return {"CANCELLED"}
        # objects sharing a mesh: computed once
        owners = {o.data.name_full: o for o in objects}
        edit = context.mode == "EDIT_MESH"
        selected_only = self.selected_only and edit
        # Edit Mode: the work is done on a Mesh. A copy of each edit mesh, read
        # back into it, costs a third of leaving and re-entering Edit Mode.
        copies = edit and all(_reloadable(o.data) for o in owners.values())
        t0 = time.perf_counter()
        corners = 0
        marked = 0
        if edit and not copies:
            bpy.ops.object.mode_set(mode="OBJECT")
        try:
            for obj in owners.values():
                work = _edit_copy(obj) if copies else obj.data
                try:
                    c, m = self._mesh(lib, work, selected_only)
                    if copies:
                        _load_edit_mesh(obj.data, work)
                finally:
                    if copies:
                        obj.to_mesh_clear()
                corners += c
                marked += m
        except binding.VnError as e:
            self.report({"ERROR"}, "vn: %s" % e)
            return {"CANCELLED"}
        finally:
            if edit and not copies:
                bpy.ops.object.mode_set(mode="EDIT")
        ms = (time.perf_counter() - t0) * 1e3
        msg = "vn %s: %d mesh%s, %d corners, %.1f ms" % (
            self.method, len(owners), "" if len(owners) == 1 else "es", corners, ms)
        if marked:
            msg += " (%d edges marked sharp)" % marked
        self.report({"INFO"}, msg)
        for o in objects:
            for w in _subsurf_warnings(o):
                self.report({"WARNING"}, "vn: " + w)
        return {"FINISHED"}

    def _weld(self, lib, a, mesh):
        """remap[v]: the vertex v counts as; with weld_keep_hard, vertices at one
        place whose current normals differ by more than the crease angle stay apart."""
        remap = lib.weld_positions(a.co, self.weld_distance)
        if not self.weld_keep_hard:
            return remap
        n = np.zeros((len(a.co), 3))
        np.add.at(n, a.corner_vert, a.from_loops(mesh_io.corner_normals(mesh)))
        n /= np.maximum(np.linalg.norm(n, axis=1), 1e-30)[:, None]
        cos_limit = math.cos(self.crease_angle)
        bad = np.flatnonzero((n * n[remap]).sum(axis=1) < cos_limit)
        groups = {}  # representative -> the vertices kept apart from it
        for v in bad:
            kept = groups.setdefault(remap[v], [])
            remap[v] = next((k for k in kept if n[k] @ n[v] >= cos_limit), v)
            if remap[v] == v:
                kept.append(v)
        return remap

    def _mesh(self, lib, mesh, selected_only):
        if not mesh.loops:
            return 0, 0
        a = mesh_io.MeshArrays(mesh)
        if selected_only and not a.face_select.any():
            return 0, 0
        a.edge_sharp &= ~_clear_own_sharp(mesh)
        corner_vert = a.corner_vert
        if self.weld:
            corner_vert = self._weld(lib, a, mesh)[corner_vert]
        # Blender 3.4-4.0's Auto Smooth splits at its angle whatever the normals are
        crease = min(self.crease_angle if self.use_crease else math.pi, mesh_io.auto_smooth_angle(mesh))
        normals = lib.polygon_corner_normals(a.co, corner_vert, a.face_offsets, self.method.lower(),
                                             crease, a.sharp_corner_flags(self.keep_sharp), dtype=np.float32)
        has_zero_rows = lib.last_stats["zero_normals"] > 0
        changed = None
        if selected_only:
            changed = a.face_select[a.face_of_corner]
            current = a.from_loops(mesh_io.corner_normals(mesh))
            normals = np.where(changed[:, None], normals, current)
        split = np.zeros(len(mesh.edges), dtype=bool)
        if selected_only or self.use_crease:
            # Blender averages custom normals over each of its fans: split its
            # fans wherever the new normals differ across an edge.
            split = a.edges_where_normals_differ(normals) & ~a.edge_sharp
            mesh_io.mark_sharp(mesh, split)
        _set_own_sharp(mesh, split)
        mesh_io.set_custom_normals(mesh, a, normals, has_zero_rows)
        return int(changed.sum()) if changed is not None else len(normals), int(split.sum())


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
    attr = mesh.attributes.get(OWN_SHARP)
    own = np.zeros(len(mesh.edges), dtype=bool)
    if attr is None:
        return own
    attr.data.foreach_get("value", own)
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


_classes = (VN_AddonPreferences, MESH_OT_vn_recompute_normals)


def register():
    for c in _classes:
        bpy.utils.register_class(c)
    draws = _menu_draws()
    draws[0] = _object_menu(draws[0])
    bpy.types.VIEW3D_MT_edit_mesh_normals.append(_normals_menu_entry)


def unregister():
    bpy.types.VIEW3D_MT_edit_mesh_normals.remove(_normals_menu_entry)
    draws = _menu_draws()
    for i, f in enumerate(draws):
        if hasattr(f, "vn_wrapped"):
            draws[i] = f.vn_wrapped
    for c in reversed(_classes):
        bpy.utils.unregister_class(c)
