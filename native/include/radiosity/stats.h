// What a solve reports: the paper's Table 2 counts plus time per phase.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace radiosity {

// Why an update solved in full instead (Solver::update): a stable code for programs, where the
// warning that goes with it is English for people and may be reworded.
enum class UpdateFallback {
    none,                  // the update was incremental, or no update ran
    scene_size,            // objects added or removed changed the scene's size (its frame)
    pocket_moved,          // a move changed a closed pocket (pockets.cpp)
    pocket_added_removed,  // an object added or removed changed a closed pocket
    no_light,              // the scene has, or had, no light (no warning of its own)
};

// The code's name, as the Python module reports it ("none" for none).
inline const char* fallback_code(UpdateFallback f) {
    switch (f) {
        case UpdateFallback::none: return "none";
        case UpdateFallback::scene_size: return "scene_size";
        case UpdateFallback::pocket_moved: return "pocket_moved";
        case UpdateFallback::pocket_added_removed: return "pocket_added_removed";
        case UpdateFallback::no_light: return "no_light";
    }
    return "none";
}

// Every code but none, for the Python module to list.
inline constexpr UpdateFallback kUpdateFallbacks[] = {UpdateFallback::scene_size, UpdateFallback::pocket_moved,
                                                      UpdateFallback::pocket_added_removed, UpdateFallback::no_light};

struct Stats {
    int64_t input_surfaces = 0;     // input polygons
    int64_t primitives = 0;         // after n-gon splitting
    int64_t skipped_polygons = 0;   // zero-area input polygons
    int64_t objects = 0;
    int64_t clusters = 0;           // cluster nodes (collections, objects, automatic)
    int64_t closed_pockets = 0;     // closed pockets besides the main space (pockets.cpp)
    int64_t pocket_surfaces = 0;    // oriented surfaces in them (a closed object's inner faces too)
    int64_t elements = 0;           // leaf elements of surfaces that receive light
    int64_t element_nodes = 0;      // all element nodes (inner ones included)
    int64_t links = 0;              // active links
    int64_t cluster_links = 0;      // active links with a cluster end
    int64_t surface_links = 0;      // active element-element links
    int64_t history_links = 0;      // inactive links kept for un-refinement
    int64_t occluded_links = 0;     // fully occluded links kept for moves that open the view
    int64_t obj_env_links = 0;      // active links between an object (collection member) and the environment
    int64_t env_env_links = 0;      // active links with both ends in the environment
    int64_t obj_obj_links = 0;
    int64_t env_env_links_recomputed = 0;  // visibility re-evaluated after a move (3.3): active and occluded ones
    int64_t history_links_recomputed = 0;  // ... and env-env history links, when un-refinement asked for them
    int64_t history_links_stale = 0;       // env-env history links a move may have changed, left stale
    int64_t env_env_links_tested = 0;      // env-env links the outcode test looked at
    int64_t env_env_links_rejected = 0;    // ... and trivially rejected
    int64_t env_env_links_rays_clear = 0;  // ... not rejected, but no ray of theirs can meet a moved box (shaft test)
    int64_t obj_env_links_removed = 0;     // active links of moved objects dropped before re-linking
    int64_t links_created = 0;             // links made by the update (incl. occluded/history)
    int64_t history_reactivated = 0;       // history links brought back (un-refinement, 3.4)
    int64_t objects_added = 0;             // objects linked in by the last update
    int64_t objects_removed = 0;           // objects taken out by the last update
    int64_t links_removed = 0;             // ... and their active links that went with them
    bool mode_incremental = false;
    double seconds_adjust = 0;             // link update (AdjustSystem) of the last update
    int64_t rays = 0;
    int64_t links_evaluated = 0;
    int64_t refined_by_oracle = 0;
    int64_t avoided_by_progressive = 0;  // refinements the 3.5 criterion avoided
    int64_t refined_by_closure = 0;      // links split because a leaf's form factors missed 1
    int iterations = 0;
    // Gathering cost (gathering.cpp): links gathered summed over the sweeps of iterate_to (a
    // sweep over n links adds n) and the time of those sweeps; gather plans built and the
    // time building them. Both times are part of the "closure" and "gather" phases.
    int64_t link_sweeps = 0;
    double seconds_sweeps = 0;
    int64_t gather_plans = 0;
    double seconds_gather_plan = 0;
    int refine_rounds = 0;
    double residual = 0;            // estimated remaining relative error at the end
    bool capped = false;            // a cap (elements/links/memory) stopped refinement
    bool memory_capped = false;     // ... the memory cap (Settings::max_memory_mb)
    int64_t memory_bytes = 0;       // estimated memory held at the end (memory.cpp: links, Embree, output)
    bool iteration_capped = false;  // max_iterations reached before the tolerance
    bool no_emitters = false;
    // The output's final gather (final_gather.h): points traced (one per vertex and normal),
    // corners, covered corners (lying on another object's face: unlit), point-link
    // evaluations, rays, and the bytes its trace keeps for re-output without rays.
    int64_t gather_sealed = 0;  // output points inside a closed solid (read 0)
    int64_t gather_points = 0, gather_corners = 0, gather_covered = 0, gather_links = 0, gather_rays = 0;
    int64_t gather_bytes = 0;
    int64_t gather_forecast_bytes = 0;  // ... as forecast before the gather (memory.cpp)
    // After an update: point-link transfers kept as they were, replayed (only rays through a
    // moved box cast), and points traced anew.
    int64_t gather_kept = 0, gather_replayed = 0, gather_fresh_points = 0;
    int64_t gather_near = 0;  // near-field corrections at output points (near_field.cpp)
    int64_t gather_near_rays = 0;  // of gather_rays: cast by those corrections
    int64_t gather_lamp_rays = 0;  // of gather_rays: the output points' own lamp shadow rays
    int64_t gather_shared = 0;  // output points that took their bounced light from gathered ones (Settings::gather_share)
    int64_t gather_probe_rays = 0;  // of gather_rays: the probes of the points that may take it (shared_gather.cpp)
    int64_t gather_probes_kept = 0;  // after an update: probes kept as they were (no probe ray could change)
    // Surfaces whose contacts (DirectLight::find_contacts) the last solve or update looked
    // for, and the time that took.
    int64_t contact_surfaces = 0;
    double seconds_contacts = 0;
    double seconds_build = 0, seconds_link = 0, seconds_solve = 0, seconds_total = 0;
    std::vector<std::string> warnings;
    // Why the last update solved in full; its warning, when it has one, is the last of `warnings`.
    UpdateFallback update_fallback = UpdateFallback::none;
    // Wall time of each phase of the last solve or update, in order (for profiling and the
    // benchmarks; names are stable: "build", "link", "closure", "gather", "refine", ...).
    std::vector<std::pair<std::string, double>> phases;
    // Rays cast in each phase, same names and order (a count that does not depend on the
    // machine's load: how the work of an update compares with a full solve's).
    std::vector<std::pair<std::string, int64_t>> phase_rays;
};

}  // namespace radiosity
