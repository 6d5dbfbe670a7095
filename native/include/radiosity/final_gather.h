// The output: every Blender corner's radiance at the corner itself (the point and normal
// Cycles bakes it at), by a final gather from the hierarchical solution -- the "local pass"
// of Lischinski, Tampieri and Greenberg (1993) and the final gather of Smits, Arvo and
// Greenberg's clustering (1994). The solution's leaves are a computational mesh: piecewise
// constant, a leaf straddling a lamp's edge or a contact line holds one average. The points
// where the user looks get their light anew from the links that reach the leaf holding them
// (and its ancestors, cluster links included), re-evaluated from the point itself: exact
// point-to-polygon form factors, visibility by rays from the point, senders at their leaf
// radiance; lamps (point, spot, sun, sky) by shadow rays from the point.
//
// What a point sees is kept (a trace: per point the leaves it reads and their weights, its
// direct light and closure fill), so output after a change of radiance alone (emission,
// reflectance, a light dimmed) costs no ray; geometry changes re-trace.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "radiosity/enclosure.h"
#include "radiosity/gather_plan.h"
#include "radiosity/hierarchy.h"
#include "radiosity/link.h"
#include "radiosity/link_store.h"
#include "radiosity/rigid.h"
#include "radiosity/scene.h"
#include "radiosity/transfer.h"
#include "radiosity/visibility.h"

namespace radiosity {

// The closure factors of an enclosed output point whose couplings sum to own + inherited, of
// which s_own and s_inherited come from cluster senders (sampled): final_gather.cpp.
ClosureFactors point_closure_factors(double own, double inherited, double s_own, double s_inherited);

class FinalGather {
public:
    FinalGather();
    ~FinalGather();
    FinalGather(FinalGather&&) noexcept;
    FinalGather& operator=(FinalGather&&) noexcept;
    // What a trace reads of the solution, borrowed for the call.
    struct Solution {
        const SceneDesc& scene;
        const Hierarchy& h;
        const Visibility& vis;
        const LinkStore& links;
        const Enclosure& enclosure;  // which leaves are enclosed (their points' closure)
        // The surface of another polygon lying on a surface at a point, turned against it (a
        // box's bottom on a floor: lights.cpp's contact test), or -1.
        std::function<int(int surface, const Vec3& p)> contact;
        // Per object, its Embree triangles' primitives (which side of a face a ray met).
        const std::vector<std::vector<int>>* tri_prim = nullptr;
        // The primitive the segment a-b first meets and where (`at`); -1 when it meets
        // nothing, or a triangle tri_prim does not map (none given).
        int prim_hit(const Vec3& a, const Vec3& b, Vec3& at) const {
            int tri = -1;
            const int obj = vis.hit_object(a, b, 0.0, &at, &tri);
            if (!tri_prim || obj < 0 || size_t(obj) >= tri_prim->size() || tri < 0) return -1;
            const std::vector<int>& tp = (*tri_prim)[size_t(obj)];
            return size_t(tri) < tp.size() ? tp[size_t(tri)] : -1;
        }
    };
    struct Config {
        int rays = 256;      // ray budget per point, shared among its links by the light they bring
        int min_rays = 4;    // every link at least (its coupling counts for the closure)
        int light_samples = 16;
        int threads = 0;
        uint64_t seed = 1;
        // Corner points where Cycles puts them (a world-space step off the vertex), or at a
        // step relative to the scene's size (the same at any scale): final_gather.cpp.
        bool cycles_points = true;
        bool sealed_solids = true;  // Settings::gather_sealed_solids
        // Shared gathers (Settings::gather_share): a point within `share` x R of a fully
        // gathered point of its object, R that point's distance to the nearest surface it
        // sees, takes that point's bounced light and gathers only its lamps and emitting
        // senders itself. 0: every point gathers everything.
        double share = 0;
    };
    struct Counts {
        int64_t points = 0, corners = 0, covered = 0;
        int64_t links = 0;       // point-link evaluations
        int64_t rays = 0;
        int64_t refined = 0;     // links given more rays because a shadow edge crossed them
        int64_t samples = 0;     // kept (leaf, weight) pairs
        int64_t kept = 0;        // retrace: point-link transfers kept as they were (no ray could change)
        int64_t replayed = 0;    // ... replayed (rays through a moved box cast again)
        int64_t fresh_points = 0;  // retrace: points traced anew
        int64_t near = 0;        // near-field corrections (a sender a hair from the point)
        int64_t near_rays = 0;   // of `rays`: cast by the near-field corrections
        int64_t lamp_rays = 0;   // of `rays`: the output points' own lamp shadow rays
        int64_t shared = 0;      // points that took their bounced light from gathered points near them
        int64_t probe_rays = 0;  // of `rays`: the shared gathers' probes of each point's own reach
        int64_t probes_kept = 0;  // retrace: probes kept as they were (no probe ray could change)
        int64_t sealed = 0;      // points inside a closed solid (no light)
        std::vector<int64_t> object_rays;  // per object: the rays its points cast (of `rays`)
    };

