#include "radiosity/settings.h"

#include <cmath>
#include <stdexcept>

namespace radiosity {

Settings Settings::preset(const std::string& name) {
    // Why each value is what it is, with the measurements: docs/decisions.md, "Presets".
    Settings s;
    if (name == "DRAFT") {
        s.error_threshold = 0.2;
        s.min_area_fraction = 1e-4;
        s.below_floor_levels = 0;  // the floor holds everywhere: leaves below it cost more than they give
        s.rays_per_link = 8;
        s.tolerance = 2e-4;
        s.gather_rays = 64;
        s.gather_min_rays = 2;
        // Corners within 0.3 of a gathered neighbour's reach share its bounced light.
        s.gather_share = 0.3;
    } else if (name == "MEDIUM") {
        // A threshold that follows the receiver's light (threshold_floor) refines what a
        // viewer sees as wrong -- a dim gap behind a cabinet, a corner in shadow -- and leaves
        // bright, smooth walls coarse, down to 5 % of the scene's light (where the accuracy
        // metric's own floor lies). Leaves stop at DRAFT's area floor except where a narrow
        // gap, an emitter's outline or a lamp's shadow edge needs them finer (oracle.cpp,
        // lights.cpp): a finer floor everywhere costs links for no better accuracy.
        s.error_threshold = 0.1;
        s.threshold_floor = 0.05;
        s.min_area_fraction = 1e-4;
        s.rays_per_link = 16;
        s.tolerance = 1e-4;
        s.gather_rays = 512;
        // Every link at least 8 rays: the many small links are the gather's noise.
        s.gather_min_rays = 8;
        // Shared gathers within 0.08 of a neighbour's reach (more costs the Cornell box's
        // corners accuracy).
        s.gather_share = 0.08;
    } else if (name == "HIGH") {
        // Half MEDIUM's threshold, with the visibility and the gather that a cube's foot on a
        // checker floor needs (tests/blender/test_textures_world.py holds it to 2 %).
        s.error_threshold = 0.05;
        s.threshold_floor = 0.05;
        s.min_area_fraction = 1e-5;
        // Its floor is fine enough: leaves below it cost links for no better error.
        s.below_floor_levels = 0;
        s.rays_per_link = 32;
        s.tolerance = 1e-5;
        s.gather_rays = 1024;
        s.gather_min_rays = 8;
    } else {
        throw std::invalid_argument("unknown preset '" + name + "' (DRAFT, MEDIUM or HIGH)");
    }
    return s;
}

void Settings::validate() const {
    auto bad = [](const std::string& w) { throw std::invalid_argument("settings: " + w); };
    if (!(std::isfinite(error_threshold) && error_threshold > 0)) bad("error_threshold must be a positive number");
    if (!(std::isfinite(threshold_floor) && threshold_floor > 0 && threshold_floor <= 1))
        bad("threshold_floor must be in (0, 1]");
    if (!(std::isfinite(min_area_fraction) && min_area_fraction >= 0)) bad("min_area_fraction must be >= 0");
    if (below_floor_levels < 0 || below_floor_levels > 8) bad("below_floor_levels must be in 0..8");
    if (max_elements < 1) bad("max_elements must be >= 1");
    if (max_links < 1) bad("max_links must be >= 1");
    if (!(std::isfinite(max_memory_mb) && max_memory_mb >= 0)) bad("max_memory_mb must be >= 0 (0 = half the physical memory)");
    if (rays_per_link < 1 || rays_per_link > 4096) bad("rays_per_link must be in [1, 4096]");
    if (max_iterations < 1) bad("max_iterations must be >= 1");
    if (max_refine_rounds < 0) bad("max_refine_rounds must be >= 0");
    if (!(std::isfinite(tolerance) && tolerance > 0)) bad("tolerance must be a positive number");
    if (threads < 0) bad("threads must be >= 0");
    if (!(crease_angle_deg >= 0 && crease_angle_deg <= 180)) bad("crease_angle_deg must be in [0, 180]");
    if (gather_rays < 0 || gather_rays > 65536) bad("gather_rays must be in [0, 65536] (0 = no final gather)");
    if (gather_min_rays < 1 || gather_min_rays > 4096) bad("gather_min_rays must be in [1, 4096]");
    if (!(std::isfinite(gather_share) && gather_share >= 0 && gather_share <= 1)) bad("gather_share must be in [0, 1]");
    if (closure_rays < 0) bad("closure_rays must be >= 0");
    if (preview_work < 0) bad("preview_work must be >= 0 (0 = every point)");
    if (!(std::isfinite(closure_refine_tolerance) && closure_refine_tolerance >= 0))
        bad("closure_refine_tolerance must be >= 0");
    if (closure_refine_passes < 0) bad("closure_refine_passes must be >= 0");
}

}  // namespace radiosity
