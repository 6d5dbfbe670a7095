"""The optional sRGB byte copy (game export) on the furnace: every corner is B = E/(1-rho) = 2,
so the byte copy at exposure x is the sRGB encoding of min(2 * 2^x, 1). Checks the bytes against
an independent encoding of the float attribute written by the same bake, and against the exact
value; the float attribute stays the active/render one; re-bakes (cached) change only the bytes.
"""
import math

import bpy
import numpy as np

import rt_common as rt
import scenes

rt.setup()
objs = scenes.build_furnace(3)
props = bpy.context.scene.radiosity
props.preset = "DRAFT"
props.byte_copy = True
BYTE = props.attribute_name + "_sRGB"


def encode(x):
    """sRGB byte of linear x (IEC 61966-2-1), clamped: written out here, not imported."""
    x = min(max(x, 0.0), 1.0)
    s = 12.92 * x if x <= 0.0031308 else 1.055 * x ** (1 / 2.4) - 0.055
    return int(math.floor(s * 255 + 0.5))


def read_bytes(o):
    attr = o.data.color_attributes.get(BYTE)
    if attr is None:
        return None
    buf = np.empty(len(o.data.loops) * 4, np.float32)
    attr.data.foreach_get("color_srgb", buf)
    return np.rint(buf.reshape(-1, 4) * 255).astype(int)


def check(exposure):
    props.exposure = exposure
    ok, err, reports = rt.bake()
    got = np.concatenate([read_bytes(o) for o in objs])
    floats = np.concatenate([rt.corner_colors(o)[:, :3] for o in objs])
    from_floats = np.array([[encode(v * 2.0 ** exposure) for v in row] for row in floats])
    exact = encode(scenes.FURNACE_E / (1 - scenes.FURNACE_RHO) * 2.0 ** exposure)
    return {
        "ok": ok, "err": err, "stats": rt.last_stats(),
        "match_floats": bool(np.array_equal(got[:, :3], from_floats)),
        "max_off_exact": int(np.abs(got[:, :3] - exact).max()),
        "exact": exact, "alpha_255": bool(np.all(got[:, 3] == 255)),
        "types": sorted({(a.name, a.data_type, a.domain) for o in objs for a in o.data.color_attributes}),
        "active": sorted({o.data.color_attributes.active_color.name for o in objs}),
        "render": sorted({o.data.color_attributes[o.data.color_attributes.render_color_index].name
                          for o in objs}),
    }


out = {"m2": check(-2.0), "p3": check(3.0), "m6": check(-6.0)}
# Off: the byte copy is neither written nor updated (the float bake is).
before = np.concatenate([read_bytes(o) for o in objs])
props.byte_copy = False
props.exposure = 0.0
ok, err, _ = rt.bake()
out["off_ok"] = ok
out["off_untouched"] = bool(np.array_equal(before, np.concatenate([read_bytes(o) for o in objs])))
out["fake"] = rt.native_is_fake()
rt.result(**out)
