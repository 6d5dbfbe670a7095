"""(a) Closed furnace: every corner must be E/(1-rho) = 2."""
import numpy as np

import rt_common as rt
import scenes

rt.setup()
objs = scenes.build_furnace(int(rt.arg("--n", "4")))
import bpy
bpy.context.scene.radiosity.preset = rt.arg("--preset", "MEDIUM")
ok, err, reports = rt.bake()
vals = np.concatenate([rt.corner_colors(o) for o in objs]) if ok else np.zeros((0, 4))
expect = scenes.FURNACE_E / (1 - scenes.FURNACE_RHO)
rt.result(ok=ok, err=err, reports=reports, stats=rt.last_stats(),
          max_rel_err=float(np.abs(vals[:, :3] / expect - 1).max()) if len(vals) else None,
          alpha_ok=bool(np.all(vals[:, 3] == 1.0)) if len(vals) else None,
          corners=int(len(vals)), fake=rt.native_is_fake())
