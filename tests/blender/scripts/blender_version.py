"""The running Blender's version and the tag of its per-version reference files."""
import bpy

import rt_common as rt

v = bpy.app.version
rt.result(ok=True, blender=bpy.app.version_string,
          ref_tag="v3" if v < (4, 0, 0) else f"v{v[0]}_{v[1]}")
