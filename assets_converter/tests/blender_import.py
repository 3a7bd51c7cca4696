# Imports a .glb into Blender headless and prints what arrived.
# usage: blender -b --factory-startup --python blender_import.py -- FILE.glb
import bpy, sys, time
import numpy
# Debian bookworm: Blender 3.4 glTF importer uses np.bool, removed in numpy 1.24 (python3-numpy 1.24.2).
if not hasattr(numpy, "bool"):
    numpy.bool = bool
path = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)
t = time.time()
res = bpy.ops.import_scene.gltf(filepath=path)
dt = time.time() - t
objs = bpy.data.objects
meshes = [o for o in objs if o.type == 'MESH']
lights = [o for o in objs if o.type == 'LIGHT']
cams = [o for o in objs if o.type == 'CAMERA']
tris = sum(sum(len(p.vertices) - 2 for p in o.data.polygons) for o in meshes)
print("RESULT", res, "seconds %.2f" % dt, "objects", len(objs), "meshes", len(meshes), "triangles", tris,
      "lights", len(lights), "cameras", len(cams), "materials", len(bpy.data.materials), "images", len(bpy.data.images))
w = bpy.data.objects.get("world")
if w: print("world dims (m)", tuple(round(d, 2) for d in w.dimensions))
