"""vn for Blender: recompute custom split normals with any of the weighting
schemes of Jin, Lewis & West 2005, computed by vn's C library (ctypes)."""

bl_info = {
    "name": "vn: Vertex Normals",
    "author": "vn",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Object > Recompute Normals (…); Edit Mode > Mesh > Normals",
    "description": "Recompute custom split normals with the weighting schemes of Jin, Lewis & West 2005",
    "category": "Mesh",
}

import math
import time

if "bpy" in locals():
    import importlib
    importlib.reload(binding)  # noqa: F821
    importlib.reload(mesh_io)  # noqa: F821

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, StringProperty

from . import binding, mesh_io

# The schemes the library offers: (name, description, reference), read at registration.
_methods = []
_load_error = ""


def _preferences(context=None):
    context = context or bpy.context
    addon = context.preferences.addons.get(__package__)
    return addon.preferences if addon else None


def _library(context=None):
    prefs = _preferences(context)
    return binding.load_configured(prefs.library_path if prefs else "")


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
            lib = binding.load_configured(self.library_path)
            layout.label(text="Using vn %s: %s" % (lib.version, lib.path), icon="CHECKMARK")
        except binding.VnError as e:
            layout.label(text=str(e), icon="ERROR")


def _selected_meshes(context):
    if context.mode == "EDIT_MESH":
        return [o for o in context.objects_in_mode_unique_data if o.type == "MESH"]
    return [o for o in context.selected_objects if o.type == "MESH"]


class MESH_OT_vn_recompute_normals(bpy.types.Operator):
    """Recompute custom split normals with one of vn's weighting schemes"""

    bl_idname = "mesh.vn_recompute_normals"
    bl_label = "Recompute Normals (vn)"
    bl_options = {"REGISTER", "UNDO"}

    # method: an EnumProperty built from the library's schemes in register().
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
    selected_only: BoolProperty(
        name="Selected Only", default=False,
        description="Edit mode: change only the corners of selected faces; the others keep their normals")

    @classmethod
    def poll(cls, context):
        return bool(_selected_meshes(context))

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
        if context.mode == "EDIT_MESH":
            layout.prop(self, "selected_only")

    def execute(self, context):
        try:
            lib = _library(context)
        except binding.VnError as e:
            self.report({"ERROR"}, "vn: %s" % e)
            return {"CANCELLED"}
        objects = _selected_meshes(context)
        edit = context.mode == "EDIT_MESH"
        selected_only = self.selected_only and edit
        t0 = time.perf_counter()
        corners = 0
        marked = 0
        if edit:
            bpy.ops.object.mode_set(mode="OBJECT")
        try:
            for obj in objects:
                c, m = self._object(lib, obj.data, selected_only)
                corners += c
                marked += m
        except binding.VnError as e:
            self.report({"ERROR"}, "vn: %s" % e)
            return {"CANCELLED"}
        finally:
            if edit:
                bpy.ops.object.mode_set(mode="EDIT")
        ms = (time.perf_counter() - t0) * 1e3
        msg = "vn %s: %d object%s, %d corners, %.1f ms" % (
            self.method, len(objects), "" if len(objects) == 1 else "s", corners, ms)
        if marked:
            msg += " (%d edges marked sharp)" % marked
        self.report({"INFO"}, msg)
        return {"FINISHED"}

    def _object(self, lib, mesh, selected_only):
        if not mesh.loops:
            return 0, 0
        a = mesh_io.MeshArrays(mesh)
        if selected_only and not a.face_select.any():
            return 0, 0
        corner_vert = a.corner_vert
        if self.weld:
            remap = lib.weld_positions(a.co, self.weld_distance)
            corner_vert = remap[corner_vert]
        crease = self.crease_angle if self.use_crease else math.pi
        normals = lib.polygon_corner_normals(a.co, corner_vert, a.face_offsets, self.method.lower(),
                                             crease, a.sharp_corner_flags(self.keep_sharp))
        changed = None
        if selected_only:
            changed = a.face_select[a.face_of_corner]
            current = a.from_loops(mesh_io.corner_normals(mesh)).astype(np.float64)
            normals = np.where(changed[:, None], normals, current)
        marked = 0
        if selected_only or self.use_crease:
            # Blender averages custom normals over each of its fans: split its
            # fans wherever the new normals differ across an edge.
            split = a.edges_where_normals_differ(normals) & ~a.edge_sharp
            marked = int(split.sum())
            mesh_io.mark_sharp(mesh, split)
        mesh_io.set_custom_normals(mesh, a.to_loops(normals))
        return int(changed.sum()) if changed is not None else len(normals), marked


def _menu_entries(self, context):
    layout = self.layout
    layout.separator()
    for name, _description, _reference in _methods:
        op = layout.operator(MESH_OT_vn_recompute_normals.bl_idname, text="Recompute Normals (%s)" % name.upper())
        op.method = name.upper()


_classes = (VN_AddonPreferences, MESH_OT_vn_recompute_normals)
_menus = ("VIEW3D_MT_object", "VIEW3D_MT_edit_mesh_normals")


def register():
    global _methods, _load_error
    bpy.utils.register_class(VN_AddonPreferences)
    try:
        _methods = list(_library().methods)
        _load_error = ""
    except binding.VnError as e:
        # Still register, so that the preference can be fixed; the operator
        # reports the error when run.
        _methods, _load_error = [], str(e)
        print("vn:", e)
    items = [(n.upper(), n.upper(), "%s (%s)" % (d, r) if r else d) for n, d, r in _methods]
    if not items:
        items = [("MWA", "MWA", "vn library not loaded: " + _load_error)]
    default = "MWA" if any(i[0] == "MWA" for i in items) else items[0][0]
    MESH_OT_vn_recompute_normals.__annotations__["method"] = EnumProperty(
        name="Method", items=items, default=default, description="Weighting scheme")
    bpy.utils.register_class(MESH_OT_vn_recompute_normals)
    for m in _menus:
        getattr(bpy.types, m).append(_menu_entries)


def unregister():
    for m in _menus:
        getattr(bpy.types, m).remove(_menu_entries)
    for c in reversed(_classes):
        bpy.utils.unregister_class(c)
