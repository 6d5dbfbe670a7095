"""The scenes the trade-off and the accuracy benchmarks judge, and where their .blend files are.

The four example scenes (example_blends/), a lights room (bench/tradeoff/scenes/, made by
make_lights_room.py: point, spot, area and sun lights and a cube in a closed room) and a lamp
box (make_lamp_box.py: a closed Cornell-type box lit by a mesh lamp 1 cm under its ceiling).
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))

SCENES = ("cornell_box", "box_room", "chair_room", "full_room", "lights_room", "lamp_box")


def blend(name):
    own = os.path.join(HERE, "scenes", f"{name}.blend")
    return own if os.path.exists(own) else os.path.join(REPO, "example_blends", f"{name}.blend")


def ref(name, flavour="bpy", ref_dir=None):
    """The cached Cycles reference of scene NAME made in FLAVOUR's Blender: bpy (PyPI's bpy 5.x,
    refs/NAME_cycles5.npz, the ground truth) or binary (Debian's 3.4, refs/NAME_cycles.npz, whose
    Cycles reads mesh lamps seen at grazing angles too dark: bench/results/reference_bias.md)."""
    return os.path.join(ref_dir or os.path.join(HERE, "refs"),
                        f"{name}_cycles{'5' if flavour == 'bpy' else ''}.npz")
