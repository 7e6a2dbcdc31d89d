"""Makes the textured OBJ test files and Blender's own GLB of them (run once;
the outputs are committed):

    blender -b --factory-startup -noaudio --python-exit-code 1 \\
        --python tests/data/obj/textured/make_textured.py -- tests/data/obj/textured

- tex/checker.png, tex/checker.jpg and tex/normal.png: 4 x 4 images made
  here (the last a normal map);
- grid.obj + grid.mtl: a grid of quads (UVs of the grid) with three
  materials, "Png" (map_Kd tex/checker.png), "Jpeg" (map_Kd tex/checker.jpg,
  map_Bump -bm 0.5 tex/normal.png) and "Glass" (Kd 0.2 0.4 0.6, d 0.5,
  Ke 0.1 0.2 0.3), each Ns 250, exported by Blender 3.4's OBJ exporter with
  relative texture paths (the quads take the materials in turn: Png, Jpeg,
  Glass, Jpeg);
- blender-grid.glb: Blender 3.4's glTF export of Blender's own import of
  grid.obj (the independent conversion vn's is compared with).
"""
import os
import sys

import bpy

out = sys.argv[sys.argv.index("--") + 1]
os.makedirs(os.path.join(out, "tex"), exist_ok=True)
bpy.ops.wm.read_factory_settings(use_empty=True)

images = {}
for name, fmt, pixels in (("checker.png", "PNG", ((1, 1, 1, 1), (0.2, 0.3, 0.9, 1))),
                          ("checker.jpg", "JPEG", ((1, 1, 1, 1), (0.2, 0.3, 0.9, 1))),
                          ("normal.png", "PNG", ((0.5, 0.5, 1, 1), (0.6, 0.5, 0.9, 1)))):
    img = bpy.data.images.new(name, 4, 4)
    img.pixels = [v for i in range(16) for v in pixels[(i + i // 4) % 2]]
    img.filepath_raw = os.path.join(out, "tex", name)
    img.file_format = fmt
    img.save()
    images[name] = bpy.data.images.load(img.filepath_raw)


def material(name, colour, image=None, alpha=1.0, normal=None, emission=None):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes, links = m.node_tree.nodes, m.node_tree.links
    bsdf = nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = colour
    bsdf.inputs["Alpha"].default_value = alpha
    if image:
        tex = nodes.new("ShaderNodeTexImage")
        tex.image = image
        links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    if normal:
        tex = nodes.new("ShaderNodeTexImage")
        tex.image = normal
        tex.image.colorspace_settings.name = "Non-Color"
        node = nodes.new("ShaderNodeNormalMap")
        node.inputs["Strength"].default_value = 0.5
        links.new(tex.outputs["Color"], node.inputs["Color"])
        links.new(node.outputs["Normal"], bsdf.inputs["Normal"])
    if emission:
        bsdf.inputs["Emission"].default_value = emission
    return m


bpy.ops.mesh.primitive_grid_add(x_subdivisions=2, y_subdivisions=2, size=2, calc_uvs=True)
grid = bpy.context.active_object
grid.name = "Grid"
mats = [material("Png", (1, 1, 1, 1), images["checker.png"]),
        material("Jpeg", (1, 1, 1, 1), images["checker.jpg"], normal=images["normal.png"]),
        material("Glass", (0.2, 0.4, 0.6, 1), alpha=0.5, emission=(0.1, 0.2, 0.3, 1))]
for m in mats:
    grid.data.materials.append(m)
for i, poly in enumerate(grid.data.polygons):
    poly.material_index = (0, 1, 2, 1)[i % 4]
obj = os.path.join(out, "grid.obj")
bpy.ops.wm.obj_export(filepath=obj, export_uv=True, export_normals=True, export_materials=True,
                      path_mode="RELATIVE", export_triangulated_mesh=False)

bpy.ops.wm.read_factory_settings(use_empty=True)
# Axes that leave every coordinate as the OBJ has it.
bpy.ops.wm.obj_import(filepath=obj, forward_axis="Y", up_axis="Z")
bpy.ops.export_scene.gltf(filepath=os.path.join(out, "blender-grid.glb"), export_format="GLB", export_yup=False)
