"""The Blender add-on, in real Blender, headless:

    blender -b --factory-startup -noaudio --python-exit-code 1 \
        --python tests/blender/test_addon.py -- --zip build/vn_blender.zip

Installs the zip as a user does (a legacy add-on before 4.2, an extension
from 4.2), enables it, then checks that Blender's corner normals after the
operator equal the C library's per-corner normals (called through the
add-on's own ctypes binding on the same mesh data), stored per vertex when
no vertex is split and per corner otherwise, the same in Edit Mode as in
Object Mode, that sharp edges stay
sharp, that "selected only" leaves the other corners alone, that undo
restores the previous normals, and that a wrong library path is a clear
error report rather than a traceback. Live normals (issue 15): recomputed
once per edit (mesh data in Object Mode, leaving Edit or Sculpt Mode) with
every stored setting, never for their own write, a frame change or a
shape key's value, turned off and on, reported once when failing, and still
live after the file is saved and reopened. Meshes above PLAN_MIN_FACES
(issue 20): computed on a plan kept per mesh, equal bit for bit to the
computation without one, made again when the faces change, freed with the
mesh and on disabling. Then parity with Blender's
Weighted Normal modifier (issue 15): MWA = its Corner Angle mode, and the
add-on's Face Influence, Vertex Group and Invert = the modifier's. Any
failure raises (exit status 1).
"""

import contextlib
import importlib
import io
import math
import os
import shutil
import subprocess
import sys
import time

import bmesh
import bpy
import mathutils
import numpy as np

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
ZIP = args[args.index("--zip") + 1]
V = bpy.app.version
# Blender's custom normals are stored as two 16-bit angles in each fan's
# space: under 0.15 degree in fans of several corners, up to 0.27 degree at a
# corner alone in its fan (the welded sphere below), far less typically.
MAX_DEG, MEDIAN_DEG = 0.15, 0.01
failures = []
PRECISION = []  # per compare(): the worst angle Blender's storage of custom normals moved a corner


def r_ok(r):
    return r == {"FINISHED"}


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


# Background Blender has no undo stack until a script pushes a step: create
# it now, as the UI has one from the start (before any mode switch, after
# which undo's poll fails in background mode).
bpy.ops.ed.undo_push(message="test start")

# ------------------------------------------------------------------ install
t0 = time.perf_counter()
if V >= (4, 2, 0):
    # What extensions.blender.org runs on an upload; installing checks less
    # (a 69-character tagline installed, and failed this).
    v = subprocess.run([bpy.app.binary_path, "-b", "--factory-startup", "--command", "extension", "validate", ZIP],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
    check(v.returncode == 0 and "FATAL_ERROR" not in v.stdout,
          "blender --command extension validate accepts the zip: %s"
          % [l for l in v.stdout.splitlines() if "TOML" in l or "ERROR" in l])
    r = bpy.ops.extensions.package_install_files(filepath=ZIP, repo="user_default", enable_on_install=True)
    check(r == {"FINISHED"}, "extension installed from %s" % ZIP)
else:
    r = bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True)
    check(r == {"FINISHED"}, "legacy add-on installed from %s" % ZIP)
    bpy.ops.preferences.addon_enable(module="vn_normals")
module = [k for k in bpy.context.preferences.addons.keys() if k.split(".")[-1] == "vn_normals"]
check(len(module) == 1, "add-on enabled: %s" % module)
MODULE = module[0]
binding = importlib.import_module(MODULE + ".binding")
mesh_io = importlib.import_module(MODULE + ".mesh_io")
prefs = bpy.context.preferences.addons[MODULE].preferences
print("installed and enabled in %.2f s; Blender %s" % (time.perf_counter() - t0, bpy.app.version_string))
lib = binding.load_configured("")
check(lib.path == os.path.join(os.path.dirname(os.path.abspath(binding.__file__)), "lib", "libvn.so")
      and os.path.isfile(lib.path), "bundled library used: %s" % lib.path)
names = [m[0].upper() for m in lib.methods]
check(len(names) >= 7 and names[:2] == ["MWE", "MWA"], "schemes from the library: %s" % names)
props = bpy.ops.mesh.vn_recompute_normals.get_rna_type().properties
items = [i.identifier for i in props["method"].enum_items]
check(items == names, "operator method items are the library's schemes")
check(props["method"].default == "MWA", "default method MWA")
check(all(props["method"].enum_items[n].description for n in names), "descriptions from the library")
addon = importlib.import_module(MODULE)
check([(m[0], m[2], m[3]) for m in getattr(addon, "METHODS", ())] == [(n.upper(), d, r) for n, d, r in lib.methods],
      "the add-on's hard-coded schemes are the library's (identifiers, descriptions, references)")
check("not for shading" in props["method"].enum_items["MEWCSA"].description.lower(),
      "MEWCSA's description says it is not for shading")


class Recorder:
    """Stands in for a menu's layout: records the operators it is asked to draw."""

    def __init__(self):
        self.ops = []

    def operator(self, idname, **kw):
        self.ops.append((idname, kw.get("text")))
        return type("Props", (), {})()

    def __getattr__(self, _name):
        return lambda *a, **k: None


def menu_entries(menu):
    """(idname, text) of every operator the menu draws, in order, with this
    add-on's entries marked by a "vn:" prefix on the idname."""
    rec = Recorder()
    for f in getattr(bpy.types, menu)._dyn_ui_initialize():
        f(type("Menu", (), {"layout": rec})(), bpy.context)
    return [("vn:" + i if i == "mesh.vn_recompute_normals" else i, t) for i, t in rec.ops]


e = menu_entries("VIEW3D_MT_object")
ours = [k for k, (i, _) in enumerate(e) if i.startswith("vn:")]
check(len(ours) == 1 and e[ours[0] - 1][0] == "object.shade_flat"
      and e[ours[0]][1] == "Recompute Normals (MWA)",
      "Object menu: one entry, \"Recompute Normals (MWA)\", right after Shade Flat: %s" % e[max(0, ours[0] - 3):ours[0] + 2]
      if ours else "Object menu: no entry")
e = menu_entries("VIEW3D_MT_edit_mesh_normals")
check([x for x in e if x[0].startswith("vn:")] == [("vn:mesh.vn_recompute_normals", "Recompute Normals (MWA)")],
      "Edit Mode's Mesh > Normals: one entry: %s" % e[-2:])


# ------------------------------------------------------------------ helpers
def new_scene_object(make):
    bpy.ops.object.select_all(action="DESELECT")
    make()
    obj = bpy.context.active_object
    obj.select_set(True)
    return obj


def shade_smooth(mesh):
    mesh.polygons.foreach_set("use_smooth", np.ones(len(mesh.polygons), dtype=bool))
    mesh.update()


def split_faces(me):
    """Every face on its own vertices (as meshes imported in split chunks)."""
    bm = bmesh.new()
    bm.from_mesh(me)
    bmesh.ops.split_edges(bm, edges=bm.edges[:])
    bm.to_mesh(me)
    bm.free()


def blender_normals(mesh):
    return mesh_io.corner_normals(mesh).astype(np.float64)


def reference(mesh, method, crease=math.pi):
    """The C library's per-corner normals (through the add-on's binding) on
    this mesh, fans split at marked sharp edges and flat faces."""
    a = mesh_io.MeshArrays(mesh)
    # the flags independently of the add-on's own: marked edges and flat faces
    flags = a.edge_sharp[a.corner_edge] | ~a.face_smooth[a.face_of_corner]
    n, _ = lib.corner_normals(a.co, a.corner_vert, a.face_offsets, method.lower(), crease,
                              flags.astype(np.uint8))
    return a.to_loops(n)


def angles_deg(a, b):
    a = a / np.maximum(np.linalg.norm(a, axis=1), 1e-30)[:, None]
    b = b / np.maximum(np.linalg.norm(b, axis=1), 1e-30)[:, None]
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), (a * b).sum(axis=1)))


def compare(label, got, ref, max_deg=MAX_DEG, median_deg=MEDIAN_DEG):
    nonzero = np.linalg.norm(ref, axis=1) > 0.5  # zero: no face contributed; Blender keeps its own
    d = angles_deg(got[nonzero], ref[nonzero])
    worst, med = float(d.max(initial=0)), float(np.median(d)) if d.size else 0.0
    PRECISION.append(worst)
    check(nonzero.sum() > 0 and worst <= max_deg and med <= median_deg,
          "%s: %d corners (%d zero), max %.4f deg, median %.5f deg" % (
              label, nonzero.size, (~nonzero).sum(), worst, med))
    return d


# ------------------------------------------------------------------ meshes
rng = np.random.default_rng(9)


def ico_sphere():
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3, radius=1.0)


def jittered_uv_sphere():
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=1.0)
    me = bpy.context.active_object.data
    co = np.empty(len(me.vertices) * 3, dtype=np.float32)
    me.vertices.foreach_get("co", co)
    co += rng.uniform(-0.02, 0.02, co.size).astype(np.float32)
    me.vertices.foreach_set("co", co)


def torus_mixed():
    bpy.ops.mesh.primitive_torus_add(major_segments=24, minor_segments=12)
    me = bpy.context.active_object.data
    bm = bmesh.new()
    bm.from_mesh(me)
    bm.faces.ensure_lookup_table()
    bmesh.ops.triangulate(bm, faces=[f for i, f in enumerate(bm.faces) if i % 3 == 0])
    bm.to_mesh(me)
    bm.free()


def cube_sharp():
    bpy.ops.mesh.primitive_cube_add(size=2.0)
    me = bpy.context.active_object.data
    bm = bmesh.new()
    bm.from_mesh(me)
    bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=2, use_grid_fill=True)
    bm.to_mesh(me)
    bm.free()
    # the edges of the original cube's top face (z = 1, on its rim) are marked sharp
    co = np.array([v.co[:] for v in me.vertices])
    ev = np.array([e.vertices[:] for e in me.edges])
    top = (np.abs(co[ev][:, :, 2] - 1) < 1e-6).all(axis=1)
    rim = (np.abs(np.abs(co[ev][:, :, :2]) - 1) < 1e-6).any(axis=2).all(axis=1)
    me.edges.foreach_set("use_edge_sharp", top & rim)


def cylinder_ngon():
    bpy.ops.mesh.primitive_cylinder_add(vertices=24, depth=2.0, end_fill_type="NGON")


MESHES = [("ico sphere", ico_sphere), ("jittered UV sphere", jittered_uv_sphere),
          ("torus of triangles and quads", torus_mixed), ("cube with marked sharp edges", cube_sharp),
          ("cylinder with n-gon caps", cylinder_ngon)]

