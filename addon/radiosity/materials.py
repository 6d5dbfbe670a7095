"""Material -> (reflectance, emission) for the solver.

Supported, following the link into the active Material Output's Surface input (through reroutes):
  Diffuse BSDF (Color), Principled BSDF (diffuse part: Base Color x (1-metallic) x (1-transmission),
  times a factor measured by Cycles (principled.py): in Blender 4.0+ the share the specular
  layers leave to the diffuse, in 3.x the brightening of its retro-reflective Disney diffuse
  (1.036 at roughness 1);
  emission colour x strength; socket names differ: 3.x "Emission", 4.x "Emission Color"),
  Emission (Color x Strength), Mix Shader (constant Fac: linear mix) and Add Shader (sum).
Anything else (textures or links into the used colour sockets, groups, other BSDFs) is
"textured": Cycles evaluates it at the surface (textures.py); until then, and if that fails, it
stands for the material's viewport colour ``diffuse_color`` with no emission. No material ->
grey 0.8. A material without nodes uses diffuse_color, as Cycles does.
"""
import bpy
import numpy as np

from . import principled

from .core.scene_data import DEFAULT_REFLECTANCE, MAX_REFLECTANCE

_ZERO = np.zeros(3, dtype=np.float64)


class Unsupported(Exception):
    pass


def _rgb(value):
    return np.array(tuple(value)[:3], dtype=np.float64)


def _input(node, *names):
    """First input socket found under one of the names (version differences)."""
    for name in names:
        sock = node.inputs.get(name)
        if sock is not None:
            return sock
    return None


def _const(node, names, kind):
    sock = _input(node, *names)
    if sock is None:
        return None
    if sock.is_linked:
        raise Unsupported(f"'{node.name}' input '{sock.name}' is driven by a link (texture?)")
    if kind == "color":
        return _rgb(sock.default_value)
    return float(sock.default_value)


def _follow(socket):
    """Node feeding a socket, skipping reroutes and muted links."""
    links = [l for l in socket.links if not getattr(l, "is_muted", False)]
    if not links:
        return None
    node = links[0].from_node
    seen = 0
    while node.type == "REROUTE" and seen < 64:
        links = [l for l in node.inputs[0].links if not getattr(l, "is_muted", False)]
        if not links:
            return None
        node, seen = links[0].from_node, seen + 1
    return node


def _shader(node, depth=0):
    """(rho, emission) of a shader node; raises Unsupported."""
    if node is None:
        return _ZERO.copy(), _ZERO.copy()     # unconnected shader input = black, like Cycles
    if depth > 32:
        raise Unsupported("shader tree too deep")
    if getattr(node, "mute", False):
        raise Unsupported(f"muted node '{node.name}'")
    t = node.type
    if t == "BSDF_DIFFUSE":
        return _const(node, ("Color",), "color"), _ZERO.copy()
    if t == "EMISSION":
        color = _const(node, ("Color",), "color")
        strength = _const(node, ("Strength",), "float")
        return _ZERO.copy(), color * strength
    if t == "BSDF_PRINCIPLED":
        base = _const(node, ("Base Color",), "color")
        metallic = _const(node, ("Metallic",), "float") or 0.0
        transmission = _const(node, ("Transmission Weight", "Transmission"), "float") or 0.0
        # Blender 4.0+: Cycles takes from the diffuse what the specular layers above reflect.
        rho = base * principled.diffuse_factor(node) * (1.0 - metallic) * (1.0 - transmission)
        e_col = _const(node, ("Emission Color", "Emission"), "color")
        e_str = _const(node, ("Emission Strength",), "float")
        emission = _ZERO.copy()
        if e_col is not None:
            emission = e_col * (1.0 if e_str is None else e_str)
        return rho, emission
    if t == "MIX_SHADER":
        fac = _const(node, ("Fac",), "float")
        fac = min(max(fac, 0.0), 1.0)
        r1, e1 = _shader(_follow(node.inputs[1]), depth + 1)
        r2, e2 = _shader(_follow(node.inputs[2]), depth + 1)
        return (1 - fac) * r1 + fac * r2, (1 - fac) * e1 + fac * e2
    if t == "ADD_SHADER":
        r1, e1 = _shader(_follow(node.inputs[0]), depth + 1)
        r2, e2 = _shader(_follow(node.inputs[1]), depth + 1)
        return r1 + r2, e1 + e2
    raise Unsupported(f"node '{node.name}' of type {t} is not supported")


def _output_node(tree):
    outputs = [n for n in tree.nodes if n.type == "OUTPUT_MATERIAL"]
    for n in outputs:
        if n.is_active_output and n.target in ("ALL", "CYCLES"):
            return n
    for n in outputs:
        if n.target in ("ALL", "CYCLES"):
            return n
    return outputs[0] if outputs else None


def material_values(mat):
    """(rho(3), emission(3), warning_or_None) for one material (unclamped)."""
    if mat is None:
        return np.full(3, DEFAULT_REFLECTANCE), _ZERO.copy(), None
    if mat.node_tree is None or (bpy.app.version < (5, 0, 0) and not mat.use_nodes):
        # 5.0 deprecates use_nodes (materials always use nodes), so read it only before 5.0.
        return _rgb(mat.diffuse_color), _ZERO.copy(), None
    try:
        out = _output_node(mat.node_tree)
        if out is None:
            raise Unsupported("no Material Output node")
        surface = out.inputs.get("Surface")
        if surface is None or not surface.is_linked:
            # Cycles renders an output with nothing linked as black.
            return _ZERO.copy(), _ZERO.copy(), None
        rho, emission = _shader(_follow(surface))
        return rho, emission, None
    except Unsupported as why:
        return (_rgb(mat.diffuse_color), _ZERO.copy(),
                f"material '{mat.name}': {why}; using its viewport colour (diffuse_color) "
                f"and no emission")


class MaterialTable:
    """Per-bake cache: each material is analysed (and warned about) once."""

    def __init__(self):
        self._values = {}
        self.warnings = []
        # name_full -> the reason the node tree has no constant value: Cycles evaluates these
        # (textures.py); the fallback warning is kept in case that cannot be done.
        self.textured = {}

    def get(self, mat):
        key = None if mat is None else mat.name_full
        hit = self._values.get(key)
        if hit is None:
            rho, emission, warning = material_values(mat)
            self.warnings.extend(principled.pop_errors())
            hit = self._values[key] = (rho, emission)
            if warning:
                self.textured[key] = warning
            else:
                self._check_range(mat, rho, emission)
        return hit

    def is_textured(self, mat):
        return mat is not None and mat.name_full in self.textured

    def _check_range(self, mat, rho, emission):
        """One warning per material whose values the bake changes (README "Materials"): the
        clamps keep the solve convergent, but Cycles would render these differently. NaN/inf
        are not handled here: the object using the material is refused (gather.py)."""
        if mat is None:
            return
        with np.errstate(invalid="ignore"):
            if (emission < 0.0).any():
                self.warnings.append(
                    f"material '{mat.name}': negative emission {_fmt(emission)} is treated as 0 "
                    f"(no negative light)")
            # rho = 1 (a white material) is clamped silently: 0.999 is what a user means.
            if (rho > 1.0).any():
                self.warnings.append(
                    f"material '{mat.name}': reflectance {_fmt(rho)} above 1 (it would create "
                    f"light) is clamped to {MAX_REFLECTANCE}")
            if (rho < 0.0).any():
                self.warnings.append(
                    f"material '{mat.name}': negative reflectance {_fmt(rho)} is treated as 0")


def _fmt(rgb):
    return "(" + ", ".join(f"{float(x):.4g}" for x in rgb) + ")"
