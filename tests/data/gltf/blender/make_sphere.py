# Writes blender-sphere.glb with Blender's own OBJ importer and glTF exporter:
#   blender -b --factory-startup -noaudio --python-exit-code 1 \
#       --python tests/data/gltf/blender/make_sphere.py -- tests/data/obj/blender_sphere.obj OUT.glb
# The UV sphere Blender exported as OBJ (tests/data/obj), read back and
# written as glTF: the same corners in both formats, each texture
# coordinate in the format's own convention (glTF's v is OBJ's 1 - v).
import sys

import bpy

src, out = sys.argv[sys.argv.index("--") + 1:][:2]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.wm.obj_import(filepath=src, forward_axis="Y", up_axis="Z")  # as the file stands
bpy.ops.export_scene.gltf(filepath=out, export_format="GLB", export_yup=False)