# ------------------------------------------------------------------ every scheme on every mesh
t0 = time.perf_counter()
for label, make in MESHES:
    obj = new_scene_object(make)
    me = obj.data
    shade_smooth(me)
    if label.startswith("cube"):
        me.polygons[0].use_smooth = False  # one flat-shaded face
    if V < (4, 1, 0):
        me.use_auto_smooth = True
        me.auto_smooth_angle = math.pi
    for method in names:
        r = bpy.ops.mesh.vn_recompute_normals(method=method)
        check(r == {"FINISHED"}, "%s %s: operator finished" % (label, method))
        compare("%s %s" % (label, method), blender_normals(me), reference(me, method))
    if label.startswith("cube"):
        # across each marked sharp edge, the corners at a shared vertex differ (90 degrees)
        bpy.ops.mesh.vn_recompute_normals()
        n = blender_normals(me)
        a = mesh_io.MeshArrays(me)
        k = np.flatnonzero(a.edge_sharp[a.corner_edge])  # corners whose outgoing edge is sharp
        vtx = a.corner_vert[k]
        diffs = []
        for c, v in zip(k[:8], vtx[:8]):
            same_v = np.flatnonzero(a.corner_vert == v)
            diffs.append(angles_deg(n[same_v], np.repeat(n[c][None], same_v.size, 0)).max())
        check(len(diffs) == 8 and min(diffs) > 45.0, "cube: marked sharp edges stay sharp (%s deg)"
              % np.round(diffs, 1).tolist())
    bpy.data.objects.remove(obj)
print("schemes x meshes in %.2f s" % (time.perf_counter() - t0))

# ------------------------------------------------------------------ write path: per vertex when nothing is split
paths = []
_set_custom_normals = mesh_io.set_custom_normals


def recording_set_custom_normals(*a, **k):
    paths.append(_set_custom_normals(*a, **k))
    return paths[-1]


mesh_io.set_custom_normals = recording_set_custom_normals  # the operator calls it through the module
# A lone sharp edge splits no fan (each end's fan goes round it the other way).
for label, split in (("smooth ico sphere", None), ("ico sphere, one sharp edge", None),
                     ("ico sphere, one flat face", "flat"), ("ico sphere, one face's edges sharp", "sharp")):
    obj = new_scene_object(ico_sphere)
    me = obj.data
    shade_smooth(me)
    if "one sharp edge" in label:
        me.edges[7].use_edge_sharp = True
    if split == "flat":
        me.polygons[5].use_smooth = False
    elif split == "sharp":
        for k in me.polygons[5].loop_indices:
            me.edges[me.loops[k].edge_index].use_edge_sharp = True
    if V < (4, 1, 0):
        me.use_auto_smooth = True
        me.auto_smooth_angle = math.pi
    paths.clear()
    r = bpy.ops.mesh.vn_recompute_normals(method="MWAAT")
    want = "corner" if split else "vertex"
    check(r == {"FINISHED"} and paths == [want], "%s: stored per %s (%s)" % (label, want, paths))
    got, ref = blender_normals(me), reference(me, "MWAAT")
    compare("%s, %s path" % (label, want), got, ref)
    if not split:
        # every corner of a vertex the library's (float32) normal, to storage precision
        d = angles_deg(got, ref)
        check(d.max() < 0.02, "%s: corner normals = library's, max %.5f deg" % (label, d.max()))
    else:
        a = mesh_io.MeshArrays(me)
        v = a.corner_vert[np.flatnonzero(~a.face_smooth[a.face_of_corner] | a.edge_sharp[a.corner_edge])[0]]
        at_v = got[a.to_loops(a.corner_vert == v)]
        check(angles_deg(at_v, np.repeat(at_v[:1], len(at_v), 0)).max() > 1.0,
              "%s: the split vertex keeps different corner normals" % label)
    bpy.data.objects.remove(obj)
mesh_io.set_custom_normals = _set_custom_normals

# ------------------------------------------------------------------ edit mode = object mode; undo in edit mode
obj = new_scene_object(jittered_uv_sphere)
shade_smooth(obj.data)
me_name = obj.data.name
twin = obj.copy()
twin.data = obj.data.copy()
bpy.context.collection.objects.link(twin)
bpy.ops.mesh.vn_recompute_normals(method="MWRELR")  # object mode, on obj only
object_mode = blender_normals(obj.data)
bpy.ops.object.select_all(action="DESELECT")
twin.select_set(True)
bpy.context.view_layer.objects.active = twin
bpy.ops.object.mode_set(mode="EDIT")
r = bpy.ops.mesh.vn_recompute_normals(method="MWRELR")
check(r == {"FINISHED"} and twin.mode == "EDIT", "edit mode: operator finished, still in Edit Mode")
bpy.ops.object.mode_set(mode="OBJECT")
d = angles_deg(blender_normals(twin.data), object_mode)
check(d.max() < 1e-4, "edit mode result = object mode result (max %.6f deg)" % d.max())
bpy.ops.object.mode_set(mode="EDIT")
bpy.ops.ed.undo_push(message="edit mode, before vn")
bpy.ops.mesh.vn_recompute_normals("EXEC_DEFAULT", True, method="MWE")
bpy.ops.object.mode_set(mode="OBJECT")
first = blender_normals(twin.data)
bpy.ops.object.mode_set(mode="EDIT")
bpy.ops.ed.undo_push(message="edit mode, between")
bpy.ops.mesh.vn_recompute_normals("EXEC_DEFAULT", True, method="MWELR")
bpy.ops.ed.undo()
bpy.ops.object.mode_set(mode="OBJECT")
restored = blender_normals(twin.data)
d = angles_deg(restored, first)
check(angles_deg(object_mode, first).max() > 0.1 and d.max() < 1e-3,
      "edit mode: undo restores the previous normals (max %.5f deg)" % d.max())
bpy.data.objects.remove(twin)
bpy.data.objects.remove(obj)

# Edit Mode without leaving it: the edit BMesh is read back from a Mesh copy
# (_load_edit_mesh), keeping selection, select mode, hidden faces and the
# active face; not when a script holds the BMesh or the mesh has shape keys
# (then the operator leaves Edit Mode and re-enters it).
reloads = []
_load_edit_mesh = addon._load_edit_mesh
addon._load_edit_mesh = lambda *a: (reloads.append(a[0].name), _load_edit_mesh(*a))
obj = new_scene_object(jittered_uv_sphere)
shade_smooth(obj.data)
ref = reference(obj.data, "MWSELR")
bpy.ops.object.mode_set(mode="EDIT")
bpy.ops.mesh.select_mode(type="EDGE")
bm = bmesh.from_edit_mesh(obj.data)
bm.faces.ensure_lookup_table()
for f in bm.faces[:10]:
    f.hide_set(True)
for f in bm.faces[20:40]:
    f.select_set(True)
bm.faces.active = bm.faces[30]
bm.select_history.add(bm.faces[25])
bmesh.update_edit_mesh(obj.data)
del bm, f
# the state as Blender's own trip out of Edit Mode and back leaves it (it
# selects the edges between selected vertices)
bpy.ops.object.mode_set(mode="OBJECT")
bpy.ops.object.mode_set(mode="EDIT")
state = lambda b: ([f.hide for f in b.faces], [e.select for e in b.edges], b.faces.active.index,
                   [b.select_history[i].index for i in range(len(b.select_history))], b.select_mode)
before = state(bmesh.from_edit_mesh(obj.data))
r = bpy.ops.mesh.vn_recompute_normals(method="MWSELR")
bm = bmesh.from_edit_mesh(obj.data)
bm.faces.ensure_lookup_table()
check(r_ok(r) and reloads == [obj.data.name] and obj.mode == "EDIT",
      "edit mode: read back into the edit mesh, never left (%s)" % reloads)
check(state(bm) == before and tuple(bpy.context.tool_settings.mesh_select_mode) == (False, True, False),
      "edit mode: hidden faces, selection, select mode, active face and select history kept")
held = bm  # a script holding the edit BMesh: Edit Mode is left and re-entered
del reloads[:]
r = bpy.ops.mesh.vn_recompute_normals(method="MWE")
check(r_ok(r) and not reloads and not held.is_valid and obj.mode == "EDIT",
      "edit mode, a script holding the BMesh: left and re-entered (its reference now invalid)")
del bm, held
bpy.ops.object.mode_set(mode="OBJECT")
compare("edit mode, twice, the second after leaving", blender_normals(obj.data), reference(obj.data, "MWE"))
obj.shape_key_add(name="Basis")
key = obj.shape_key_add(name="Key")
co = np.empty(len(obj.data.vertices) * 3, dtype=np.float32)
key.data.foreach_get("co", co)
key.data.foreach_set("co", co * 1.5)
obj.active_shape_key_index = 1
bpy.ops.object.mode_set(mode="EDIT")
r = bpy.ops.mesh.vn_recompute_normals(method="MWSELR")
bpy.ops.object.mode_set(mode="OBJECT")
after = np.empty_like(co)
key.data.foreach_get("co", after)
check(r_ok(r) and not reloads and np.array_equal(after, co * 1.5),
      "edit mode with shape keys: left and re-entered, the active key's shape kept")
addon._load_edit_mesh = _load_edit_mesh
me = obj.data
bpy.data.objects.remove(obj)
bpy.data.meshes.remove(me)

# ------------------------------------------------------------------ crease angle, weld by position
obj = new_scene_object(cylinder_ngon)
shade_smooth(obj.data)
ref = reference(obj.data, "MWA", math.radians(30))
r = bpy.ops.mesh.vn_recompute_normals(method="MWA", use_crease=True, crease_angle=math.radians(30))
check(r == {"FINISHED"}, "crease 30 deg: operator finished")
compare("crease 30 deg: cylinder, caps split off", blender_normals(obj.data), ref)
check(np.count_nonzero(mesh_io.MeshArrays(obj.data).edge_sharp) == 48, "crease 30 deg: the 48 rim edges marked sharp")
bpy.data.objects.remove(obj)

obj = new_scene_object(jittered_uv_sphere)
shade_smooth(obj.data)
whole = reference(obj.data, "MWSELR")
a0 = mesh_io.MeshArrays(obj.data)
split_faces(obj.data)
a1 = mesh_io.MeshArrays(obj.data)
check(len(obj.data.vertices) == a1.corner_vert.size, "weld: the sphere split into %d vertices" % a1.corner_vert.size)
# Keep Hard Edges off: the jitter tilts the thin pole faces' normals by more than 30 degrees
r = bpy.ops.mesh.vn_recompute_normals(method="MWSELR", weld=True, weld_distance=0.0, weld_keep_hard=False)
check(r == {"FINISHED"}, "weld: operator finished")


