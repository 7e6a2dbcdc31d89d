"""Speed of the Blender add-on against Blender's Weighted Normal modifier
(issue 15), in real Blender, headless:

    blender -b --factory-startup -noaudio --python-exit-code 1 \
        --python tests/bench/blender_speed.py -- --zip build/vn_blender.zip [--runs 3] [--small-only] [--only TEXT]

(tests/bench/blender_speed.sh runs it in Blender 3.4 and 4.3.) Two meshes,
every face smooth-shaded, nothing marked sharp:
  ico sphere, subdivisions 8 (its operator counts the icosahedron as 1):
      163,842 vertices, 327,680 triangles;
  Suzanne with a Subdivision Surface modifier of level 6 applied:
      2,016,578 vertices, 2,015,232 quads.
Times, in seconds, the median of --runs runs, each on a fresh copy of the
mesh: the add-on's operator with each scheme (default options, Object Mode),
the Weighted Normal modifier added and applied (Corner Angle, Face Area;
weight 50, Keep Sharp off: its defaults), and the operator (MWA) in Edit
Mode. Both sides are timed around one bpy.ops call, which includes the view
layer updates bpy.ops makes. Prints a Markdown table.
"""

import math
import sys
import time

import bpy
import numpy as np

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
ZIP = args[args.index("--zip") + 1]
RUNS = int(args[args.index("--runs") + 1]) if "--runs" in args else 3
V = bpy.app.version

if V >= (4, 2, 0):
    bpy.ops.extensions.package_install_files(filepath=ZIP, repo="user_default", enable_on_install=True)
else:
    bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True)
    bpy.ops.preferences.addon_enable(module="vn_normals")
assert any(k.split(".")[-1] == "vn_normals" for k in bpy.context.preferences.addons.keys()), "add-on not enabled"
bpy.ops.object.select_all(action="SELECT")
bpy.ops.object.delete()


def smooth(obj):
    me = obj.data
    me.polygons.foreach_set("use_smooth", np.ones(len(me.polygons), dtype=bool))
    if V < (4, 1, 0):
        me.use_auto_smooth = True  # 3.4: custom normals and the modifier need it
        me.auto_smooth_angle = math.pi
    me.update()
    return obj


def ico_sphere():
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=8)
    return smooth(bpy.context.active_object)


def suzanne_level6():
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.active_object
    mod = obj.modifiers.new("subsurf", "SUBSURF")
    mod.levels = 6
    bpy.ops.object.modifier_apply(modifier=mod.name)
    return smooth(obj)


def fresh(base):
    """A new selected, active object with a copy of base's mesh."""
    obj = bpy.data.objects.new("bench", base.data.copy())
    bpy.context.collection.objects.link(obj)
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    return obj


def discard(obj):
    if obj.mode != "OBJECT":
        bpy.ops.object.mode_set(mode="OBJECT")
    me = obj.data
    bpy.data.objects.remove(obj)
    bpy.data.meshes.remove(me)


def median_time(base, run, edit=False):
    ts = []
    for _ in range(RUNS):
        obj = fresh(base)
        if edit:
            bpy.ops.object.mode_set(mode="EDIT")
        t = time.perf_counter()
        r = run(obj)
        ts.append(time.perf_counter() - t)
        assert r == {"FINISHED"}, r
        discard(obj)
    return float(np.median(ts))


def addon(method):
    return lambda obj: bpy.ops.mesh.vn_recompute_normals(method=method)


printed = set()


def modifier(mode):
    def run(obj):
        mod = obj.modifiers.new("wn", "WEIGHTED_NORMAL")
        mod.mode = mode
        if mode not in printed:
            printed.add(mode)
            print("  modifier %s: weight %d, keep_sharp %s" % (mode, mod.weight, mod.keep_sharp))
        return bpy.ops.object.modifier_apply(modifier=mod.name)
    return run


methods = [i.identifier for i in bpy.ops.mesh.vn_recompute_normals.get_rna_type().properties["method"].enum_items]
rows = [("add-on, %s" % m, addon(m), False) for m in methods]
rows += [("Weighted Normal modifier, Corner Angle, apply", modifier("CORNER_ANGLE"), False),
         ("Weighted Normal modifier, Face Area, apply", modifier("FACE_AREA"), False),
         ("add-on, MWA, Edit Mode", addon("MWA"), True)]
if "--only" in args:  # rows whose label contains this text
    rows = [r for r in rows if args[args.index("--only") + 1] in r[0]]
meshes = [("ico sphere, 327,680 triangles", ico_sphere)]
if "--small-only" not in args:
    meshes.append(("Suzanne level 6, 2,015,232 quads", suzanne_level6))

results = {}
for mesh_label, make in meshes:
    base = make()
    base.hide_set(True)
    print("%s: %d vertices, %d faces" % (mesh_label, len(base.data.vertices), len(base.data.polygons)), flush=True)
    for label, run, edit in rows:
        results[label, mesh_label] = median_time(base, run, edit)
        print("  %-50s %7.3f s" % (label, results[label, mesh_label]), flush=True)
    me = base.data
    bpy.data.objects.remove(base)
    bpy.data.meshes.remove(me)

print("\nBlender %s, seconds, median of %d:\n" % (bpy.app.version_string, RUNS))
print("| | " + " | ".join(m for m, _ in meshes) + " |")
print("|---|" + "---|" * len(meshes))
for label, _, _ in rows:
    print("| %s | " % label + " | ".join("%.2f" % results[label, m] for m, _ in meshes) + " |")
if all(("add-on, MWA" + e, m) in results for e in ("", ", Edit Mode") for m, _ in meshes):
    print("| Edit Mode / Object Mode, MWA | " + " | ".join(
        "%.2f" % (results["add-on, MWA, Edit Mode", m] / results["add-on, MWA", m]) for m, _ in meshes) + " |")
