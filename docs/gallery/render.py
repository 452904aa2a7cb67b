"""Renders one GLB to a JPEG for the example gallery (docs/examples.md).

Run inside Blender: blender -b --factory-startup -P render.py -- model.glb picture.jpg
The camera looks down at the model from the front right and frames its bounding box, so
every picture shows its model whole at the same angle whatever its size.
"""

import math
import sys

import bpy
import numpy
from mathutils import Vector

# Blender 3.4's glTF importer still uses `np.bool`, which numpy 1.24 removed.
if "bool" not in numpy.__dict__:
    numpy.bool = bool

source, target = sys.argv[sys.argv.index("--") + 1 :][:2]

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=source)
meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
corners = [o.matrix_world @ Vector(c) for o in meshes for c in o.bound_box]
low = Vector(min(c[i] for c in corners) for i in range(3))
high = Vector(max(c[i] for c in corners) for i in range(3))
centre = (low + high) / 2
radius = max((high - low).length / 2, 1e-3)

scene = bpy.context.scene
camera_data = bpy.data.cameras.new("camera")
camera_data.lens_unit = "FOV"
# The angle is the height's: the picture is wider than tall, so the sphere fits both ways.
camera_data.sensor_fit = "VERTICAL"
camera_data.angle = math.radians(35)
camera = bpy.data.objects.new("camera", camera_data)
scene.collection.objects.link(camera)
direction = Vector((1.0, -1.3, 0.75)).normalized()
camera.rotation_euler = (-direction).to_track_quat("-Z", "Y").to_euler()
# Blender places the camera, along its view, where the box's corners just fill the picture;
# backing off a little leaves a margin.
fitted, _ = camera.camera_fit_coords(
    bpy.context.evaluated_depsgraph_get(), [x for c in corners for x in c]
)
camera.location = fitted + direction * radius * 0.12
camera_data.clip_start = radius * 0.01
camera_data.clip_end = radius * 10
scene.camera = camera

scene.render.engine = "BLENDER_WORKBENCH"
shading = scene.display.shading
shading.light = "STUDIO"
shading.color_type = "TEXTURE"
shading.show_cavity = True
shading.show_shadows = True
scene.world = bpy.data.worlds.new("world")
scene.world.color = (0.93, 0.94, 0.96)
scene.display_settings.display_device = "sRGB"
scene.view_settings.view_transform = "Standard"
scene.render.film_transparent = False
scene.render.resolution_x = 640
scene.render.resolution_y = 400
scene.render.resolution_percentage = 100
scene.render.image_settings.file_format = "JPEG"
scene.render.image_settings.color_mode = "RGB"
scene.render.image_settings.quality = 85
scene.render.filepath = target
bpy.ops.render.render(write_still=True)
