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
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "radiosity/gather_plan.h"
#include "radiosity/hierarchy.h"
#include "radiosity/link.h"
#include "radiosity/rigid.h"
#include "radiosity/scene.h"
#include "radiosity/transfer.h"
#include "radiosity/visibility.h"

namespace radiosity {

struct PointCouplings;  // point_couplings.h

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
        const std::vector<Link>& links;
        // The surface of another polygon lying on a surface at a point, turned against it (a
        // box's bottom on a floor: lights.cpp's contact test), or -1.
        std::function<int(int surface, const Vec3& p)> contact;
        // Per object, its Embree triangles' primitives (which side of a face a ray met).
        const std::vector<std::vector<int>>* tri_prim = nullptr;
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
    bool traced() const { return traced_; }
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
        std::vector<char> moved_nodes;              // per node: a cluster holding a moved object
        // Whether a point (on `surface`, normal n) lies under another polygon at the new
        // placements (a floor point under the dragged box): covered, unlit as in Cycles.
        std::function<bool(int surface, const Vec3& x, const Vec3& n)> covered;
    };
    struct PreviewCounts {
        int64_t points = 0;     // points re-traced (their light may have changed)
        int64_t lamps = 0;      // points whose lamps were re-traced
        int64_t transfers = 0;  // emitter transfers re-traced
        int64_t uncovered = 0;  // points a moved object covered and covers no more (gathered afresh)
        int64_t covered = 0;    // points it covers now
        int64_t rays = 0;
    };
    // Per point, the change of its irradiance / pi.
    std::vector<Rgb> preview(const Solution& s, const Preview& p, PreviewCounts& counts) const;
    // One corner's value as corner_radiance (or with `irradiance`, corner_irradiance) gives
    // it, with `change` (preview's) added to what arrives there; false when the object or
    // corner was not traced (its value is 0).
    bool corner_value(const Hierarchy& h, int object, size_t corner, bool irradiance, const Rgb& change, Rgb& out) const;
    // The point a corner reads (-1: none; preview()'s index).
    int corner_point(int object, size_t corner) const {
        if (!traced_ || object < 0 || size_t(object) >= corner_point_.size()) return -1;
        const auto& cp = corner_point_[size_t(object)];
        return corner < cp.size() ? cp[corner] : -1;
    }
    void clear();
    // Per corner (RGB interleaved) of one object, from the trace and the current leaf
    // radiances: outgoing radiance, or irradiance / pi (lighting only). Empty when the object
    // was not traced (added since, or no trace yet).
    std::vector<float> corner_radiance(const Hierarchy& h, int object) const { return values(h, object, false); }
    std::vector<float> corner_irradiance(const Hierarchy& h, int object) const { return values(h, object, true); }
    const Counts& counts() const { return counts_; }
    // Bytes kept by the trace (points, their records and samples, the corner map), as
    // measured when it was made: the solver asks at every link it makes.
    size_t bytes() const { return bytes_; }
    // Bytes a trace of `points` points reading `records` point-link transfers in all is
    // expected to keep (the samples a transfer keeps after merging, on average).
    static double trace_bytes(double points, double records);

