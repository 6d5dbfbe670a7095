// User-facing solver settings and the presets the add-on offers.
#pragma once
#include <cstdint>
#include <string>

namespace radiosity {

struct Settings {
    double error_threshold = 0.05;      // relative error threshold of the oracle
    // Once a solve has estimated the light, a link's threshold follows its receiver's
    // radiance: error_threshold x L_ref x min(1, max(L_rcv / L_ref, this)). A dim receiver
    // (the back of a cabinet 2 cm from a wall) is judged by what a viewer sees there, a
    // relative error, down to this fraction of the scene-wide threshold; 1 = the scene-wide
    // threshold everywhere (bench/results/presets_sweep.md).
    double threshold_floor = 1.0;
    double min_area_fraction = 1e-5;    // smallest element area / scene-diagonal^2
    // Quadtree levels below that floor a leaf may still split where an emitter's outline, a
    // narrow gap or a lamp's shadow edge crosses it (each level a quarter of the area).
    int below_floor_levels = 2;
    int64_t max_elements = 2000000;     // refinement stops at these caps (stats say so)
    int64_t max_links = 10000000;
    // Refinement also stops when the solver's estimated memory (elements, links with their
    // history) would pass this many MiB; 0 = half the machine's physical memory. A cap, not
    // an out-of-memory kill: the solve ends coarser and says so.
    double max_memory_mb = 0;
    bool use_clustering = true;
    bool progressive_refinement = true;  // the paper's 3.5 criterion
    int rays_per_link = 16;
    int max_iterations = 5000;          // gathering iterations per solve (stops at the tolerance)
    int max_refine_rounds = 8;          // refine/solve alternations
    double tolerance = 1e-5;            // estimated remaining relative error of the iteration
    int threads = 0;                    // 0 = all cores
    // Corner-leaf output only (gather_rays = 0): corners average across faces within this angle.
    double crease_angle_deg = 35.0;
    // Output by a final gather at each corner (final_gather.h): rays per output point, shared
    // among the links that reach it by the light they bring; 0 = the leaf element's average
    // at the corner (the computational mesh as it is, no gather). The presets give 64 / 512 /
    // 1024 (DRAFT / MEDIUM / HIGH: bench/results/presets_sweep.md); a default-constructed
    // Settings has it off.
    int gather_rays = 0;
    int gather_min_rays = 8;  // ... and at least this many for every link that reaches the point
    // Shared gathers (final_gather.h Config::share): a corner within this fraction of a
    // gathered neighbour's distance to the nearest surface takes that neighbour's bounced
    // light and gathers only its lamps and emitting surfaces. 0 = every corner gathers all.
    double gather_share = 0.0;
    // Gathered corners at the points Cycles bakes (the vertex moved 1e-4 x max(|world
    // coordinate|, 1) into the corner's first triangle): the same values where light changes
    // within a millimetre. Off: a step of 3e-5 of the scene's size, so that the output, as the
    // rest of the solution, does not depend on the scene's scale or offset.
    bool cycles_corner_points = true;
    // A point inside a closed solid (each of its 64 escape rays reaches the back of a face)
    // reads no light, as in Cycles, unless some lamp or emitting face lies inside a solid
    // itself (final_gather.cpp point_sealed). The solution's leaves cannot give that: a floor
    // polygon straddling the wall of a box standing on it carries the room's light inside.
    bool gather_sealed_solids = true;
    int closure_rays = 32;              // escape rays per leaf for the closure correction
    // Closure-driven refinement (refinement.h): an enclosed leaf whose form factors sum further
    // than this from 1 has the links at its ancestors split toward it (0 = off), at most
    // closure_refine_passes times per closure computation.
    double closure_refine_tolerance = 0.1;
    int closure_refine_passes = 6;
    uint64_t seed = 1;
    // After a move, recast only the visibility rays that pass through a moved object's old
    // or new box and take the others' outcomes from the link's record (exact: the result is
    // the same; off only to check that, or to measure what it saves).
    bool replay_rays = true;
    // The live drag's preview (Solver::preview): a step re-lights the points nearest the
    // dragged objects first and stops after about this much work (shadow rays streamed from
    // their records, each one cast counting 5); the others show what an earlier step of the
    // drag found (what a step then costs, by room size: bench/results/live_drag.md); 0 =
    // every point at every step.
    int64_t preview_work = 1000000;

    // 'DRAFT' | 'MEDIUM' | 'HIGH'; throws std::invalid_argument otherwise.
    static Settings preset(const std::string& name);
    // Throws std::invalid_argument naming the first bad field.
    void validate() const;
};

}  // namespace radiosity
