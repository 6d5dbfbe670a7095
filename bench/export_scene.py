"""Export an example .blend's scene (as the add-on gathers it) plus its stored move to .npz,
so the native solver can be benchmarked outside Blender (bench/update_examples.py).

    blender -b example_blends/box_room.blend --python bench/export_scene.py -- OUT.npz
"""
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
    arrays["objects"] = np.array(names)
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