private:
    // What a trace keeps per point and per point-link transfer, and one point to trace
    // (final_gather_trace.h, private to the final gather's sources).
    struct Record;
    struct Point;
    struct Job;
    std::vector<Job> make_jobs(const Solution& s);
    std::vector<float> values(const Hierarchy& h, int object, bool irradiance) const;
    // `bounced` (values()'s cache, per point): a lender's bounced light, made when first read.
    Rgb point_value(const Hierarchy& h, const Point& p, bool irradiance, const Rgb& change = Rgb{},
                    std::vector<std::pair<bool, Rgb>>* bounced = nullptr) const;
    // What one record's samples read of the current solution (irradiance / pi, before closure).
    static Rgb record_light(const Hierarchy& h, const Point& p, const Record& r);
    // A gathered point's irradiance / pi without what emitted_part gives: what it lends.
    Rgb bounced_part(const Hierarchy& h, const Point& p) const;
    // preview(): irradiance / pi at a point gathered afresh from the active links reaching its
    // leaf and the lamps, without retraces, closure or near field (a footprint uncovered).
    Rgb fresh_irradiance(const Solution& s, const Point& pt, int64_t& rays) const;
    // The seed of a point's transfer from sender node `src`: the point's and the sender's alone
    // (not the link's), so the same transfer draws the same rays whichever link holds it.
    static uint64_t transfer_seed(const Hierarchy& h, uint64_t point_seed, int src) {
        return Hierarchy::mix(point_seed, Hierarchy::mix(h.nodes[size_t(src)].key, 0x5e4d3ull));
    }
    // A transfer's share of a point's ray budget: `budget` x weight / total in powers of two,
    // within [lo, hi] (lo when it brings nothing).
    static int ray_share(int budget, double weight, double total, int lo, int hi);
    // A point traced afresh, or (with `old` and `moves`) re-traced after moves; with
    // `emitters_only`, only its lamps and the links from emitting senders (a shared point).
    void trace_point(const Solution& s, const Config& c, Point& pt, const Point* old, const Moves* moves,
                     Counts& counts, bool emitters_only = false) const;
    // trace_point's parts: the links reaching the point's leaf with the light each may bring
    // (its share of the ray budget), the nearest of them that brings none, whether a move left
    // the point's near field as it was, and the transfers traced (their couplings, for the
    // closure).
    // weight: the light at stake (for the ray budget). unknown: a link whose point model failed
    // and whose coupling the solver could not estimate (Link::must_refine into a cluster at the
    // resolution limit): traced all the same, with the fewest rays.
    struct Use { int link; bool own; double weight; bool unknown; };
    void uses(const Solution& s, int leaf, std::vector<Use>& use) const;
    static double nearest_dark(const Solution& s, const std::vector<Use>& use, const Vec3& x);
    static bool near_unchanged(const Solution& s, const Point& pt, const Point* old, const Moves* moves);
    PointCouplings trace_transfers(const Solution& s, const Config& c, Point& pt, const Point* old, const Moves* moves,
                                   Counts& counts, const std::vector<Use>& use, bool enclosed, bool emitters_only) const;
    // ... the point's lamps (kept after a move that cannot shade them), and
    // one sender's transfer to it (`weight` its light at stake, of `total` over `links` links).
    void trace_lamps(const Solution& s, const Config& c, Point& pt, const Point* old, const Moves* moves,
                     Counts& counts) const;
    Record trace_transfer(const Solution& s, const Config& c, Point& pt, const Point* old, const Moves* moves,
                          Counts& counts, int src, double weight, double total, size_t links) const;
    // A gathered point's reach: the harmonic mean distance of what its rays found, or the
    // distance to the nearest dark sender (`dark`, found by trace_point) when that is less;
    // 0 when it lends nothing (covered, sealed, nothing seen).
    static float lend_reach(const Point& pt, double dark);
    // Decides, level by level, which points gather fully and which share (Config::share);
    // `trace(i, emitters_only)` traces point i. Fills the shared points' borrow lists; returns
    // the rays it cast itself (probes of the points' surroundings).
    int64_t share_gathers(const Solution& s, const Config& c, const std::vector<Job>& jobs,
                       const std::function<void(size_t, bool)>& trace, const std::function<void(double)>& progress);
    // What a point's lamps and emitting senders bring (irradiance / pi, through its closure).
    Rgb emitted_part(const Hierarchy& h, const Point& p) const;
    // The links that reach a leaf: at it (own), at its element ancestors and at the clusters
    // above its surface, fully occluded ones included.
    void links_reaching(const Solution& s, int leaf, std::vector<std::pair<int, bool>>& out) const;
    void near_field(const Solution& s, const Config& c, Point& pt, Counts& counts) const;
    // Near field (near_field): a sender's part within kNearReach x d of a point at distance d.
    static constexpr double kNearReach = 20.0;
    // The near field's internals (near_field.h, private to the solver's sources): the
    // point's own plane as a sender's point sees it, and the plane's direct-light term.
    struct NearPlane;
    class DirectVariation;
    class NearField;
    // Outgoing radiance at a point sp of leaf m_id, gathered there (lamps and m's links); with
    // `wall`, also what it gathers of that plane near sp.
    Rgb radiance_at(const Solution& s, const Config& c, int m_id, const Vec3& sp, uint64_t seed, Counts& counts,
                    NearPlane* wall = nullptr) const;
    // Whether an escape ray from x finds open space (the point is not enclosed).
    static bool point_escapes(const Solution& s, const Vec3& x, const Vec3& n, uint64_t seed, Counts& counts);
    // Whether every one of 64 stratified rays from o (already off its surface) over the
    // hemisphere of n reaches the back of a face: o lies inside a closed solid.
    static bool point_sealed(const Solution& s, const Vec3& o, const Vec3& n, uint64_t seed, Counts& counts);
    // Whether the sealed rule holds for this scene: no lamp and no emitting face lies inside a
    // closed solid (a lamp in a closed box, a room whose normals all point outward).
    static bool light_sealed_in(const Solution& s, Counts& counts);
    void run(const Solution& s, const Config& c, std::vector<Job>& jobs, const Moves* moves,
             const std::function<void(double)>& progress);

    // Per receiving node, the fully occluded links into it (not in its in_links), for the
    // duration of a run.
    struct OccludedLinks {
        std::vector<int32_t> begin, links;  // links[begin[node] .. begin[node + 1])
        void build(const Hierarchy& h, const std::vector<Link>& links);
    };
    OccludedLinks occluded_;
    bool sealed_rule_ = false;  // for the duration of a run: Config::sealed_solids && !light_sealed_in

    bool traced_ = false;
    Config config_;
    std::vector<LightDesc> lights_;  // as last traced (a light changed: every point's lamps again)
    std::vector<Point> points_;
    std::vector<std::vector<int>> corner_point_;  // per object, per corner: its point (-1: none)
    Counts counts_;
    size_t bytes_ = 0;
    size_t measure_bytes() const;
};

}  // namespace radiosity