def by_face_and_position(a, per_loop):
    """per_loop's rows sorted by (face, corner position): comparable across splits."""
    co = a.co[a.corner_vert].astype(np.float64)
    order = np.lexsort((co[:, 2], co[:, 1], co[:, 0], a.face_of_corner))
    return a.from_loops(per_loop)[order]


# Every corner is now a fan of its own, which Blender stores less precisely
# (0.27 deg at a pole corner of 3.4 here): a looser worst case.
compare("weld: split sphere welded = whole sphere", by_face_and_position(a1, blender_normals(obj.data)),
        by_face_and_position(a0, whole), max_deg=0.5)
bpy.data.objects.remove(obj)

# ------------------------------------------------------------------ object mode: all selected meshes at once
a_obj = new_scene_object(ico_sphere)
b_obj = new_scene_object(cylinder_ngon)
for o in (a_obj, b_obj):
    shade_smooth(o.data)
    o.select_set(True)
r = bpy.ops.mesh.vn_recompute_normals(method="MWSELR")
check(r == {"FINISHED"}, "two selected objects: operator finished")
for o in (a_obj, b_obj):
    compare("two selected objects, " + o.name, blender_normals(o.data), reference(o.data, "MWSELR"))
bpy.data.objects.remove(a_obj)
bpy.data.objects.remove(b_obj)

# ------------------------------------------------------------------ edit mode, selected only
def edit_top_third(me):
    """Edit Mode with the first third of the faces (a sphere's top) selected."""
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_mode(type="FACE")
    bpy.ops.mesh.select_all(action="DESELECT")
    bm = bmesh.from_edit_mesh(me)
    bm.faces.ensure_lookup_table()
    for f in bm.faces[: len(bm.faces) // 3]:
        f.select_set(True)
    bmesh.update_edit_mesh(me)


obj = new_scene_object(jittered_uv_sphere)
me = obj.data
shade_smooth(me)
bpy.ops.mesh.vn_recompute_normals(method="MWE")
before = blender_normals(me)
edit_top_third(me)
r = bpy.ops.mesh.vn_recompute_normals(method="MWAAT", selected_only=True)
check(r == {"FINISHED"}, "edit mode, selected only: operator finished")
bpy.ops.object.mode_set(mode="OBJECT")
after = blender_normals(me)
a = mesh_io.MeshArrays(me)
changed = a.to_loops(a.face_select[a.face_of_corner].astype(np.uint8)).astype(bool)
check(changed.any() and not changed.all(), "selected only: %d of %d corners selected" % (changed.sum(), changed.size))
# unchanged up to storage precision: where the selection's border splits a
# fan, Blender stores the kept normals again in the new, smaller fan's space
compare("selected only: other corners unchanged", after[~changed], before[~changed])
# the selected corners get the full mesh's MWAAT normals (no selection-made seams)
obj2 = obj.copy()
obj2.data = me.copy()
obj2.data.edges.foreach_set("use_edge_sharp", np.zeros(len(me.edges), dtype=bool))
ref = reference(obj2.data, "MWAAT")
compare("selected only: selected corners", after[changed], ref[changed])
check(angles_deg(after[changed], before[changed]).max() > 0.1, "selected only: selected corners changed")
bpy.data.objects.remove(obj2)
bpy.data.objects.remove(obj)

# ------------------------------------------------------------------ undo
obj = new_scene_object(torus_mixed)
me_name = obj.data.name
shade_smooth(obj.data)
bpy.ops.ed.undo_push(message="before vn")
# undo=True: the operator pushes its undo step as when run from the UI
bpy.ops.mesh.vn_recompute_normals("EXEC_DEFAULT", True, method="MWE")
first = blender_normals(bpy.data.meshes[me_name])
bpy.ops.mesh.vn_recompute_normals("EXEC_DEFAULT", True, method="MWELR")
second = blender_normals(bpy.data.meshes[me_name])
check(angles_deg(first, second).max() > 0.1, "undo: the two schemes differ")
bpy.ops.ed.undo()
restored = blender_normals(bpy.data.meshes[me_name])
d = angles_deg(restored, first)
check(d.max() < 1e-3, "undo restores the previous normals (max %.5f deg)" % d.max())
bpy.data.objects.remove(bpy.data.objects[obj.name] if obj.name in bpy.data.objects else obj)

# ------------------------------------------------------------------ wrong library path
obj = new_scene_object(ico_sphere)
prefs = bpy.context.preferences.addons[MODULE].preferences
prefs.library_path = "/nonexistent/libvn.so"
try:
    bpy.ops.mesh.vn_recompute_normals()
    message = ""
except RuntimeError as e:
    message = str(e)
print("wrong library path reports: %r" % message)
check("/nonexistent/libvn.so" in message and "does not exist" in message and "preference" in message
      and "Traceback" not in message, "wrong library path: a clear error report, no traceback")
prefs.library_path = ""
check(bpy.ops.mesh.vn_recompute_normals() == {"FINISHED"}, "library path fixed: operator works again")

# ------------------------------------------------------------------ issue 15
def sphere_smooth():
    obj = new_scene_object(jittered_uv_sphere)
    shade_smooth(obj.data)
    if V < (4, 1, 0):
        obj.data.use_auto_smooth = True
        obj.data.auto_smooth_angle = math.pi
    return obj


def run_message(**props):
    """The operator's result, or the error it raised (also for a property unknown before issue 15)."""
    try:
        return str(bpy.ops.mesh.vn_recompute_normals(**props))
    except (RuntimeError, TypeError) as e:
        return "%s: %s" % (type(e).__name__, e)


def face_normal_angles(me):
    """Per loop: degrees between Blender's corner normal and its face's normal."""
    fn = np.empty(len(me.polygons) * 3)
    me.polygons.foreach_get("normal", fn)
    a = mesh_io.MeshArrays(me)
    return angles_deg(blender_normals(me), a.to_loops(fn.reshape(-1, 3)[a.face_of_corner]))


def cube_smooth():
    bpy.ops.mesh.primitive_cube_add(size=2.0)
    shade_smooth(bpy.context.active_object.data)


# Auto Smooth (3.4-4.0) splits at its angle; Smooth by Angle (4.1+) marks sharp edges
obj = new_scene_object(cube_smooth)
me = obj.data
if V < (4, 1, 0):
    me.use_auto_smooth = True
    me.auto_smooth_angle = math.radians(30)
    how = "Auto Smooth 30 deg"
else:
    bpy.ops.object.shade_smooth_by_angle(angle=math.radians(30))
    how = "Smooth by Angle 30 deg"
check(r_ok(bpy.ops.mesh.vn_recompute_normals()), how + ": operator finished")
d = face_normal_angles(me)
check(d.max() < 0.5, "%s: cube corners keep their faces' normals (max %.2f deg)" % (how, d.max()))
bpy.data.objects.remove(obj)

obj = new_scene_object(lambda: bpy.ops.mesh.primitive_cylinder_add(vertices=32, depth=2.0))
me = obj.data
bm = bmesh.new()
bm.from_mesh(me)
rim = [e for e in bm.edges if abs(e.verts[0].co.z - e.verts[1].co.z) < 1e-6]
bmesh.ops.bevel(bm, geom=rim, offset=0.1, segments=2, affect="EDGES", profile=0.5)
bm.to_mesh(me)
bm.free()
shade_smooth(me)
if V < (4, 1, 0):
    me.use_auto_smooth = True
    me.auto_smooth_angle = math.radians(30)
else:
    bpy.ops.object.shade_smooth_by_angle(angle=math.radians(30))
own = blender_normals(me)  # Blender's own shading: angle weighted, split at 30 deg
check(r_ok(bpy.ops.mesh.vn_recompute_normals(method="MWA")), how + ", bevelled cylinder: operator finished")
compare(how + ", bevelled cylinder: MWA = Blender's own shading", blender_normals(me), own, max_deg=0.5)
bpy.data.objects.remove(obj)

# Selected Only, then a default run on the whole mesh: no seam left behind
obj = sphere_smooth()
me = obj.data
bpy.ops.mesh.vn_recompute_normals()
fresh = blender_normals(me)
edit_top_third(me)
bpy.ops.mesh.vn_recompute_normals(method="MWAAT", selected_only=True)
bpy.ops.object.mode_set(mode="OBJECT")
border = int(mesh_io.MeshArrays(me).edge_sharp.sum())
bpy.ops.mesh.vn_recompute_normals()
d = angles_deg(blender_normals(me), fresh)
check(border > 0 and not mesh_io.MeshArrays(me).edge_sharp.any() and d.max() < 0.5,
      "selected only (%d border edges marked), then a default run: no marks left, max %.3f deg from a "
      "fresh default run" % (border, d.max()))
bpy.data.objects.remove(obj)

# Crease 40 then 60 degrees: exactly the 60 degree set stays marked
obj = new_scene_object(lambda: bpy.ops.mesh.primitive_cylinder_add(vertices=7, depth=2.0))
me = obj.data
shade_smooth(me)
me.edges[0].use_edge_sharp = True  # the user's own mark, kept throughout
user = mesh_io.MeshArrays(me).edge_sharp.copy()
bpy.ops.mesh.vn_recompute_normals(use_crease=True, crease_angle=math.radians(40))
n40 = int(mesh_io.MeshArrays(me).edge_sharp.sum())
bpy.ops.mesh.vn_recompute_normals(use_crease=True, crease_angle=math.radians(60))
sharp60 = mesh_io.MeshArrays(me).edge_sharp
fn = np.array([p.normal[:] for p in me.polygons])
dihedral = np.zeros(len(me.edges))
edge_faces = {}
for p in me.polygons:
    for k in p.edge_keys:
        edge_faces.setdefault(k, []).append(p.index)
for e in me.edges:
    f = edge_faces[e.key]
    dihedral[e.index] = np.degrees(np.arccos(np.clip(fn[f[0]] @ fn[f[1]], -1, 1)))
check(np.array_equal(sharp60, (dihedral > 60) | user),
      "crease 40 (%d marked) then 60: marked = the user's + edges over 60 deg (%d, expected %d)"
      % (n40, sharp60.sum(), ((dihedral > 60) | user).sum()))
bpy.ops.mesh.vn_recompute_normals()
check(np.array_equal(mesh_io.MeshArrays(me).edge_sharp, user), "then a default run: only the user's mark stays")
bpy.data.objects.remove(obj)

# Weld by Position keeps hard edges: a cube split into its faces stays a cube
obj = new_scene_object(cube_smooth)
me = obj.data
split_faces(me)
check(r_ok(bpy.ops.mesh.vn_recompute_normals(weld=True)), "weld, split cube: operator finished")
d = face_normal_angles(me)
check(d.max() < 0.5, "weld keeps the split cube's hard edges (max %.2f deg from face normals)" % d.max())
m = run_message(weld=True, weld_keep_hard=False)
d = face_normal_angles(me)
check(m == "{'FINISHED'}" and abs(d.max() - 54.7356) < 0.5, "weld without Keep Hard Edges joins them (%.2f deg)" % d.max())
bpy.data.objects.remove(obj)

# Weld by Position on an imported glTF (the Khronos Duck): the file stores
# its hard edges as vertices split at one place with different normals, and
# its UV seams as split vertices with one normal. Read here as Blender's
# importer does it (the split vertices kept, the file's normals as custom
# normals), without the importer: 3.4's fails with Debian's numpy.
def read_glb(path):
    """POSITION, NORMAL and the indices of a GLB's first primitive (float32, uint16/32)."""
    import json
    import struct
    data = open(path, "rb").read()
    n = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20:20 + n])
    binary = data[20 + n + 8:]

    def accessor(i):
        a = doc["accessors"][i]
        view = doc["bufferViews"][a["bufferView"]]
        dtype = {5126: np.float32, 5123: np.uint16, 5125: np.uint32}[a["componentType"]]
        width = {"SCALAR": 1, "VEC3": 3}[a["type"]]
        start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        stride = view.get("byteStride", np.dtype(dtype).itemsize * width)
        rows = np.lib.stride_tricks.as_strided(np.frombuffer(binary, dtype=np.uint8, offset=start),
                                               (a["count"], np.dtype(dtype).itemsize * width), (stride, 1))
        return np.ascontiguousarray(rows).view(dtype).reshape(a["count"], width)

    prim = doc["meshes"][0]["primitives"][0]
    return (accessor(prim["attributes"]["POSITION"]), accessor(prim["attributes"]["NORMAL"]),
            accessor(prim["indices"]).reshape(-1, 3))


