"""The README demo, inside Blender: bake, render, move, re-bake incrementally, render again.

    blender -b example_blends/box_room.blend --python addon/tools/demo.py -- \
        --zip build/radiosity.zip --out demo_output [--preset MEDIUM] [--exposure -2.5]

Installs + enables the add-on zip (run it with BLENDER_USER_CONFIG / BLENDER_USER_SCRIPTS pointing
at a private directory so the user's own Blender setup is untouched; scripts/demo.sh does), bakes,
renders OUT/before.png with the Workbench engine (flat lighting, attribute colours, so the picture
shows exactly the baked radiance), applies scene["radiosity_move"], bakes again (full=False: the
incremental path), renders OUT/after.png, then bakes the moved scene from scratch (full=True) to
time the incremental update against it. Writes OUT/stats.json and prints a summary.
Exit code 1 on any failure.
"""
import argparse
import json
import math
import os
import sys
import time
import traceback

import bpy
import numpy as np


def parse(argv):
    argv = argv[argv.index("--") + 1:] if "--" in argv else []
    p = argparse.ArgumentParser(prog="demo.py")
    p.add_argument("--zip", required=True)
    p.add_argument("--out", default="demo_output")
    p.add_argument("--preset", default="MEDIUM")
    p.add_argument("--exposure", type=float, default=-1.3,
                   help="stops; the light's radiance is 12, the walls around 0.5-3")
    p.add_argument("--resolution", type=int, nargs=2, default=(800, 600))
    return p.parse_args(argv)


def install(zip_path):
    bpy.ops.preferences.addon_install(filepath=os.path.abspath(zip_path), overwrite=True)
    bpy.ops.preferences.addon_enable(module="radiosity")
    if not hasattr(bpy.ops.radiosity, "bake"):
        raise SystemExit("the radiosity add-on did not register")


def bake(**kw):
    res = bpy.ops.radiosity.bake(**kw)
    if "FINISHED" not in res:
        raise SystemExit(f"bake failed: {res}")
    return json.loads(bpy.context.scene.radiosity.last_stats)


def setup_render(scene, args):
    scene.render.engine = "BLENDER_WORKBENCH"
    shading = scene.display.shading
    shading.light = "FLAT"              # show the baked radiance, no extra lighting
    shading.color_type = "VERTEX"       # "Attribute" in the UI: the active colour attribute
    shading.show_shadows = False
    shading.show_cavity = False
    shading.show_specular_highlight = False
    shading.show_object_outline = False
    scene.display.render_aa = "8"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = args.exposure
    scene.view_settings.gamma = 1.0
    scene.render.resolution_x, scene.render.resolution_y = args.resolution
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.film_transparent = False


def render(scene, path):
    scene.render.filepath = path
    t = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    return time.perf_counter() - t


def make_active(name):
    for o in bpy.context.scene.objects:
        if o.type == "MESH" and name in o.data.color_attributes:
            o.data.color_attributes.active_color = o.data.color_attributes[name]


def apply_move(scene):
    """scene["radiosity_move"]: an object (or every top-level object of a collection) goes to
    `location` and turns `rotation_z_deg` about its local Z. Returns the moved names."""
    move = scene.get("radiosity_move")
    if not move:
        raise SystemExit('the scene has no scene["radiosity_move"]')
    name = move["object"]
    loc = np.array(move["location"], dtype=float)
    angle = math.radians(float(move.get("rotation_z_deg", 0.0)))
    if name in bpy.data.objects:
        objs, ref = [bpy.data.objects[name]], bpy.data.objects[name]
    elif name in bpy.data.collections:
        objs = [o for o in bpy.data.collections[name].all_objects if o.parent is None]
        if not objs:
            raise SystemExit(f"collection '{name}' has no objects to move")
        ref = objs[0]
    else:
        raise SystemExit(f"radiosity_move names '{name}', which is neither object nor collection")
    delta = loc - np.array(ref.location)
    for o in objs:
        o.location = tuple(np.array(o.location) + delta)
        o.rotation_euler.z += angle
    bpy.context.view_layer.update()
    return [o.name for o in objs]


def colours(scene, attr):
    return sys.modules["radiosity"].writer.read_colours(scene, attr)


def nrmse(a, b):
    keys = sorted(set(a) & set(b))
    x = np.concatenate([a[k] for k in keys])
    y = np.concatenate([b[k] for k in keys])
    return float(np.sqrt(np.mean((x - y) ** 2)) / np.sqrt(np.mean(y ** 2)))


def main():
    args = parse(sys.argv)
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    install(args.zip)
    scene = bpy.context.scene
    props = scene.radiosity
    props.preset = args.preset
    setup_render(scene, args)

    print(f"demo: baking {os.path.basename(bpy.data.filepath)} at {args.preset} …", flush=True)
    first = bake(full=True)
    make_active(props.attribute_name)
    t_before = render(scene, os.path.join(out, "before.png"))

    moved = apply_move(scene)
    print(f"demo: moved {', '.join(moved)}; incremental re-bake …", flush=True)
    incremental = bake(full=False)
    inc_colours = colours(scene, props.attribute_name)
    t_after = render(scene, os.path.join(out, "after.png"))

    print("demo: full re-bake of the moved scene (for the timing ratio) …", flush=True)
    full = bake(full=True)
    full_colours = colours(scene, props.attribute_name)

    ratio = incremental["seconds"] / full["seconds"] if full["seconds"] > 0 else None
    summary = {
        "blend": bpy.data.filepath, "blender": bpy.app.version_string, "preset": args.preset,
        "moved": moved, "move": {k: (list(v) if hasattr(v, "__len__") and not isinstance(v, str)
                                     else v) for k, v in dict(scene["radiosity_move"]).items()},
        "first_bake": first, "incremental_bake": incremental, "full_rebake": full,
        "incremental_over_full_seconds": ratio,
        "incremental_vs_full_nrmse": nrmse(inc_colours, full_colours),
        "render_seconds": {"before": t_before, "after": t_after},
        "exposure": args.exposure,
    }
    with open(os.path.join(out, "stats.json"), "w") as f:
        json.dump(summary, f, indent=2, sort_keys=True)
    print("")
    print("Radiosity demo — %s, preset %s" % (os.path.basename(bpy.data.filepath), args.preset))
    print(f"  first bake (full):       {first['seconds']:7.2f} s  {first['elements']} elements, "
          f"{first['links']} links")
    print(f"  after the move ({incremental['mode']}): {incremental['seconds']:7.2f} s  "
          f"{incremental.get('env_env_links_recomputed', 0)} env-env links recomputed"
          + (f"  (full because: {incremental['full_reason']})"
             if incremental.get("full_reason") else ""))
    print(f"  full re-bake, same scene: {full['seconds']:7.2f} s")
    if ratio is not None:
        print(f"  incremental / full time:  {ratio:7.2f}")
    print(f"  incremental vs full NRMSE: {summary['incremental_vs_full_nrmse'] * 100:.2f} %")
    print(f"  wrote {out}/before.png, after.png, stats.json")


try:
    main()
except SystemExit as exc:
    if exc.code not in (None, 0):
        print(f"demo failed: {exc.code}", file=sys.stderr)
        sys.exit(1)
except Exception:
    traceback.print_exc()
    sys.exit(1)
