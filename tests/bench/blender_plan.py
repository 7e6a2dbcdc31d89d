"""The Blender add-on's live recompute per frame with and without a vn plan
(issue 20), in real Blender, headless:

    blender -b --factory-startup -noaudio --python-exit-code 1 \\
        --python tests/bench/blender_plan.py -- --zip build/vn_blender.zip [--size 1000] [--frames 7]
    (Blender 4.3: bash .ci/blender43 build/vn_blender.zip tests/bench/blender_plan.py WORKDIR --size 1000)

A benchmark, not a test. A bumpy grid of --size x --size quads, smooth,
live with MWA. Each frame moves every vertex (mesh data, Object Mode) and
lets the depsgraph run the live handler: read the arrays and digest them,
compute, store the custom normals. Times in ms, the median of --frames
frames: the whole update (view_layer.update()), and within it the library
call alone (Library.corner_normals without a plan, Plan.corner_normals with
one); first with the add-on's PLAN_MIN_FACES above the mesh (no plan), then
at its default (one plan, made in a first frame not counted; its creation
timed apart).
"""

import math
import statistics
import sys
import time
import importlib

import bpy
import numpy as np

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
ZIP = args[args.index("--zip") + 1]
SIZE = int(args[args.index("--size") + 1]) if "--size" in args else 1000
FRAMES = int(args[args.index("--frames") + 1]) if "--frames" in args else 7
V = bpy.app.version

if V >= (4, 2, 0):
    bpy.ops.extensions.package_install_files(filepath=ZIP, repo="user_default", enable_on_install=True)
else:
    bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True)
    bpy.ops.preferences.addon_enable(module="vn_normals")
module = [k for k in bpy.context.preferences.addons.keys() if k.split(".")[-1] == "vn_normals"][0]
addon = importlib.import_module(module)
binding = addon.binding
bpy.ops.object.select_all(action="SELECT")
bpy.ops.object.delete()

bpy.ops.mesh.primitive_grid_add(x_subdivisions=SIZE, y_subdivisions=SIZE, size=2.0)
obj = bpy.context.active_object
me = obj.data
base = np.empty((len(me.vertices), 3), dtype=np.float32)
me.vertices.foreach_get("co", base.ravel())
base[:, 2] = 0.05 * np.sin(9 * base[:, 0]) * np.cos(7 * base[:, 1])
me.vertices.foreach_set("co", base.ravel())
me.polygons.foreach_set("use_smooth", np.ones(len(me.polygons), dtype=bool))
if V < (4, 1, 0):
    me.use_auto_smooth = True
    me.auto_smooth_angle = math.pi
me.update()
print("Blender %s: %d faces, %d corners" % (bpy.app.version_string, len(me.polygons), len(me.loops)))

in_library = []  # seconds in the library call of each recompute


def timed(f):
    def call(*a, **k):
        t0 = time.perf_counter()
        try:
            return f(*a, **k)
        finally:
            in_library.append(time.perf_counter() - t0)
    return call


binding.Library.corner_normals = timed(binding.Library.corner_normals)
binding.Plan.corner_normals = timed(binding.Plan.corner_normals)
_plan_create = binding.Library.plan
creates = []
binding.Library.plan = lambda *a, **k: creates.append(time.perf_counter()) or _plan_create(*a, **k)

bpy.ops.mesh.vn_recompute_normals(method="MWA", live=True)
frame = 0


def step():
    """One frame: the vertices moved, the live handler run. Its seconds."""
    global frame
    frame += 1
    me.vertices.foreach_set("co", (base * np.float32(1 + 0.01 * math.sin(frame))).ravel())
    me.update()
    t0 = time.perf_counter()
    bpy.context.view_layer.update()
    return time.perf_counter() - t0


rows = []
default = addon.PLAN_MIN_FACES
for label, min_faces in (("without a plan", 10 ** 12), ("with a plan", default)):
    addon.PLAN_MIN_FACES = min_faces
    first = step()  # with a plan: makes it
    in_library.clear()
    n0 = addon.live_stats["recomputed"]
    whole = [step() for _ in range(FRAMES)]
    assert addon.live_stats["recomputed"] == n0 + FRAMES, "not every frame recomputed"
    rows.append((label, statistics.median(whole), statistics.median(in_library), first))
create_ms = float("nan")
if addon._plans:
    entry = next(iter(addon._plans.values()))
    t0 = time.perf_counter()
    entry[1].plan(entry[3], entry[4], len(base)).close()
    create_ms = (time.perf_counter() - t0) * 1e3
print("\n| live recompute, %d faces | per frame ms | library call ms | first frame ms |" % len(me.polygons))
print("|---|---|---|---|")
for label, whole, lib_s, first in rows:
    print("| %s | %.1f | %.1f | %.1f |" % (label, whole * 1e3, lib_s * 1e3, first * 1e3))
print("\nplan creation: %.1f ms (%d made)" % (create_ms, len(creates)))
