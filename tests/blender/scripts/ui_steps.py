"""Drive interactive Blender (under Xvfb) step by step from a timer: the window's context,
the Radiosity sidebar, screenshots and pixel comparisons of parts of them.

A step is a callable returning None (go on to the next step), a number (call it again after
that many seconds: waiting for a job) or raising (the run ends with the traceback in
RESULT["exception"]). The timer is persistent: steps may open files.
"""
import os
import sys
import time
import traceback

import bpy
import numpy as np

import rt_common as rt

out = {}
SHOTS = rt.arg("--shots") or "."
WAIT_STEP = 0.2


def window():
    return bpy.context.window_manager.windows[0]


def area(kind="VIEW_3D"):
    return next(a for a in window().screen.areas if a.type == kind)


def ctx(kind="VIEW_3D", region="WINDOW"):
    """Context of the 3D viewport (as a click in it has), for bpy.ops calls from a timer."""
    win, a = window(), area(kind)
    return dict(window=win, screen=win.screen, area=a,
                region=next(r for r in a.regions if r.type == region))


def finish():
    rt.result(**out)
    sys.stdout.flush()
    os._exit(0)         # quitting may ask to save; leave once RESULT is printed


def run(*steps, first=1.0):
    queue = list(steps)

    def tick():
        try:
            if not queue:
                finish()
            again = queue[0]()
            if again is None:
                queue.pop(0)
                return WAIT_STEP
            return float(again)
        except Exception:
            out["exception"] = traceback.format_exc()
            finish()

    bpy.app.timers.register(tick, first_interval=first, persistent=True)


class Waiter:
    """wait(cond, timeout) as a step: repeats until cond() is true; a timeout fails the run."""

    def __init__(self, cond, timeout, what):
        self.cond, self.timeout, self.what, self.t0 = cond, timeout, what, None

    def __call__(self):
        if self.t0 is None:
            self.t0 = time.monotonic()
        if self.cond():
            self.t0 = None
            return None
        if time.monotonic() - self.t0 > self.timeout:
            raise TimeoutError(f"waited {self.timeout} s for {self.what}")
        return WAIT_STEP


def pause(seconds):
    """Step: let Blender run (redraw, handle events) for `seconds`."""
    state = {}

    def step():
        if "t" not in state:
            state["t"] = time.monotonic()
        if time.monotonic() - state["t"] < seconds:
            return WAIT_STEP
        state.clear()
        return None
    return step


def install_and_open(blend):
    bpy.ops.preferences.addon_install(filepath=os.path.abspath(rt.arg("--zip")), overwrite=True)
    bpy.ops.preferences.addon_enable(module="radiosity")
    if blend:
        bpy.ops.wm.open_mainfile(filepath=blend)


def addon():
    return sys.modules["radiosity"]


def live_state():
    mod = addon()
    return mod.core.session.session(mod.bake.scene_key(bpy.context.scene)).live


def live_runs():
    return sum(st.runs for st in (x.live for x in addon().core.session.sessions().values()))


def open_sidebar():
    """Step: the 3D viewport's sidebar open, nothing selected or active (so its tabs are
    Tool, View, Radiosity: see click_radiosity_tab)."""
    area().spaces.active.show_region_ui = True
    bpy.context.view_layer.objects.active = None
    for o in bpy.context.view_layer.objects:
        o.select_set(False)


def click_radiosity_tab():
    """Step: a click on the sidebar's Radiosity tab (Blender 3.4 offers no Python way to pick
    a tab). With the tabs Tool, View, Radiosity it lies about 126 px below the region's top
    at UI scale 1, 14 px in from its right edge."""
    a = area()
    reg = next(r for r in a.regions if r.type == "UI")
    x, y = reg.x + reg.width - 14, reg.y + reg.height - 126
    win = window()
    win.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    win.event_simulate(type="LEFTMOUSE", value="PRESS", x=x, y=y)
    win.event_simulate(type="LEFTMOUSE", value="RELEASE", x=x, y=y)
    # Park the pointer in the viewport (hovering the tab would raise its tooltip).
    mid = next(r for r in a.regions if r.type == "WINDOW")
    win.event_simulate(type="MOUSEMOVE", value="NOTHING", x=mid.x + 40, y=mid.y + 40)


def screenshot(name):
    path = os.path.join(SHOTS, name + ".png")
    with bpy.context.temp_override(**ctx()):
        bpy.ops.screen.screenshot(filepath=path)
    return path


def pixels(path, box=None):
    """RGB of a screenshot as (H, W, 3) float, rows from the bottom (Blender's order); box =
    (x0, y0, x1, y1) in window pixels from the bottom left."""
    img = bpy.data.images.load(path, check_existing=False)
    try:
        w, h = img.size
        px = np.empty(w * h * 4, np.float32)
        img.pixels.foreach_get(px)
    finally:
        bpy.data.images.remove(img)
    px = px.reshape(h, w, 4)[:, :, :3]
    if box is not None:
        x0, y0, x1, y1 = box
        px = px[y0:y1, x0:x1]
    return px


def region_box(kind, region):
    a = area(kind)
    r = next(r for r in a.regions if r.type == region)
    return (r.x, r.y, r.x + r.width, r.y + r.height)


def statusbar_box():
    a = area("STATUSBAR")
    return (a.x, a.y, a.x + a.width, a.y + a.height)


def differs(path_a, path_b, box):
    """Do two screenshots differ inside box (any pixel changed)?"""
    return bool(np.abs(pixels(path_a, box) - pixels(path_b, box)).max() > 0.02)


def colours(names=None, attribute="Radiosity"):
    """{object: (corners, 3) float} of every mesh holding the attribute."""
    res = {}
    for o in bpy.data.objects:
        if o.type == "MESH" and (names is None or o.name in names):
            c = rt.corner_colors(o, attribute)
            if c is not None:
                res[o.name] = c[:, :3].copy()
    return res