def duck_weld(obj, label):
    """Weld with and without Keep Hard Edges on obj, which holds the Duck with
    the file's normals as custom normals."""
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    me = obj.data
    if V < (4, 1, 0):  # 3.4's importer leaves Auto Smooth at 30 degrees, which alone splits these edges
        me.auto_smooth_angle = math.pi
    # corners of two faces at one position: hard where the file's normals differ by over 30 degrees
    a = mesh_io.MeshArrays(me)
    key = np.unique(a.co, axis=0, return_inverse=True)[1].ravel()[a.corner_vert]
    pos_order = np.argsort(key, kind="stable")
    pairs = np.flatnonzero(key[pos_order][1:] == key[pos_order][:-1])
    loop = a.from_loops(np.arange(a.corner_vert.size))  # loop[corner]
    c0, c1 = loop[pos_order[pairs]], loop[pos_order[pairs + 1]]
    file_loop = blender_normals(me)
    file_deg = angles_deg(file_loop[c0], file_loop[c1])
    loop_vert = a.to_loops(a.corner_vert)
    hard, seam = file_deg > 30, (file_deg < 0.5) & (loop_vert[c0] != loop_vert[c1])  # 0.5: storage precision
    check(hard.sum() > 50 and seam.sum() > 50, "%s: %d corner pairs across hard edges (%.0f-%.0f deg), %d across UV seams"
          % (label, hard.sum(), file_deg[hard].min(), file_deg[hard].max(), seam.sum()))
    check(r_ok(bpy.ops.mesh.vn_recompute_normals(weld=True)), "%s, weld: operator finished" % label)
    got = blender_normals(me)
    d = angles_deg(got[c0], got[c1])
    # recomputed from the geometry, a hard edge's two normals need not keep the file's angle, but stay well apart
    check(d[hard].min() > 10 and d[seam].max() < 0.5,
          "%s, weld: hard edges stay hard (min %.1f, median %.1f deg), UV seams closed (max %.3f deg)"
          % (label, d[hard].min(), np.median(d[hard]), d[seam].max()))
    check(r_ok(bpy.ops.mesh.vn_recompute_normals(weld=True, weld_keep_hard=False)),
          "%s, weld without Keep Hard Edges" % label)
    got = blender_normals(me)
    d = angles_deg(got[c0], got[c1])
    check(d[hard].max() < 0.5, "%s, weld without Keep Hard Edges: hard edges joined (max %.3f deg)"
          % (label, d[hard].max()))
    bpy.data.objects.remove(obj)
    bpy.data.meshes.remove(me)


duck = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "Duck.glb")
co, file_normals, tris = read_glb(duck)
me = bpy.data.meshes.new("Duck")
me.from_pydata(co.tolist(), [], tris.tolist())
shade_smooth(me)
if V < (4, 1, 0):
    me.use_auto_smooth = True
me.normals_split_custom_set_from_vertices(file_normals / np.linalg.norm(file_normals, axis=1)[:, None])
obj = bpy.data.objects.new("Duck", me)
bpy.context.collection.objects.link(obj)
duck_weld(obj, "Duck")
if V >= (4, 1, 0):  # Blender's own importer (3.4's fails with Debian's numpy)
    bpy.ops.object.select_all(action="DESELECT")
    check(r_ok(bpy.ops.import_scene.gltf(filepath=duck)), "Duck imported by Blender's glTF importer")
    duck_weld(next(o for o in bpy.context.selected_objects if o.type == "MESH"), "Duck (imported)")

# Two objects sharing one mesh: computed once
a_obj = sphere_smooth()
b_obj = a_obj.copy()
bpy.context.collection.objects.link(b_obj)
b_obj.select_set(True)
calls = []
real = binding.Library.corner_normals
binding.Library.corner_normals = lambda self, *a, **k: calls.append(1) or real(self, *a, **k)
try:
    r = bpy.ops.mesh.vn_recompute_normals()
finally:
    binding.Library.corner_normals = real
check(r_ok(r) and len(calls) == 1, "two objects, one mesh: computed %d time(s)" % len(calls))
bpy.data.objects.remove(b_obj)

# The menu entry names the method it will run: the last one used (Blender
# keeps the settings of operators run as the UI runs them: with undo)
check(r_ok(bpy.ops.mesh.vn_recompute_normals("EXEC_DEFAULT", True, method="MWSELR")), "MWSELR run")
e = [x for x in menu_entries("VIEW3D_MT_object") if x[0].startswith("vn:")]
check(e == [("vn:mesh.vn_recompute_normals", "Recompute Normals (MWSELR)")], "the entry now says MWSELR: %s" % e)
check(r_ok(bpy.ops.mesh.vn_recompute_normals("EXEC_DEFAULT", True, method="MWA")), "MWA run")

# Subdivision Surface's default settings throw custom normals away: a warning names the fix
mod = a_obj.modifiers.new("Subdivision", "SUBSURF")
w = addon._subsurf_warnings(a_obj) if hasattr(addon, "_subsurf_warnings") else []
check(len(w) == 1 and a_obj.name in w[0] and "Subdivision" in w[0] and "use_custom_normals" in w[0],
      "live Subdivision Surface: warning %s" % w)
mod.use_custom_normals = True
check(addon._subsurf_warnings(a_obj) == [] if w else False, "no warning once Use Custom Normals is on")
bpy.data.objects.remove(a_obj)

# Nothing selected: greyed out, saying why (the poll message)
bpy.ops.object.select_all(action="DESELECT")
m = run_message()
check(m.startswith("RuntimeError") and "No mesh object selected" in m,
      "nothing selected: not run (%s)" % m.strip())

# Library path errors say what is wrong
obj = sphere_smooth()
tmp = os.path.join(os.environ.get("TMPDIR", "/tmp"), "vn15")
os.makedirs(tmp, exist_ok=True)
other = os.path.join(tmp, "libfilter_other.so")  # an ELF library that is not vn's
shutil.copy(np.core._multiarray_umath.__file__, other)


prefs.library_path = tmp
m = run_message()
check("is a directory" in m and "does not exist" not in m, "library path a directory: %s" % m.strip())
prefs.library_path = other
m = run_message()
maps = open("/proc/self/maps").read()
check("not a vn library" in m and "vn_version" in m and "too old" not in m and other not in maps,
      "library path another library, not loaded: %s" % m.strip())
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(tmp, "scene.blend"))
shutil.copy(lib.path, os.path.join(tmp, "libvn_copy.so"))
prefs.library_path = "//libvn_copy.so"
m = run_message()
check(m == "{'FINISHED'}", "library path relative to the .blend (//libvn_copy.so): %s" % m.strip())
prefs.library_path = ""

# The library failing to load at enable time: the menus and schemes stay, the operator reports it
os.environ[binding.ENV_VAR] = "/nonexistent/libvn.so"
bpy.ops.preferences.addon_disable(module=MODULE)
bpy.ops.preferences.addon_enable(module=MODULE)
items = [i.identifier for i in bpy.ops.mesh.vn_recompute_normals.get_rna_type().properties["method"].enum_items]
check(items == names, "library not loadable at enable: all schemes offered (%s)" % items)
check(sum(i.startswith("vn:") for i, _ in menu_entries("VIEW3D_MT_object")) == 1,
      "library not loadable at enable: menu entry there")
m = run_message(method="MWE")
check(m.startswith("RuntimeError") and "does not exist" in m, "...and running it reports: %s" % m.strip())
del os.environ[binding.ENV_VAR]
check(run_message(method="MWE") == "{'FINISHED'}", "library fixed: operator works without re-enabling")
prefs = bpy.context.preferences.addons[MODULE].preferences
bpy.data.objects.remove(obj)

# Linked data is refused, local copies work, and the result survives save + reopen
for o in list(bpy.data.objects):
    bpy.data.objects.remove(o)
libfile = os.path.join(tmp, "library.blend")
src = sphere_smooth()
src.name = src.data.name = "LibSphere"
bpy.data.libraries.write(libfile, {src, src.data}, fake_user=True)
bpy.data.objects.remove(src)
bpy.data.meshes.remove(bpy.data.meshes["LibSphere"])
with bpy.data.libraries.load(libfile, link=True) as (data_from, data_to):
    data_to.objects = ["LibSphere"]
