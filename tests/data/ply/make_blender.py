# Makes the Blender-exported test files (run once; the outputs are committed):
#   blender -b --factory-startup -noaudio --python-exit-code 1 \
#     --python tests/data/ply/make_blender.py -- tests/data
# Suzanne (quads and triangles, with Blender's UVs) with a byte colour per
# vertex, through Blender 3.4's PLY exporter (ASCII and binary: normals,
# colours, UVs) and STL exporter (binary and ASCII).
import os
import sys

import bpy

out = sys.argv[sys.argv.index("--") + 1]
bpy.ops.object.select_all(action="SELECT")
bpy.ops.object.delete()
bpy.ops.mesh.primitive_monkey_add(size=2.0, calc_uvs=True)
mesh = bpy.context.active_object.data
# Blender 3.4's PLY exporter writes the face-corner byte colours (the
# legacy vertex colour layer); each corner gets its vertex's colour.
colours = mesh.color_attributes.new("Col", "BYTE_COLOR", "CORNER")
for loop in mesh.loops:
    x, y, z = mesh.vertices[loop.vertex_index].co
    colours.data[loop.index].color = ((x + 1) / 2, (y + 1) / 2, (z + 1) / 2, 1.0)

ply = os.path.join(out, "ply")
stl = os.path.join(out, "stl")
bpy.ops.export_mesh.ply(filepath=os.path.join(ply, "blender_ascii.ply"), use_ascii=True, use_selection=True,
                        use_mesh_modifiers=False, use_normals=True, use_uv_coords=True, use_colors=True)
bpy.ops.export_mesh.ply(filepath=os.path.join(ply, "blender_binary.ply"), use_ascii=False, use_selection=True,
                        use_mesh_modifiers=False, use_normals=True, use_uv_coords=True, use_colors=True)
bpy.ops.export_mesh.stl(filepath=os.path.join(stl, "blender_binary.stl"), ascii=False, use_selection=True)
bpy.ops.export_mesh.stl(filepath=os.path.join(stl, "blender_ascii.stl"), ascii=True, use_selection=True)