    // Traces every output point of the scene's objects. `progress(f)` is called with f in
    // [0, 1] from the calling thread and may throw (cancellation).
    void trace(const Solution& s, const Config& c, const std::function<void(double)>& progress);
    // What changed in the geometry since the last trace (an update that moved objects only).
    struct Moves {
        std::vector<char> moved;        // per object
        std::vector<Aabb> clips;        // old and new boxes of the moved objects
        // Cast every ray again instead (same budgets and seeds: the result is the same, bit
        // for bit; Settings::replay_rays off, to check that).
        bool cast_all = false;
        bool lights_changed = false;  // set by retrace: the lamps differ from the last trace's
        bool materials_changed = false;  // emission or reflectance changed (radiances everywhere)
    };
    // The trace after moves: a point that did not move keeps what its rays found where no ray
    // of it meets a moved box (a link whose rays' hull with the point meets none keeps its
    // samples; others replay their rays, casting only those through a box), and gathers the
    // links new at its leaf afresh. Moved points, and any point when the corners changed, are
    // traced anew. The result is what trace() gives for the same links and ray budgets.
    void retrace(const Solution& s, const Config& c, const Moves& moves, const std::function<void(double)>& progress);
    bool traced() const;
    // --- The live drag's preview (preview.cpp). While an object is dragged, each step shows
    // this trace with its direct light re-traced at the new placements: lamps' shadow rays and
    // the transfers from emitting senders, for the points whose rays may meet a moved object's
    // old or new box (their rays replayed where the record allows) and for the moved objects'
    // own points, carried rigidly. Light that bounced stays as solved: the update run when the
    // drag pauses gives the real output. The trace itself does not change.
    struct Preview {
        std::vector<char> moved;                    // per object
        std::vector<Rigid> carry;                   // per object: the solved placement -> the new one
        std::vector<Aabb> clips;                    // old and new boxes of the moved objects
        std::vector<Aabb> now;                      // new boxes alone
        std::vector<int> moved_nodes;               // the clusters holding a moved object, ascending
        // Whether a point (on `surface`, normal n) lies under another polygon at the new
        // placements (a floor point under the dragged box): covered, unlit as in Cycles.
        std::function<bool(int surface, const Vec3& x, const Vec3& n)> covered;
        // Whether a dragged object's surface that lay on another (a box's bottom on the floor)
        // is off it at x: out of the plane of every polygon it touched in the bake.
        std::function<bool(int surface, const Vec3& x)> lifted;
        // Work a step may do (Settings::preview_work; 0: every point): the points nearest the
        // boxes first, the rest showing what an earlier step of the same drag found.
        int64_t work = 0;
    };
    struct PreviewCounts {
        int64_t points = 0;     // points re-traced (their light may have changed)
        int64_t lamps = 0;      // points whose lamps were re-traced
        int64_t transfers = 0;  // emitter transfers re-traced
        int64_t uncovered = 0;  // points a moved object covered and covers no more (gathered afresh)
        int64_t covered = 0;    // points it covers now
        int64_t rays = 0;
        int64_t deferred = 0;   // points the work left showing an earlier step's change
    };
    // A corner whose light a preview changes, and what it shows now: irradiance / pi and the
    // radiance it leaves with (its leaf's reflectance and emission).
    struct CornerChange {
        int object = -1, corner = -1;
        Rgb irradiance, radiance;
    };
    // The corners whose light changed, by object and corner. Remembers what it showed until
    // the next trace, or a drag of other objects.
    std::vector<CornerChange> preview(const Solution& s, const Preview& p, PreviewCounts& counts);
    // The point a corner reads (-1: none; preview()'s index).
    int corner_point(int object, size_t corner) const;
    // Per point of the last trace, the shared gathers' probe of its own reach (-1: none made):
    // a retrace's kept probes are checked against cast ones with it.
    std::vector<double> probes() const;
    void clear();
    // Per corner (RGB interleaved) of one object, from the trace and the current leaf
    // radiances: outgoing radiance, or irradiance / pi (lighting only). Empty when the object
    // was not traced (added since, or no trace yet).
    std::vector<float> corner_radiance(const Hierarchy& h, int object) const;
    std::vector<float> corner_irradiance(const Hierarchy& h, int object) const;
    const Counts& counts() const;
    // Bytes kept by the trace (points, their records and samples, the corner map), as
    // measured when it was made: the solver asks at every link it makes.
    size_t bytes() const;
    // Bytes a trace of `points` points reading `records` point-link transfers in all is
    // expected to keep (the samples a transfer keeps after merging, on average).
    static double trace_bytes(double points, double records);

private:
    // What the last trace keeps (its points, their records and samples, the corner map, the
    // counts) and the steps that make and read it: final_gather_trace.h, private to the final
    // gather's sources.
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace radiosity
