"""Live re-bakes and progress in interactive Blender (Xvfb, 1600x1000): what the user sees
while a bake or a live re-bake runs, and why a live re-bake solved from scratch.

Part A, box_room.blend at MEDIUM: the modal bake's status bar moves while the native progress
rests on one figure; a live re-bake after a move shows itself in the status bar and the panel
and clears both when done; the panel then describes the update the user watched.
Part B, a closed crate in a room: moving a cube into it makes the live re-bake solve in full,
and the panel says why.
"""
import os
import time

import bpy

import rt_common as rt
import ui_steps as ui
from ui_moves import move, when_live_job
from ui_steps import out

EXAMPLE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                       "example_blends", "box_room.blend")
S = {}


def scene():
    return bpy.context.scene


def op(fn, *args, **kw):
    with bpy.context.temp_override(**ui.ctx()):
        return sorted(fn(*args, **kw))


def quiet():
    st = ui.live_state()
    return st.job is None and not st.pending


def setup():
    ui.install_and_open(os.path.abspath(EXAMPLE))


def prepare():
    scene().radiosity.preset = "MEDIUM"
    op(bpy.ops.radiosity.show_colors)


def idle_shot():
    S["idle"] = ui.screenshot("0_idle")


def bake_button():
    S["stats_before"] = scene().radiosity.last_stats
    out["invoke"] = op(bpy.ops.radiosity.bake, "INVOKE_DEFAULT")
    S["t0"] = time.monotonic()
    S["progress"] = []


def bake_running():
    """Two screenshots of the running modal bake, a second and more apart, with the native
    progress at each."""
    done = scene().radiosity.last_stats != S["stats_before"]
    t = time.monotonic() - S["t0"]
    job = getattr(bpy.context.window_manager, "operators", None)
    if not done and t >= 1.5 and "modal_a" not in S:
        S["modal_a"] = ui.screenshot("1_modal_a")
        return 1.6
    if not done and "modal_a" in S and "modal_b" not in S:
        S["modal_b"] = ui.screenshot("1_modal_b")
        return 0.1
    if done:
        out["modal_seconds"] = t
        return None
    return 0.1


def modal_compare():
    if "modal_b" in S:
        out["modal_statusbar_moves"] = ui.differs(S["modal_a"], S["modal_b"], statusbar())
        out["modal_statusbar_busy"] = ui.differs(S["idle"], S["modal_a"], statusbar())
    else:
        out["modal_too_fast"] = True


def statusbar():
    win = ui.window()
    return (0, 0, win.width, 18)


def sidebar():
    return ui.region_box("VIEW_3D", "UI")


def live_on():
    scene().radiosity.live = True
    S["baked"] = ui.screenshot("2_baked")
    out["stats_baked"] = rt.last_stats()


def live_running(st):
    if "job_seen" not in S:
        S["job_seen"] = time.monotonic()
        # The move was previewed before the debounced update began (by the preview timer, or by
        # the live timer just before it starts the update when a busy main thread runs both).
        out["previews_at_job_start"] = st.previews
        out["last_preview"] = st.last_preview
        out["preview_skipped"] = st.preview_skipped
    if time.monotonic() - S["job_seen"] < 1.2:
        return ui.WAIT_STEP
    S["running"] = ui.screenshot("3_live_running")
    out["live_status_text"] = ui.addon().handlers.live_status_text(st)
    out["live_progress"] = st.progress
    return None


def live_done():
    S["done"] = ui.screenshot("4_live_done")
    stats = rt.last_stats()
    out["live_stats"] = {k: stats.get(k) for k in ("mode", "live", "cached", "full_reason")}
    out["live_describe"] = ui.addon().core.stats.describe(stats)
    if "running" in S:
        out["running_statusbar_shown"] = ui.differs(S["baked"], S["running"], statusbar())
        out["running_panel_shown"] = ui.differs(S["baked"], S["running"], sidebar())
        out["done_statusbar_cleared"] = not ui.differs(S["baked"], S["done"], statusbar())


# -- part B: a closed crate ---------------------------------------------------------------------
def pocket_scene():
    sc = bpy.data.scenes.new("Pocket")
    ui.window().scene = sc
    rt.black_world()
    wall = rt.diffuse_material("Wall", (0.7, 0.7, 0.7))
    grey = rt.diffuse_material("Crate", (0.6, 0.6, 0.6))
    lamp = rt.emission_material("Lamp", (1, 1, 1), 10.0)
    v, f = rt.box((1.5, 1.5, 1.25), (3, 3, 2.5), inward=True)
    rt.mesh_object("Room", v, f, None, wall)
    v, f = rt.grid((1.25, 1.25, 2.4), (0, 0.5, 0), (0.5, 0, 0), 1)     # faces down
    rt.mesh_object("Lamp", v, f, None, lamp)
    v, f = rt.box((0.8, 0.8, 0.55), (1.0, 1.0, 1.0))
    rt.mesh_object("Crate", v, f, rt.new_collection("Crate"), grey)
    v, f = rt.box((0.0, 0.0, 0.0), (0.2, 0.2, 0.2))
    cube = rt.mesh_object("Cube", v, f, rt.new_collection("CubeColl"), grey)
    cube.location = (2.1, 2.1, 0.2)
    sc.radiosity.preset = "DRAFT"
    sc.radiosity.live = True
    op(bpy.ops.radiosity.show_colors)
    out["pocket_bake"] = op(bpy.ops.radiosity.bake)


def pocket_done():
    stats = rt.last_stats()
    out["pocket_stats"] = {k: stats.get(k) for k in ("mode", "live", "cached", "full_reason")}
    out["pocket_describe"] = ui.addon().core.stats.describe(stats)
    ui.screenshot("5_pocket_full")


ui.run(
    setup, prepare, ui.open_sidebar, ui.click_radiosity_tab, idle_shot,
    bake_button, bake_running, modal_compare,
    ui.Waiter(quiet, 60, "quiet"), live_on,
    move(lambda: bpy.data.objects["Box1"], lambda: scene()["radiosity_move"]["location"], S),
    when_live_job(live_running, S, "live_too_fast"),
    ui.Waiter(lambda: ui.live_runs() > S["runs"] and quiet(), 300, "the live re-bake"),
    live_done,
    pocket_scene, move(lambda: bpy.data.objects["Cube"], lambda: (0.8, 0.8, 0.2), S),
    ui.Waiter(lambda: ui.live_runs() > S["runs"] and quiet(), 120, "the live re-bake"),
    pocket_done, ui.finish)
