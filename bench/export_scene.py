"""Export an example .blend's scene (as the add-on gathers it) plus its stored move to .npz,
so the native solver can be benchmarked outside Blender (bench/update_examples.py,
bench/accuracy_native.py).

    blender -b example_blends/box_room.blend --python bench/export_scene.py -- OUT.npz

Per object i: o{i}_vertices, _loop_starts, _loop_totals, _corner_verts (Blender's order),
_reflectance, _emission; o{i}_two_sided and o{i}_occluder when not the defaults (an area
light: one-sided, casts no shadow), o{i}_corner_perm for a mirrored object (the solver gets
corner_verts[perm] and its output is mapped back with the same permutation), o{i}_corner_map
for a modifier's evaluated mesh (per corner of the mesh written, the evaluated corner it reads:
the solver gathers only at those), o{i}_written
(False for what the add-on gathers but never writes: area lights, unwritable meshes,
instances) and o{i}_output when False (the same objects: the solver gathers no light at
their corners, core.scene_data.ObjectInput.output);
"lights": JSON of the Blender lights and the world (core.lights.LightInput fields).
"""
import json
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "addon"))
from radiosity import gather as rgather  # noqa: E402  (the add-on's own gather, from source)


def main():
    out = sys.argv[sys.argv.index("--") + 1]
    scene = bpy.context.scene
    vl = bpy.context.view_layer
    si, _, _ = rgather.gather(scene, vl, bpy.context.evaluated_depsgraph_get())
    arrays = {"clusters": np.array([f"{c.name}\t{c.parent}" for c in si.clusters])}
    names = []
    for i, o in enumerate(si.objects):
        names.append(f"{o.name}\t{o.cluster}")
        for k in ("vertices", "loop_starts", "loop_totals", "corner_verts", "reflectance", "emission"):
            arrays[f"o{i}_{k}"] = getattr(o, k)
        if o.two_sided is not None:
            arrays[f"o{i}_two_sided"] = np.asarray(o.two_sided, np.uint8)
        if not o.occluder:
            arrays[f"o{i}_occluder"] = np.array(False)
        if o.corner_perm is not None:
            arrays[f"o{i}_corner_perm"] = np.asarray(o.corner_perm, np.int64)
        if o.corner_map is not None:
            arrays[f"o{i}_corner_map"] = np.asarray(o.corner_map, np.int64)
        arrays[f"o{i}_written"] = np.array(o.target is not None)
        if not o.output:
            arrays[f"o{i}_output"] = np.array(False)
    arrays["objects"] = np.array(names)
    arrays["lights"] = np.array(json.dumps([dict(vars(li)) for li in si.lights], default=float))
    mv = scene.get("radiosity_move")
    if mv is not None:
        # The stored move applied as the demo applies it (addon/tools/demo.py): an object, or
        # every top-level object of a collection, goes to `location` (the first one's) and
        # turns `rotation_z_deg` about its local Z. Exported per moved object as the rigid
        # world delta M_after @ inv(M_before).
        import math
        name = mv["object"]
        if name in bpy.data.objects:
            objs = [bpy.data.objects[name]]
        else:
            objs = [o for o in bpy.data.collections[name].all_objects if o.parent is None]
        before = {o.name: np.array(o.matrix_world) for o in objs}
        delta = np.array(mv["location"], dtype=float) - np.array(objs[0].location)
        for o in objs:
            o.location = tuple(np.array(o.location) + delta)
            o.rotation_euler.z += math.radians(float(mv.get("rotation_z_deg", 0.0)))
        vl.update()
        index = {o.name: i for i, o in enumerate(si.objects)}
        moved = [(index[o.name], np.array(o.matrix_world) @ np.linalg.inv(before[o.name]))
                 for o in objs if o.name in index]
        arrays["move_ids"] = np.array([m[0] for m in moved], dtype=np.int32)
        arrays["move_deltas"] = np.array([m[1] for m in moved])
    np.savez_compressed(out, **arrays)
    print("exported", len(si.objects), "objects,", si.polygon_count, "polygons to", out)


main()
