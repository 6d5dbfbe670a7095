"""4.2+: the same zip installs as an extension (module bl_ext.<repo>.radiosity) and bakes."""
import sys

import bpy

import rt_common as rt
import scenes

if bpy.app.version < (4, 2, 0):
    rt.result(skip=f"Blender {bpy.app.version_string} has no extensions")
    raise SystemExit(0)
rt.reset()
res = bpy.ops.extensions.package_install_files(filepath=rt.arg("--zip"), repo="user_default",
                                               enable_on_install=True)
mods = sorted(m for m in sys.modules if m.endswith("radiosity"))
objs = scenes.build_furnace(2)
ok = "FINISHED" in bpy.ops.radiosity.bake()
import numpy as np
vals = np.concatenate([rt.corner_colors(o) for o in objs])
rt.result(installed=list(res), modules=mods, ok=ok,
          max_rel_err=float(np.abs(vals[:, :3] / 2.0 - 1).max()),
          native=[m for m in sys.modules if m.endswith("radiosity_native")])