linked = data_to.objects[0]
bpy.context.collection.objects.link(linked)
bpy.ops.object.select_all(action="DESELECT")
linked.select_set(True)
bpy.context.view_layer.objects.active = linked
m = run_message()
check(m != "{'FINISHED'}", "linked mesh alone: not run (%s)" % m.strip())
local = sphere_smooth()
local.name = "LocalSphere"
linked.select_set(True)
check(r_ok(bpy.ops.mesh.vn_recompute_normals(method="MWE")), "linked + local mesh: the local one done")
local_normals = blender_normals(local.data)
made = bpy.data.objects["LibSphere"].copy()
made.data = made.data.copy()  # a local copy of the linked object and mesh
made.name = "MadeLocal"
bpy.context.collection.objects.link(made)
bpy.ops.object.select_all(action="DESELECT")
made.select_set(True)
check(r_ok(bpy.ops.mesh.vn_recompute_normals(method="MWE")), "local copy of linked data: operator finished")
made_normals = blender_normals(made.data)
# Library overrides: Blender saves an override's changed properties, not its
# geometry, so neither a linked mesh under an overridden object nor an
# overridden mesh can keep normals; Make Local (objects and data) can.
coll = bpy.data.collections.new("LibColl")
src = sphere_smooth()
src.name = src.data.name = "OvrSphere"
bpy.context.collection.objects.unlink(src)
coll.objects.link(src)
bpy.data.libraries.write(os.path.join(tmp, "library_coll.blend"), {coll}, fake_user=True)
bpy.data.objects.remove(src)
bpy.data.collections.remove(coll)
with bpy.data.libraries.load(os.path.join(tmp, "library_coll.blend"), link=True) as (data_from, data_to):
    data_to.collections = ["LibColl"]
data_to.collections[0].override_hierarchy_create(bpy.context.scene, bpy.context.view_layer, do_fully_editable=True)
ovr = next(o for o in bpy.data.objects if o.override_library is not None and o.name.startswith("OvrSphere"))
bpy.ops.object.select_all(action="DESELECT")
ovr.select_set(True)
bpy.context.view_layer.objects.active = ovr
check(ovr.data.library is not None, "library override object: its mesh is linked")
m = run_message()
check(m != "{'FINISHED'}" and "is linked from library_coll.blend" in m, "override object, linked mesh: not run (%s)" % m.strip())
ovr_mesh = ovr.data.override_create(remap_local_usages=True)
check(ovr.data == ovr_mesh and ovr_mesh.override_library is not None, "overridden mesh")
m = run_message()
check(m != "{'FINISHED'}" and "is a library override" in m, "overridden mesh: not run (%s)" % m.strip())
check(r_ok(bpy.ops.object.make_local(type="SELECT_OBDATA")) and ovr.data.override_library is None
      and ovr.data.library is None, "Make Local > Selected Objects and Data")
check(r_ok(bpy.ops.mesh.vn_recompute_normals(method="MWE")), "made local: operator finished")
ovr_name, ovr_normals = ovr.name, blender_normals(ovr.data)
scene = os.path.join(tmp, "linked.blend")
bpy.ops.wm.save_as_mainfile(filepath=scene)
bpy.ops.wm.open_mainfile(filepath=scene)
o = bpy.data.objects
check(not o["LibSphere"].data.has_custom_normals, "after reopening: the linked mesh has no custom normals")
check(o["LocalSphere"].data.has_custom_normals and angles_deg(blender_normals(o["LocalSphere"].data),
                                                               local_normals).max() < 1e-3,
      "after reopening: the local mesh keeps its normals")
check(o["MadeLocal"].data.has_custom_normals and angles_deg(blender_normals(o["MadeLocal"].data),
                                                            made_normals).max() < 1e-3,
      "after reopening: the local copy keeps its normals")
check(o[ovr_name].data.has_custom_normals and angles_deg(blender_normals(o[ovr_name].data), ovr_normals).max() < 1e-3,
      "after reopening: the override made local keeps its normals")
# ------------------------------------------------------------------ issue 15: live normals
# Live meshes are recomputed by a depsgraph_update_post handler. Background
# Blender (-b) has no event loop: nothing evaluates the depsgraph between two
# lines of this script, so the handler runs when the script asks
# (view_layer.update(): settle() below) or an operator evaluates it (mode_set,
# opening a file do); in the UI the event loop does it after every edit.
t0 = time.perf_counter()
addon = importlib.import_module(MODULE)  # the add-on was disabled and enabled above
prefs = bpy.context.preferences.addons[MODULE].preferences
for o in list(bpy.data.objects):
    bpy.data.objects.remove(o)


def settle():
    bpy.context.view_layer.update()


def recomputed():
    return addon.live_stats["recomputed"]


def move_vertices(me, amount, seed):
    """Moves every vertex by up to amount in each coordinate (mesh data, Object Mode)."""
    co = np.empty(len(me.vertices) * 3, dtype=np.float32)
    me.vertices.foreach_get("co", co)
    co += np.random.default_rng(seed).uniform(-amount, amount, co.size).astype(np.float32)
    me.vertices.foreach_set("co", co)
    me.update()


def positions(me):
    co = np.empty((len(me.vertices), 3), dtype=np.float32)
    me.vertices.foreach_get("co", co.ravel())
    return co


def transform_vertices(me, matrix):
    """A linear map of every vertex (flat faces stay flat)."""
    me.vertices.foreach_set("co", (positions(me) @ np.float32(matrix).T).ravel())
    me.update()


def stale_deg(me, method, crease=math.pi):
    """The worst corner's angle from the library's normals for the mesh as it is now."""
    return angles_deg(blender_normals(me), reference(me, method, crease)).max()


def our_handlers():
    return [f for f in bpy.app.handlers.depsgraph_update_post if f.__name__ == "_on_depsgraph_update"]


# Live off (the default): normals made by the operator go stale when vertices move
obj = sphere_smooth()
me = obj.data
check(r_ok(bpy.ops.mesh.vn_recompute_normals(method="MWSELR")), "live off: operator finished")
settle()
n0, checked0 = recomputed(), addon.live_stats["checked"]
move_vertices(me, 0.03, 1)
settle()
d = stale_deg(me, "MWSELR")
check(not me.vn_live.live and d > 3 and recomputed() == n0 and addon.live_stats["checked"] == checked0,
      "live off: moved vertices leave the normals stale (%.1f deg off), nothing checked or recomputed" % d)
bpy.data.objects.remove(obj)

# Live on: the same edit recomputes them, once
obj = sphere_smooth()
me = obj.data
n0 = recomputed()
r = bpy.ops.mesh.vn_recompute_normals(method="MWSELR", live=True)
check(r_ok(r) and me.vn_live.live and me.vn_live.method == "MWSELR", "live on: stored on the mesh (%s)"
      % me.vn_live.method)
settle()  # evaluates the operator's own write
check(recomputed() == n0, "live on: the operator's own write is not recomputed")
move_vertices(me, 0.03, 1)
settle()
compare("live on: vertices moved in Object Mode (mesh data), recomputed", blender_normals(me),
        reference(me, "MWSELR"))
check(recomputed() == n0 + 1, "live on: one edit, one recompute (%d)" % (recomputed() - n0))
checked0 = addon.live_stats["checked"]
settle()  # nothing tagged: the recompute's own write does not come back (no loop)
me.update()  # an update that changes nothing: checked, not recomputed
settle()
obj.location.x += 1.0  # moving the object is no edit of its mesh
settle()
check(recomputed() == n0 + 1 and addon.live_stats["checked"] == checked0 + 1,
      "live on: no recompute of its own write, of an update without change, of an object move "
      "(%d recomputes, %d checks)" % (recomputed() - n0 - 1, addon.live_stats["checked"] - checked0))
move_vertices(me, 0.03, 2)
settle()
compare("live on: a second edit", blender_normals(me), reference(me, "MWSELR"))
check(recomputed() == n0 + 2, "live on: two edits, two recomputes (%d)" % (recomputed() - n0))

# The panel's tick and settings: off leaves normals stale, on and a new method recompute at once
me.vn_live.live = False
move_vertices(me, 0.03, 3)
settle()
d = stale_deg(me, "MWSELR")
check(d > 3 and recomputed() == n0 + 2, "live ticked off: an edit leaves them stale (%.1f deg)" % d)
me.vn_live.live = True
compare("live ticked on: recomputed at once", blender_normals(me), reference(me, "MWSELR"))
me.vn_live.method = "MWE"
compare("live method changed to MWE: recomputed at once", blender_normals(me), reference(me, "MWE"))
check(recomputed() == n0 + 4, "tick + method: two recomputes (%d)" % (recomputed() - n0 - 2))


class Layout:
    """Stands in for a panel's layout: records the properties drawn (and reads them)."""

    def __init__(self):
        self.props, self.labels = [], []

    def prop(self, data, name, **kw):
        self.props.append(name)
        getattr(data, name)

    def prop_search(self, data, name, *a, **kw):
        self.prop(data, name)

    def label(self, text="", **kw):
        self.labels.append(text)

    def __getattr__(self, _name):
        return lambda *a, **k: self


lay = Layout()
panel = type("Panel", (), {"layout": lay})()
fake_context = type("Context", (), {"mesh": me, "object": obj})()
addon.DATA_PT_vn_live.draw_header(panel, fake_context)
addon.DATA_PT_vn_live.draw(panel, fake_context)
check(lay.props == ["live"] + list(addon.SETTINGS), "vn Live Normals panel draws the tick and %s" % lay.props[1:])

class Invoked:
    """Stands in for the operator invoked from a menu (background Blender calls execute, not
    invoke): records the properties invoke sets; the caller's are_set stay as they are."""

    def __init__(self, **are_set):
        self.__dict__.update(live=False, method="MWA", properties=self)
        self.__dict__.update(are_set)
        self.are_set = set(are_set)

    def is_property_set(self, name):
        return name in self.are_set

    def execute(self, context):
        return {"FINISHED"}


# Running the operator: from the menu (invoke) a live mesh starts from its settings, Live ticked;
# run with Live off it is no longer live
op = Invoked()
addon.MESH_OT_vn_recompute_normals.invoke(op, bpy.context, None)
op_set = Invoked(method="MWAAT")
addon.MESH_OT_vn_recompute_normals.invoke(op_set, bpy.context, None)
check(op.live and op.method == "MWE" and op.use_crease is False and op_set.method == "MWAAT" and op_set.live,
      "invoked on a live mesh: starts from its settings (%s), Live ticked (%s); a method the caller set wins (%s)"
      % (op.method, op.live, op_set.method))
op.layout = lay = Layout()
addon.MESH_OT_vn_recompute_normals.draw(op, bpy.context)
check(lay.props == list(addon.SETTINGS) + ["live"], "redo panel (Object Mode) draws %s" % lay.props)
check(r_ok(bpy.ops.mesh.vn_recompute_normals(method="MWAAT")) and not me.vn_live.live,
      "run again with Live off: no longer live")
