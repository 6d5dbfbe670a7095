"""Bad input the core must refuse, and what an incremental job reports as its work."""
import math

import numpy as np
import pytest

from radiosity.core import job, lights, presets, scene_data

import scenes_np


# Each test starts and ends with no kept solution (conftest.py).
pytestmark = pytest.mark.usefixtures("no_kept_solutions")


def _job(native, si, key="scene", use_cache=True):
    return job.SolveJob(native, si, presets.make_settings(native, "DRAFT"),
                        presets.settings_key("DRAFT", 0.05), cache_key=key, use_cache=use_cache)


def test_incremental_job_reports_the_rays_of_the_update_not_the_running_total(native):
    first = _job(native, scenes_np.room()).prepare().run()
    full_rays = first.native_stats()["rays"]
    assert full_rays > 0
    inc = _job(native, scenes_np.room((0.3, 0.2))).prepare()
    assert inc.mode == "incremental"
    inc.run()
    st = inc.native_stats()
    # The native counter runs on from the full solve; the job reports the difference.
    assert st["rays_cumulative"] == full_rays + st["rays"], st
    assert 0 < st["rays"], st
    # A second update counts only its own rays too.
    again = _job(native, scenes_np.room((0.6, 0.2))).prepare().run()
    st2 = again.native_stats()
    assert st2["rays_cumulative"] == st["rays_cumulative"] + st2["rays"], st2


@pytest.mark.parametrize("field,value", [("intensity", (math.nan, 1.0, 1.0)),
                                         ("intensity", (math.inf, 0.0, 0.0)),
                                         ("position", (0.0, math.nan, 1.0)),
                                         ("direction", (math.inf, 0.0, -1.0)),
                                         ("radius", math.nan)])
def test_non_finite_light_is_refused_naming_it(field, value):
    si = scenes_np.room(light=0.0)      # no emitting object: the lamp is the only emitter
    li = lights.LightInput("Lamp", lights.POINT, (1.0, 1.0, 1.0), position=(2.0, 2.0, 1.5))
    setattr(li, field, value)
    si.lights.append(li)
    with pytest.raises(scene_data.InputError, match=r"light 'Lamp'.*NaN or infinite"):
        scene_data.validate(si)


def test_an_object_absurdly_far_away_is_refused_naming_it():
    # Blender stores an infinite location as 3.4e38: the room would vanish in the solver's
    # frame (a black bake with a misleading "no emitter" warning).
    si = scenes_np.room()
    far = scenes_np.obj("Far", scenes_np._box((3.4e38, 0.0, 0.0), (1.0, 1.0, 1.0)),
                        [0.5] * 3, [0, 0, 0])
    si.objects.append(far)
    with pytest.raises(scene_data.InputError, match=r"object 'Far' lies too far.*'wall0'"):
        scene_data.validate(si)


def test_tiny_and_huge_objects_within_resolution_are_accepted():
    # 1 mm next to a 1000 km plane: 1e-9 of the scene, above the 1e-10 limit.
    si = scenes_np.room()
    si.objects.append(scenes_np.obj("Plane", scenes_np.grid((-5e5, -5e5, -1), (1e6, 0, 0),
                                                            (0, 1e6, 0), 1), [0.5] * 3, [0, 0, 0]))
    si.objects.append(scenes_np.obj("Grain", scenes_np._box((1, 1, 1), (1e-3,) * 3),
                                    [0.5] * 3, [0, 0, 0]))
    scene_data.validate(si)


def test_a_lone_object_at_any_scale_is_accepted():
    si = scenes_np.room()
    si.objects = [scenes_np.obj("Huge", scenes_np._box((3e38, 0, 0), (1e37,) * 3),
                                [0.5] * 3, [1, 1, 1])]
    scene_data.validate(si)
    assert np.isfinite(si.objects[0].vertices).all()


def test_an_update_the_solver_runs_in_full_is_reported_as_full(native):
    if getattr(native, "FAKE", False):
        pytest.skip("the stand-in's update never decides to solve in full")
    # A dark scene lit afterwards: the native update solves in full (adjust.cpp), and its
    # counters start again from zero, so nothing is subtracted.
    _job(native, scenes_np.room(light=0.0)).prepare().run()
    lit = _job(native, scenes_np.room(light=10.0)).prepare()
    assert lit.mode == "incremental"        # queued on the kept solver...
    lit.run()
    assert lit.mode == "full"               # ...which solved in full
    assert lit.full_reason.startswith("the solver solved in full"), lit.full_reason
    assert lit.update_fallback == "no_light"
    st = lit.native_stats()
    assert "rays_cumulative" not in st and st["rays"] > 0
