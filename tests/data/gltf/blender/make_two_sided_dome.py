# Writes two-sided-dome.glb with Blender's own glTF exporter:
#   blender -b --factory-startup -noaudio --python-exit-code 1 \
#       --python tests/data/gltf/blender/make_two_sided_dome.py -- OUT.glb
# The upper half of a 16 x 8 UV sphere, smooth shaded, and a copy of it
# with its faces reversed on vertices of its own: a double-sided surface as
# modellers build one. The exporter gives each side its own normals and
# splits the front's UV seam.
import sys

import bmesh
import bpy

out = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8)
ob = bpy.context.active_object
bm = bmesh.new()
bm.from_mesh(ob.data)
bmesh.ops.delete(bm, geom=[v for v in bm.verts if v.co.z < -1e-6], context="VERTS")
back = bmesh.ops.duplicate(bm, geom=bm.faces[:] + bm.edges[:] + bm.verts[:])
bmesh.ops.reverse_faces(bm, faces=[g for g in back["geom"] if isinstance(g, bmesh.types.BMFace)])
bm.to_mesh(ob.data)
bm.free()
for p in ob.data.polygons:
    p.use_smooth = True
bpy.ops.export_scene.gltf(filepath=out, export_format="GLB")
