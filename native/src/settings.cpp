#include "radiosity/settings.h"

#include <cmath>
#include <stdexcept>

namespace radiosity {

namespace {

// The fields a preset sets; the others keep Settings' defaults.
struct PresetRow {
    const char* name;
    double error_threshold, threshold_floor, min_area_fraction;
    int below_floor_levels, rays_per_link;
    double tolerance;
    int gather_rays, gather_min_rays;
    double gather_share;
};

}  // namespace

Settings Settings::preset(const std::string& name) {
    // Why each value is what it is, with the measurements: docs/decisions.md, "Presets".
    // DRAFT: the area floor holds everywhere (below_floor_levels 0): leaves below it cost more
    // than they give. Corners within 0.3 of a gathered neighbour's reach share its bounced light.
    // MEDIUM: a threshold that follows the receiver's light (threshold_floor) refines what a
    // viewer sees as wrong -- a dim gap behind a cabinet, a corner in shadow -- and leaves
    // bright, smooth walls coarse, down to 5 % of the scene's light (where the accuracy
    // metric's own floor lies). Leaves stop at DRAFT's area floor except where a narrow
    // gap, an emitter's outline or a lamp's shadow edge needs them finer (oracle.cpp,
    // lights.cpp): a finer floor everywhere costs links for no better accuracy. Every link at
    // least 8 gather rays: the many small links are the gather's noise. Shared gathers within
    // 0.08 of a neighbour's reach (more costs the Cornell box's corners accuracy).
    // HIGH: half MEDIUM's threshold, with the visibility and the gather that a cube's foot on a
    // checker floor needs (tests/blender/test_textures_world.py holds it to 2 %). Its area
    // floor is fine enough but in narrow gaps (a cabinet's back 2 cm from the wall): one level
    // below it there, so that a gap resolves at least as finely as at MEDIUM.
    // Each row in PresetRow's order: name, error_threshold, threshold_floor, min_area_fraction,
    // below_floor_levels, rays_per_link, tolerance, gather_rays, gather_min_rays, gather_share.
    const Settings d;  // `d.` in a row: that preset keeps the default
    const PresetRow rows[] = {
        {"DRAFT",  0.2,  d.threshold_floor, 1e-4, 0,                    8,  2e-4, 64,   2, 0.3},
        {"MEDIUM", 0.1,  0.05,              1e-4, d.below_floor_levels, 16, 1e-4, 512,  8, 0.08},
        {"HIGH",   0.05, 0.05,              1e-5, 1,                    32, 1e-5, 1024, 8, d.gather_share},
    };
    for (const PresetRow& r : rows) {
        if (name != r.name) continue;
        Settings s;
        s.error_threshold = r.error_threshold;
        s.threshold_floor = r.threshold_floor;
        s.min_area_fraction = r.min_area_fraction;
        s.below_floor_levels = r.below_floor_levels;
        s.rays_per_link = r.rays_per_link;
        s.tolerance = r.tolerance;
        s.gather_rays = r.gather_rays;
        s.gather_min_rays = r.gather_min_rays;
        s.gather_share = r.gather_share;
        return s;
    }
    throw std::invalid_argument("unknown preset '" + name + "' (DRAFT, MEDIUM or HIGH)");
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
