"""A .blend saved after a bake, opened in a fresh Blender (bad_input.py's saved_blend case made
it): the attribute is there, no solution is kept, the next bake is full and works."""
import os

import bpy
import numpy as np

import rt_common as rt

mod = rt.install_addon()
f = rt.arg("--file")
if f and os.path.abspath(bpy.data.filepath or "") != os.path.abspath(f):
    bpy.ops.wm.open_mainfile(filepath=f)
from radiosity.core import session   # noqa: E402  (the installed add-on)

meshes = [o for o in bpy.data.objects if o.type == "MESH"]
loaded = {o.name: rt.corner_colors(o) for o in meshes}
stats_loaded = rt.last_stats()
kept = sum(x.kept is not None for x in session.sessions().values())
ok, err, reports = rt.bake()
after = {o.name: rt.corner_colors(o) for o in meshes}
same = all(loaded[n] is not None and after[n] is not None
           and np.allclose(loaded[n], after[n], rtol=1e-5, atol=1e-7) for n in loaded)
rt.result(loaded={n: c is not None for n, c in loaded.items()},
          loaded_finite=all(c is None or bool(np.isfinite(c).all()) for c in loaded.values()),
          stats_loaded=stats_loaded, kept_solutions=kept, ok=ok, err=err, reports=reports,
          stats=rt.last_stats(), same_after_rebake=bool(same),
          attributes={n: rt.color_attr_names(o) for n, o in ((o.name, o) for o in meshes)})