move_vertices(me, 0.03, 4)
settle()
d = stale_deg(me, "MWAAT")
check(d > 3 and recomputed() == n0 + 4, "...and an edit leaves it stale (%.1f deg, %d recomputes)"
      % (d, recomputed() - n0 - 4))
bpy.data.objects.remove(obj)

# Every setting is stored; Crease and Weld are used by the live recomputes
# (Face Influence without face strengths and every vertex by an inverted absent group: no effect)
props = dict(method="MWRELR", keep_sharp=False, use_crease=True, crease_angle=math.radians(40.0), weld=True,
             weld_distance=2e-4, weld_keep_hard=False, use_face_influence=True, vertex_group="none",
             invert_vertex_group=True)
obj = sphere_smooth()
me = obj.data
bpy.ops.mesh.vn_recompute_normals(live=True, **props)
got = {k: getattr(me.vn_live, k) for k in props}
check(set(props) == set(addon.SETTINGS) and all(
      abs(got[k] - v) < 1e-6 if isinstance(v, float) else got[k] == v for k, v in props.items()),
      "live: every setting stored on the mesh: %s" % got)
bpy.data.objects.remove(obj)

obj = new_scene_object(cube_smooth)  # a smooth-shaded cube: Crease 30 gives its faces' normals
me = obj.data
bpy.ops.mesh.vn_recompute_normals(method="MWA", use_crease=True, crease_angle=math.radians(30), live=True)
transform_vertices(me, [[1.0, 0.0, 0.5], [0.2, 1.3, 0.0], [0.0, 0.3, 2.0]])  # sheared
settle()
d = face_normal_angles(me)
ref = reference(me, "MWA", math.radians(30))
compare("live crease 30 deg: a sheared cube, recomputed", blender_normals(me), ref)
check(d.max() < 0.5 and int(mesh_io.MeshArrays(me).edge_sharp.sum()) == 12,
      "live crease 30 deg: faces' normals (max %.2f deg), the 12 edges marked" % d.max())
bpy.data.objects.remove(obj)

obj = new_scene_object(cube_smooth)  # split into its faces, welded back
split_faces(obj.data)
whole = new_scene_object(cube_smooth)
bpy.ops.object.select_all(action="DESELECT")
obj.select_set(True)
bpy.ops.mesh.vn_recompute_normals(method="MWE", weld=True, weld_keep_hard=False, live=True)
for m in (obj.data, whole.data):
    transform_vertices(m, np.diag([1.0, 1.5, 2.5]))
settle()
compare("live weld: split cube stretched = whole cube stretched",
        by_face_and_position(mesh_io.MeshArrays(obj.data), blender_normals(obj.data)),
        by_face_and_position(mesh_io.MeshArrays(whole.data), reference(whole.data, "MWE")))
bpy.data.objects.remove(obj)
bpy.data.objects.remove(whole)

# Edit Mode: recomputed on leaving it, not per edit inside it, not when nothing changed
obj = sphere_smooth()
me = obj.data
bpy.ops.mesh.vn_recompute_normals(method="MWAAT", live=True)
settle()
n0 = recomputed()
bpy.ops.object.mode_set(mode="EDIT")
bm = bmesh.from_edit_mesh(me)
offsets = np.random.default_rng(6).uniform(-0.03, 0.03, (len(bm.verts), 3))
for v, off in zip(bm.verts, offsets):
    v.co += mathutils.Vector(off)
bmesh.update_edit_mesh(me)
checked0 = addon.live_stats["checked"]
settle()
inside = recomputed() - n0 + addon.live_stats["checked"] - checked0
bpy.ops.object.mode_set(mode="OBJECT")  # evaluates the depsgraph: the handler runs
compare("live, Edit Mode: vertices moved with bmesh, recomputed on leaving", blender_normals(me),
        reference(me, "MWAAT"))
bpy.ops.object.mode_set(mode="EDIT")
bpy.ops.object.mode_set(mode="OBJECT")
check(inside == 0 and recomputed() == n0 + 1, "live, Edit Mode: %d checks or recomputes inside, 1 on leaving, "
      "none for entering and leaving again without a change (%d)" % (inside, recomputed() - n0 - 1))
# Live with Selected Only: live recomputes whole meshes, so the run does too
n0 = recomputed()
edit_top_third(me)
r = bpy.ops.mesh.vn_recompute_normals(method="MWE", selected_only=True, live=True)
bpy.ops.object.mode_set(mode="OBJECT")
compare("live with Selected Only: the whole mesh computed", blender_normals(me), reference(me, "MWE"))
check(r_ok(r) and not mesh_io.MeshArrays(me).edge_sharp.any(), "live with Selected Only: no border marked")
check(recomputed() == n0, "live, run in Edit Mode: its result is current on leaving (%d recomputes)"
      % (recomputed() - n0))
# Sculpt Mode: its strokes change the mesh data one by one: recomputed on leaving
n0 = recomputed()
bpy.ops.object.mode_set(mode="SCULPT")
move_vertices(me, 0.03, 7)
settle()
inside = recomputed() - n0
bpy.ops.object.mode_set(mode="OBJECT")
compare("live, Sculpt Mode: recomputed on leaving", blender_normals(me), reference(me, "MWE"))
check(inside == 0 and recomputed() == n0 + 1, "live, Sculpt Mode: %d inside, %d on leaving"
      % (inside, recomputed() - n0 - inside))


def animate(obj, bulged, last, arm_location, rotation):
    """A shape key from obj's positions to bulged and an armature bending every vertex, keyed from
    frame 1 (rest) to last. Returns (key, armature object, bone)."""
    obj.shape_key_add(name="Basis")
    key = obj.shape_key_add(name="Bulge")
    key.data.foreach_set("co", bulged.ravel())
    key.value = 0.0
    key.keyframe_insert("value", frame=1)
    key.value = 1.0
    key.keyframe_insert("value", frame=last)
    bpy.ops.object.armature_add(location=arm_location)
    arm = bpy.context.active_object
    obj.vertex_groups.new(name=arm.pose.bones[0].name).add(list(range(len(obj.data.vertices))), 1.0, "REPLACE")
    obj.modifiers.new("Armature", "ARMATURE").object = arm
    bone = arm.pose.bones[0]
    bone.rotation_mode = "XYZ"
    bone.keyframe_insert("rotation_euler", frame=1)
    bone.rotation_euler = rotation
    bone.keyframe_insert("rotation_euler", frame=last)
    return key, arm, bone


# Animation: frame changes (shape key and armature) neither check nor recompute; the deformation
# is Blender's (it carries the custom normals), the mesh data is not changed
key, arm, bone = animate(obj, positions(me) * np.float32([1.5, 1.0, 0.7]), 20, (0.0, 0.0, -1.0), (0.8, 0.0, 0.0))
scene = bpy.context.scene
scene.frame_set(1)
settle()
n0, checked0 = recomputed(), addon.live_stats["checked"]


def evaluated_positions():
    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    return np.array([v.co[:] for v in ev.vertices])


first = evaluated_positions()
for f in range(2, 21):
    scene.frame_set(f)
moved = np.abs(evaluated_positions() - first).max()
check(moved > 0.3 and recomputed() == n0 and addon.live_stats["checked"] == checked0,
      "live: 19 frames of shape key + armature animation (moved %.2f): %d checks, %d recomputes"
      % (moved, addon.live_stats["checked"] - checked0, recomputed() - n0))
bone.rotation_euler = (0.3, 0.0, 0.0)  # posing outside a frame change: no edit of the mesh either
key.value = 0.5
settle()
check(recomputed() == n0, "live: posing and a shape key's value changed: not recomputed (%d checks)"
      % (addon.live_stats["checked"] - checked0))
actions = [me.shape_keys.animation_data.action, arm.animation_data.action]
arm_data = arm.data
for o in (obj, arm):
    bpy.data.objects.remove(o)
bpy.data.meshes.remove(me)  # not left behind without users (with its shape keys) in the file saved below
bpy.data.armatures.remove(arm_data)
for a in actions:
    bpy.data.actions.remove(a)

# Two objects sharing one mesh: one recompute per edit
a_obj = sphere_smooth()
b_obj = a_obj.copy()
bpy.context.collection.objects.link(b_obj)
b_obj.select_set(True)
bpy.ops.mesh.vn_recompute_normals(method="MWELR", live=True)
settle()
n0 = recomputed()
calls = []
real = binding.Library.corner_normals
binding.Library.corner_normals = lambda self, *a, **k: calls.append(1) or real(self, *a, **k)
try:
    move_vertices(a_obj.data, 0.03, 8)
    settle()
finally:
    binding.Library.corner_normals = real
compare("live, two objects, one mesh: recomputed", blender_normals(a_obj.data), reference(a_obj.data, "MWELR"))
check(len(calls) == 1 and recomputed() == n0 + 1, "live, two objects, one mesh: computed %d time(s)" % len(calls))
bpy.data.objects.remove(b_obj)

# A failing recompute: one message, the error kept for the panel, the normals left stale
me = a_obj.data
kept = positions(me)
prefs.library_path = "/nonexistent/libvn.so"
out = io.StringIO()
with contextlib.redirect_stdout(out):
    for seed in (9, 10):
        move_vertices(me, 0.03, seed)
        settle()
lines = [line for line in out.getvalue().splitlines() if line.startswith("vn live")]
print(out.getvalue(), end="")
d = stale_deg(me, "MWELR")
check(len(lines) == 1 and "stale" in lines[0] and "does not exist" in me.vn_live.error and d > 3,
      "live recompute failing twice: one message %s, error kept (%r), normals stale (%.1f deg)"
      % (lines, me.vn_live.error, d))
lay = Layout()
addon.DATA_PT_vn_live.draw(type("Panel", (), {"layout": lay})(), type("Context", (), {"mesh": me, "object": a_obj})())
check(me.vn_live.error in lay.labels, "the vn panel shows the error")
prefs.library_path = ""
me.vertices.foreach_set("co", kept.ravel())  # put back: Blender stores normals less precisely on crumpled meshes
me.update()
settle()
compare("library fixed: the next edit recomputes", blender_normals(me), reference(me, "MWELR"))
check(me.vn_live.error == "", "library fixed: error cleared")
bpy.data.objects.remove(a_obj)

# Disabling the add-on removes its handler and settings type; enabling brings them back, the data kept
obj = sphere_smooth()
me_name = obj.data.name
bpy.ops.mesh.vn_recompute_normals(method="MWRELR", live=True)
bpy.ops.preferences.addon_disable(module=MODULE)
check(our_handlers() == [] and not hasattr(bpy.types.Mesh, "vn_live"), "add-on disabled: no handler, no vn_live")
bpy.ops.preferences.addon_enable(module=MODULE)
addon = importlib.import_module(MODULE)
me = bpy.data.meshes[me_name]
check(len(our_handlers()) == 1 and me.vn_live.live and me.vn_live.method == "MWRELR",
      "add-on enabled again: one handler, the mesh still live with MWRELR")

