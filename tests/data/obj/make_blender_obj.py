"""Makes the Blender-exported OBJ test files (run once; the outputs are committed):

    blender -b --factory-startup -noaudio --python-exit-code 1 \
        --python tests/data/obj/make_blender_obj.py -- tests/data/obj

- blender_sphere.obj: a UV sphere (16 segments, 8 rings) with its UVs and smooth
  normals: quads, and triangles at the poles;
- blender_cube.obj + blender_cube.mtl: a cube, two of its faces with the material
  "Red", the others "Blue";
- blender_cylinder.obj: a cylinder of 12 vertices around, flat shaded: 12-corner caps,
  longer than the 8 corners Draco's OBJ reader takes.
"""
import os
import sys

import bpy

out = sys.argv[sys.argv.index("--") + 1]


def export(obj, name, materials):
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.wm.obj_export(filepath=os.path.join(out, name), export_selected_objects=True, export_uv=True,
                          export_normals=True, export_materials=materials, export_triangulated_mesh=False)


bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, radius=1)
sphere = bpy.context.active_object
sphere.name = "Sphere"
bpy.ops.object.shade_smooth()
export(sphere, "blender_sphere.obj", False)

bpy.ops.mesh.primitive_cube_add(size=2)
cube = bpy.context.active_object
cube.name = "Cube"
for name, colour in (("Blue", (0, 0, 1, 1)), ("Red", (1, 0, 0, 1))):
    m = bpy.data.materials.new(name)
    m.diffuse_color = colour
    cube.data.materials.append(m)
for polygon in cube.data.polygons[:2]:
    polygon.material_index = 1
export(cube, "blender_cube.obj", True)

bpy.ops.mesh.primitive_cylinder_add(vertices=12, radius=1, depth=2)
cylinder = bpy.context.active_object
cylinder.name = "Cylinder"
export(cylinder, "blender_cylinder.obj", False)
