"""scene.radiosity PropertyGroup."""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, StringProperty

from .core import presets
from .bake import STATS_KEY

# What each preset gives and costs, as measured on the example rooms, the Cornell box and a room
# with point, spot, area and sun lights against converged Blender 5.x Cycles bakes (bench/results/
# presets_sweep.md, tradeoff.md): per-corner error (rRMSE) and time.
_PRESET_ITEMS = [
    ("DRAFT", "Draft", "Quick: about 3-7 % error per corner against a converged Cycles bake, "
                       "a fifth of Medium's time"),
    ("MEDIUM", "Medium", "Balanced: about 1-2 % error per corner, a few seconds on a furnished room"),
    ("HIGH", "High", "Fine: about 1-1.6 % error per corner, sharper at contacts and on textures, "
                     "2-3 times Medium's time"),
    ("CUSTOM", "Custom", "Medium with your own error threshold"),
]


def _get_last_stats(self):
    return self.get(STATS_KEY, "")


def _live_update(self, context):
    from . import handlers
    handlers.live_toggled(self, context)


class RadiositySceneSettings(bpy.types.PropertyGroup):
    preset: EnumProperty(name="Preset", items=_PRESET_ITEMS, default="MEDIUM",
                         description="Quality preset of the solver")
    error_threshold: FloatProperty(
        name="Error Threshold", default=presets.DEFAULT_ERROR_THRESHOLD, min=1e-6, max=1.0,
        soft_min=1e-4, soft_max=0.5, precision=4,
        description="Relative error threshold of the refinement (Custom preset only); "
                    "smaller is finer and slower")
    attribute_name: StringProperty(name="Attribute", default="Radiosity",
                                   description="Colour attribute that receives the bake")
    lighting_only: BoolProperty(
        name="Lighting Only", default=False,
        description="Bake the light arriving at each surface (irradiance / pi: what a white "
                    "diffuse surface would reflect) instead of its outgoing radiance; the "
                    "surface's own colour and emission are left out")
    adaptive_mesh: BoolProperty(
        name="Adaptive Mesh", default=False,
        description="Also build, per baked object, a new mesh object from the solver's "
                    "elements (finer where shadows need it) carrying the colours; the original "
                    "is not modified")
    byte_copy: BoolProperty(
        name="8-bit sRGB Copy", default=False,
        description="Also write a BYTE_COLOR corner attribute named <attribute>_sRGB for game "
                    "export: the baked values times 2^exposure, sRGB-encoded and clamped to "
                    "[0, 1] (8 bits per channel)")
    exposure: FloatProperty(
        name="Exposure", default=0.0, min=-64.0, max=64.0, soft_min=-10.0, soft_max=10.0,
        step=10, precision=2, unit="NONE",
        description="Stops applied to the sRGB byte copy only (x 2^exposure before encoding); "
                    "the float attribute keeps Cycles' units")
    live: BoolProperty(name="Live", default=False, update=_live_update,
                       description="Re-bake automatically when baked objects are moved")
    # Read-only: a getter without a setter. The value lives in an ID property so that it is
    # saved with the file and restored by undo.
    last_stats: StringProperty(name="Last Stats", get=_get_last_stats,
                               description="JSON statistics of the last bake")


def register():
    bpy.utils.register_class(RadiositySceneSettings)
    bpy.types.Scene.radiosity = bpy.props.PointerProperty(type=RadiositySceneSettings)


def unregister():
    del bpy.types.Scene.radiosity
    bpy.utils.unregister_class(RadiositySceneSettings)