# Saved and reopened: still live with its settings, not recomputed on opening, an edit recomputes
obj.name = me.name = "LiveSphere"
blend = os.path.join(tmp, "live.blend")
bpy.ops.wm.save_as_mainfile(filepath=blend)
n0 = recomputed()
bpy.ops.wm.open_mainfile(filepath=blend)  # runs none of the add-on's registration again
me = bpy.data.meshes["LiveSphere"]  # the objects fetched before the file was opened are gone
check(len(our_handlers()) == 1 and addon._on_depsgraph_update in bpy.app.handlers.depsgraph_update_post,
      "reopened: the handler is still registered (persistent), once")
check(me.vn_live.live and me.vn_live.method == "MWRELR", "reopened: still live with MWRELR")
settle()
check(recomputed() == n0, "reopened: not recomputed on opening (the stored state matches)")
move_vertices(me, 0.03, 12)
settle()
compare("reopened: an edit recomputes", blender_normals(me), reference(me, "MWRELR"))
check(recomputed() == n0 + 1, "reopened: one edit, one recompute (%d)" % (recomputed() - n0))
print("live normals in %.2f s" % (time.perf_counter() - t0))
# ------------------------------------------------------------------ issue 15: parity with the Weighted Normal modifier
# The modifier at Weight 50 gives every corner the inverse power weight
# 1 / 1^n = 1 (whatever the Threshold): Corner Angle mode is then exactly
# angle weighted (MWA), Face Area mode weights by the face's area. Keep
# Sharp on: its fans are Blender's, as the add-on's (Keep Sharp Edges on).
def weighted_normal_modifier(obj, **settings):
    """Corner normals of a copy of obj with the Weighted Normal modifier
    (Corner Angle, weight 50, threshold 0.01, Keep Sharp, and settings) applied."""
    copy = obj.copy()
    copy.data = obj.data.copy()
    bpy.context.collection.objects.link(copy)
    m = copy.modifiers.new("WN", "WEIGHTED_NORMAL")
    m.mode, m.weight, m.thresh, m.keep_sharp = "CORNER_ANGLE", 50, 0.01, True
    for k, v in settings.items():
        setattr(m, k, v)
    bpy.ops.object.select_all(action="DESELECT")
    copy.select_set(True)
    bpy.context.view_layer.objects.active = copy
    bpy.ops.object.modifier_apply(modifier=m.name)
    n = blender_normals(copy.data)
    data = copy.data
    bpy.data.objects.remove(copy)
    bpy.data.meshes.remove(data)
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    return n


def vn_normals(obj, **props):
    """obj's corner normals after the operator with props, on a copy of its mesh
    (obj keeps its own)."""
    saved = obj.data
    obj.data = saved.copy()
    r = bpy.ops.mesh.vn_recompute_normals(**props)
    n = blender_normals(obj.data)
    data, obj.data = obj.data, saved
    bpy.data.meshes.remove(data)
    check(r_ok(r), "operator finished (%s)" % props)
    return n


def differs(label, got, ref, min_deg):
    d = angles_deg(got, ref)
    check(d.max() > min_deg, "%s: max %.2f deg apart (> %g)" % (label, d.max(), min_deg))


# MWA = Corner Angle on an irregular mesh of quads and triangles
obj = sphere_smooth()
mod = weighted_normal_modifier(obj)
compare("jittered sphere (quads, pole triangles): MWA = modifier's Corner Angle",
        vn_normals(obj, method="MWA"), mod)
differs("...while MWE is not angle weighted", vn_normals(obj, method="MWE"), mod, 0.3)

# Face Area: MWAAT weights a corner by |E x E'| (its corner triangle), the
# modifier by its face's area: the same on triangles, not on quads
area = weighted_normal_modifier(obj, mode="FACE_AREA")
d = angles_deg(vn_normals(obj, method="MWAAT"), area)
check(d.max() > 0.3, "Face Area != MWAAT on the jittered sphere's quads: max %.3f deg, median %.4f deg, mean %.4f deg"
      % (d.max(), np.median(d), d.mean()))
bpy.data.objects.remove(obj)
obj = new_scene_object(bpy.ops.mesh.primitive_monkey_add)
shade_smooth(obj.data)
if V < (4, 1, 0):
    obj.data.use_auto_smooth = True
    obj.data.auto_smooth_angle = math.pi
d = angles_deg(vn_normals(obj, method="MWAAT"), weighted_normal_modifier(obj, mode="FACE_AREA"))
check(d.max() > 0.3, "Face Area != MWAAT on Suzanne (quads and triangles): max %.3f deg, median %.4f deg, "
      "mean %.4f deg" % (d.max(), np.median(d), d.mean()))
bpy.data.objects.remove(obj)
obj = new_scene_object(ico_sphere)
me = obj.data
shade_smooth(me)
co = np.empty(len(me.vertices) * 3, dtype=np.float32)
me.vertices.foreach_get("co", co)
me.vertices.foreach_set("co", co * rng.uniform(0.9, 1.1, co.size).astype(np.float32))
if V < (4, 1, 0):
    me.use_auto_smooth = True
    me.auto_smooth_angle = math.pi
compare("jittered ico sphere (triangles): MWAAT = modifier's Face Area", vn_normals(obj, method="MWAAT"),
        weighted_normal_modifier(obj, mode="FACE_AREA"))
bpy.data.objects.remove(obj)


# Face Influence: a cube bevelled with Harden Normals (face strengths: the
# original faces strong, the bevel's weak and medium), jittered
def hardened_cube():
    bpy.ops.mesh.primitive_cube_add(size=2.0)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.bevel(offset=0.3, segments=3, harden_normals=True, face_strength_mode="AFFECTED")
    bpy.ops.object.mode_set(mode="OBJECT")


obj = new_scene_object(hardened_cube)
me = obj.data
shade_smooth(me)
co = np.empty(len(me.vertices) * 3, dtype=np.float32)
me.vertices.foreach_get("co", co)
me.vertices.foreach_set("co", co + rng.uniform(-0.01, 0.01, co.size).astype(np.float32))
if V < (4, 1, 0):
    me.use_auto_smooth = True
    me.auto_smooth_angle = math.pi
strength = mesh_io.MeshArrays(me).face_strength
levels = sorted(set(strength.tolist())) if strength is not None else []
check(levels == [-16384, 0, 16384], "bevelled cube: face strengths %s in %s" % (levels, mesh_io.FACE_STRENGTH))
mod = weighted_normal_modifier(obj, use_face_influence=True)
got = vn_normals(obj, method="MWA", use_face_influence=True)
compare("bevelled cube, Face Influence: MWA = modifier's Corner Angle", got, mod)
plain = vn_normals(obj, method="MWA")
differs("...and Face Influence off differs from it", plain, mod, 5.0)
compare("bevelled cube, Face Influence off = modifier's off", plain, weighted_normal_modifier(obj))
big = mesh_io.MeshArrays(me)
on_strong = big.to_loops((strength[big.face_of_corner] == 16384).astype(np.uint8)).astype(bool)
fn = np.empty(len(me.polygons) * 3)
me.polygons.foreach_get("normal", fn)
face_n = big.to_loops(fn.reshape(-1, 3)[big.face_of_corner])
d = angles_deg(got[on_strong], face_n[on_strong])
check(d.max() < 0.5, "Face Influence: the strong (original) faces stay flat: %.3f deg from their normals" % d.max())
me.attributes.remove(me.attributes[mesh_io.FACE_STRENGTH])
compare("no face strengths: Face Influence changes nothing", vn_normals(obj, method="MWA", use_face_influence=True),
        plain, max_deg=1e-6, median_deg=1e-6)
bpy.data.objects.remove(obj)

# Vertex group and Invert: the group's vertices (membership, not weight:
# some weigh 0) get new normals, the others keep theirs
obj = sphere_smooth()
me = obj.data
me.normals_split_custom_set_from_vertices(np.tile(np.float32([0, 0, 1]), (len(me.vertices), 1)))
me.update()
up = blender_normals(me)  # +z as stored: what the others keep
co = np.array([v.co[:] for v in me.vertices])
top = np.flatnonzero(co[:, 2] > 0.3)
group = obj.vertex_groups.new(name="Top")
group.add(top[::2].tolist(), 1.0, "REPLACE")
group.add(top[1::2].tolist(), 0.0, "REPLACE")
obj.vertex_groups.new(name="Other").add([0], 1.0, "REPLACE")
a = mesh_io.MeshArrays(me)
in_top = a.to_loops(np.isin(a.corner_vert, top).astype(np.uint8)).astype(bool)
check(0 < in_top.sum() < in_top.size, "vertex group: %d of %d corners in 'Top'" % (in_top.sum(), in_top.size))
whole = vn_normals(obj, method="MWA")
for invert in (False, True):
    label = "vertex group 'Top'%s" % (", inverted" if invert else "")
    mod = weighted_normal_modifier(obj, vertex_group="Top", invert_vertex_group=invert)
    got = vn_normals(obj, method="MWA", vertex_group="Top", invert_vertex_group=invert)
    compare(label + ": MWA = modifier's Corner Angle", got, mod)
    changed = ~in_top if invert else in_top
    compare(label + ": changed corners = the whole mesh's", got[changed], whole[changed])
    compare(label + ": the others keep their +z", got[~changed], up[~changed])
    differs(label + ": without the group", whole, mod, 20.0)
props = bpy.ops.mesh.vn_recompute_normals.get_rna_type().properties
P = bpy.types.WeightedNormalModifier.bl_rna.properties
check(all(props[k].name == P[k].name and props[k].description == P[k].description
          for k in ("use_face_influence", "vertex_group", "invert_vertex_group")),
      "Face Influence, Vertex Group, Invert: the modifier's names and descriptions")


class Layout:
    """Stands in for the Adjust Last Operation panel's layout: records prop and prop_search calls."""

    def __init__(self, calls):
        self.calls = calls

    def __getattr__(self, name):
        def call(*a, **k):
            self.calls.append((name,) + a)
            return Layout(self.calls)
        return call


calls = []
op = type("Op", (), {k: props[k].default for k in props.keys() if hasattr(props[k], "default")
                     and not getattr(props[k], "is_array", False)})()
op.layout, op.vertex_group = Layout(calls), "Top"
addon.MESH_OT_vn_recompute_normals.draw(op, bpy.context)
search = [c for c in calls if c[0] == "prop_search"]
check(len(search) == 1 and search[0][2:] == ("vertex_group", obj, "vertex_groups")
      and ("prop", op, "invert_vertex_group") in calls and ("prop", op, "use_face_influence") in calls,
      "panel: Face Influence, a search of the object's vertex groups, Invert (%s)" % [c[2:] for c in search])

# A selected object whose mesh lacks the group is skipped (nothing to change), said in a warning
other = sphere_smooth()
before = blender_normals(other.data)
obj.select_set(True)
bpy.context.view_layer.objects.active = obj
m = run_message(method="MWA", vertex_group="Top")
check(m == "{'FINISHED'}" and angles_deg(blender_normals(other.data), before).max() < 1e-6,
      "second object without the group: left alone (%s)" % m)
bpy.data.objects.remove(other)
bpy.data.objects.remove(obj)

# ------------------------------------------------------------------ issue 20: plans for large meshes
# Above PLAN_MIN_FACES faces the operator and live recomputes go through a
# vn plan kept per mesh: the same normals, bit for bit, as without one; made
# again when the faces change; freed with the mesh and on disabling.
t0 = time.perf_counter()
for o in list(bpy.data.objects):
    bpy.data.objects.remove(o)
addon = importlib.import_module(MODULE)
check(addon.plan_stats["created"] == 0 and not addon._plans,
      "plans: none made for the meshes above (%d faces and fewer)" % addon.PLAN_MIN_FACES)
written = []  # the normals each run stores (the array given to set_custom_normals)
_store = addon.mesh_io.set_custom_normals
addon.mesh_io.set_custom_normals = lambda mesh, a, normals, zero: written.append(normals.copy()) or _store(
    mesh, a, normals, zero)


def big_grid():
    """A bumpy grid of quads above PLAN_MIN_FACES, a few edges marked sharp and faces flat-shaded."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=320, y_subdivisions=320, size=2.0)
    me = bpy.context.active_object.data
    co = positions(me)
    co[:, 2] = 0.05 * np.sin(9 * co[:, 0]) * np.cos(7 * co[:, 1])
    me.vertices.foreach_set("co", co.ravel())
    shade_smooth(me)
    me.polygons.foreach_set("use_smooth", np.arange(len(me.polygons)) % 997 != 0)
    me.edges.foreach_set("use_edge_sharp", np.arange(len(me.edges)) % 1009 == 0)
    if V < (4, 1, 0):
        me.use_auto_smooth = True
        me.auto_smooth_angle = math.pi
    me.update()


def fresh(me, method, crease=math.pi):
    """The library's float32 corner normals of the mesh as it is now, without a plan, in vn's corner order."""
    a = mesh_io.MeshArrays(me)
    flags = a.edge_sharp[a.corner_edge] | ~a.face_smooth[a.face_of_corner]
    return lib.corner_normals(a.co, a.corner_vert, a.face_offsets, method.lower(), crease, flags,
                              dtype=np.float32)[0]


obj = new_scene_object(big_grid)
me = obj.data
faces = len(me.polygons)
created = addon.plan_stats["created"]
r = bpy.ops.mesh.vn_recompute_normals(method="MWA", use_crease=True, crease_angle=math.radians(20))
key = me.as_pointer()
check(r_ok(r) and faces > addon.PLAN_MIN_FACES and addon.plan_stats["created"] == created + 1 and key in addon._plans,
      "plans: operator on %d faces made one, kept for the mesh" % faces)
compare("plans: operator, %d faces" % faces, blender_normals(me), reference(me, "MWA", math.radians(20)))
r = bpy.ops.mesh.vn_recompute_normals(method="MWA", use_crease=True, crease_angle=math.radians(20))
check(r_ok(r) and addon.plan_stats["created"] == created + 1 and np.array_equal(written[-1], written[-2]),
      "plans: run again (the redo panel): the plan reused, the same normals")
addon.PLAN_MIN_FACES, min_faces = faces, addon.PLAN_MIN_FACES  # this mesh no longer above it
r = bpy.ops.mesh.vn_recompute_normals(method="MWA", use_crease=True, crease_angle=math.radians(20))
addon.PLAN_MIN_FACES = min_faces
check(r_ok(r) and addon.plan_stats["created"] == created + 1 and np.array_equal(written[-1], written[-2]),
      "plans: without a plan, the same normals bit for bit (%d corners)" % len(written[-1]))

# Live across frames: at each frame a script writes a shape key + armature deformation (another
# object's, evaluated) into the mesh data, as a bake or simulation step does; each write is
# recomputed on the plan. (Not from a frame_change_post handler: Blender runs no
# depsgraph_update_post for what those write, so live meshes do not see it.)
source = obj.copy()
source.data = me.copy()
bpy.context.collection.objects.link(source)
co = positions(me)
_key, arm, _bone = animate(source, co + np.float32([0, 0, 0.3]) * np.exp(-4 * (co ** 2).sum(axis=1))[:, None], 4,
                           (-1.0, 0.0, 0.0), (0.0, 0.4, 0.0))
bpy.ops.object.select_all(action="DESELECT")
obj.select_set(True)
bpy.context.view_layer.objects.active = obj
check(r_ok(bpy.ops.mesh.vn_recompute_normals(method="MWSELR", live=True)), "plans: live on")
settle()


def follow_source():
    ev = source.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    co = np.empty(len(ev.vertices) * 3, dtype=np.float32)
    ev.vertices.foreach_get("co", co)
    me.vertices.foreach_set("co", co)
    me.update()


n0, created, frames, moved = recomputed(), addon.plan_stats["created"], [], 0.0
first = positions(me)
for f in (2, 3, 4, 1):  # the scene starts at frame 1, where nothing is deformed
    written.clear()
    bpy.context.scene.frame_set(f)
    follow_source()
    settle()  # the event loop's update after the edit: the live handler
    frames.append(len(written) == 1 and np.array_equal(written[0], fresh(me, "MWSELR")))
    moved = max(moved, float(np.abs(positions(me) - first).max()))
check(all(frames) and recomputed() == n0 + 4 and addon.plan_stats["created"] == created and moved > 0.2,
      "plans: live, 4 frames of shape key + armature deformation (moved %.2f): %d recomputes on the one plan, "
      "each equal to a fresh computation bit for bit (%s)" % (moved, recomputed() - n0, frames))
compare("plans: live, last frame as stored", blender_normals(me), reference(me, "MWSELR"))


def edit_faces(me, change):
    bm = bmesh.new()
    bm.from_mesh(me)
    bm.faces.ensure_lookup_table()
    change(bm)
    bm.to_mesh(me)
    bm.free()
    me.update()


# New faces: the plan is made again, for the new faces only
for label, change in (("a face deleted", lambda bm: bmesh.ops.delete(bm, geom=[bm.faces[5000]], context="FACES_ONLY")),
                      ("a face turned over (the same counts)", lambda bm: bmesh.ops.reverse_faces(
                          bm, faces=[bm.faces[70000]]))):
    created, n0 = addon.plan_stats["created"], recomputed()
    written.clear()
    edit_faces(me, change)
    settle()
    check(recomputed() == n0 + 1 and addon.plan_stats["created"] == created + 1 and len(written) == 1
          and np.array_equal(written[0], fresh(me, "MWSELR")),
          "plans: %s: recomputed on a new plan (%d faces), equal to a fresh computation" % (label, len(me.polygons)))
    written.clear()
    move_vertices(me, 0.001, 13)
    settle()
    check(addon.plan_stats["created"] == created + 1 and len(written) == 1
          and np.array_equal(written[0], fresh(me, "MWSELR")), "plans: %s: the next edit reuses it" % label)
compare("plans: live after new faces, as stored", blender_normals(me), reference(me, "MWSELR"))
check(list(addon._plans) == [key], "plans: one kept, for the one mesh (%d)" % len(addon._plans))
addon.PLAN_MIN_FACES = 100  # small meshes, to see PLAN_CACHE_SIZE's limit
small = [new_scene_object(ico_sphere) for _ in range(addon.PLAN_CACHE_SIZE)]
evicted = addon._plans[key][2]
for o in small:
    bpy.ops.object.select_all(action="DESELECT")
    o.select_set(True)
    bpy.ops.mesh.vn_recompute_normals(method="MWE")
addon.PLAN_MIN_FACES = min_faces
check(list(addon._plans) == [o.data.as_pointer() for o in small] and evicted.closed,
      "plans: %d kept at most, the least recently used freed" % addon.PLAN_CACHE_SIZE)

# Freed with their meshes
plans = [addon._plans[o.data.as_pointer()][2] for o in small]
for o in small:
    small_me = o.data
    bpy.data.objects.remove(o)
    bpy.data.meshes.remove(small_me)
settle()
check(not addon._plans and all(p.closed for p in plans), "plans: the meshes removed, their plans freed")
actions = [source.data.shape_keys.animation_data.action, arm.animation_data.action]
for o in (obj, source, arm):
    me_o = o.data
    bpy.data.objects.remove(o)
    (bpy.data.armatures if o is arm else bpy.data.meshes).remove(me_o)
for a in actions:
    bpy.data.actions.remove(a)
obj = new_scene_object(big_grid)  # Edit Mode, then disabling with a plan kept
written.clear()
created = addon.plan_stats["created"]
bpy.ops.mesh.vn_recompute_normals(method="MWE")
plan = addon._plans[obj.data.as_pointer()][2]
bpy.ops.object.mode_set(mode="EDIT")  # the operator computes a copy of the edit mesh: the mesh's plan serves it
r = bpy.ops.mesh.vn_recompute_normals(method="MWE")
bpy.ops.object.mode_set(mode="OBJECT")
check(r_ok(r) and addon.plan_stats["created"] == created + 1 and len(written) == 2
      and np.array_equal(written[0], written[1]), "plans: Edit Mode uses the mesh's plan, the same normals")
addon.mesh_io.set_custom_normals = _store
bpy.ops.preferences.addon_disable(module=MODULE)
check(not addon._plans and plan.closed, "plans: add-on disabled, plans freed")
bpy.ops.preferences.addon_enable(module=MODULE)
addon = importlib.import_module(MODULE)
me = obj.data
bpy.data.objects.remove(obj)
bpy.data.meshes.remove(me)
print("plans in %.2f s" % (time.perf_counter() - t0))

print("storage precision: worst corner %.3f deg from the library's normals" % max(PRECISION))

if failures:
    raise SystemExit("%d failure(s):\n  %s" % (len(failures), "\n  ".join(failures)))
print("all Blender add-on tests passed")
