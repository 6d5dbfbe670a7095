// The final gather's internals, private to its sources (final_gather.cpp, shared_gather.cpp,
// near_field.cpp, near_direct.cpp, preview.cpp): what a trace keeps per output point (Point)
// and per point-link transfer (Record), one point to trace (Job), what a run passes along to
// each point it traces (Run, Scratch), and FinalGather::Impl, which holds the last trace.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "radiosity/lights.h"
#include "near_field.h"  // (with FinalGather's Solution, Config and Counts as fg's own)

namespace radiosity {

class PointIndex;  // preview_order.h

namespace fg {

using Moves = FinalGather::Moves;

// One link's transfer to a point, as traced: its samples, coupling and ray outcomes. Compact
// (32 bytes): a large room keeps tens of millions of them for its updates. Its samples end at
// `end` in Point::samples and begin where the record before it ends (Point::begin_of).
struct Record {
    uint64_t blocked = 0;  // its rays' outcomes (outcome(): bit k set when ray k was blocked)
    // The link's sender: a point reads each sender through one link, and what it finds
    // does not depend on the receiver node that holds the link (its seed is the point's
    // and the sender's), so after a split on the receiver side the record still serves.
    int src = -1;
    uint32_t end = 0;
    float F = 0;               // coupling, visibility included (for the closure)
    float inv_dist = 0;        // PointTransfer::inv_dist
    uint16_t rays = 0;         // ray budget it was traced with
    uint16_t count = 0;        // rays streamed, at most 65535 (over 64 no outcome is replayed)
    bool own = false;          // a link at the leaf itself (not inherited)
    bool refined = false;      // traced again with more rays (a shadow edge)
    bool emits = false;        // its sender emits, or holds a surface that does
    // The outcomes as a ray stream replays them after a move.
    PointRays outcome() const {
        PointRays o;
        o.count = count;
        o.blocked = blocked;
        return o;
    }
    void set_outcome(const PointRays& o) {
        count = uint16_t(std::min(o.count, 65535));
        blocked = o.blocked;
    }
};
static_assert(sizeof(Record) == 32, "a Record stays 32 bytes");
struct Point {
    // Empties what a trace found (before tracing the point again); `gather`: it gathers all
    // its links, not only its emitters (a shared point).
    void reset(bool gather) {
        gathered = gather;
        reach = 0;
        samples.clear();
        records.clear();
        direct = Rgb{};
        lamp_rays = LampRays{};
        near = Rgb{};
        escapes = -1;
        c_own = c_inherited = 1;
        fill = 0;
        sealed = false;
    }
    // Frees what a trace found (an old point once the retrace has read it).
    void release() {
        std::vector<std::pair<int, float>>().swap(samples);
        std::vector<Record>().swap(records);
        std::vector<std::pair<int, float>>().swap(borrow);
        lamp_rays = LampRays{};
    }
    // Where record r's samples begin in `samples` (r one of `records`).
    uint32_t begin_of(const Record& r) const {
        const size_t i = size_t(&r - records.data());
        return i > 0 ? records[i - 1].end : 0;
    }
    int object = -1, prim = -1, k = 0;  // the corner it was made for (first of its corners)
    Vec3 x, n;
    uint64_t seed = 0;
    int leaf = -1;       // the leaf holding it (its reflectance, emission, and fill radiance)
    bool covered = false;
    // Covered: the leaf of the covering polygon's other side at the point. What lies
    // beyond the contact is what Cycles' rays from there find (a box's dark inside under
    // it, the underside of the floor under the box's bottom), and that side's radiance is
    // what the point gathers; -1 when the covering polygon is one-sided.
    int beyond = -1;
    Rgb direct;          // lamps' irradiance / pi
    LampRays lamp_rays;  // its shadow rays' outcomes (replayed after a move)
    // Near-field correction (near_field.cpp), irradiance / pi: the senders a
    // hair from the point read at a point of theirs instead of their leaf's average.
    Rgb near;
    // Inside a closed solid (point_sealed): no light reaches it; a covered point so
    // sealed reads nothing beyond its contact either.
    bool sealed = false;
    int8_t escapes = -1;  // enclosed leaves only: whether the point's own escape rays find open space
    // Closure (as the solver's at the leaf): factors on own and inherited couplings, and
    // the share of the hemisphere taken to see the leaf's own radiance.
    double c_own = 1, c_inherited = 1, fill = 0;
    std::vector<std::pair<int, float>> samples;  // (node, weight): irradiance / pi = sum w L
    std::vector<Record> records;
    // A shared point (Config::share) traced only its lamps and emitting senders; its
    // bounced light is that of gathered points near it: (point, weight), weights summing
    // to 1. A gathered point lends within share x `reach` (0: lends nothing).
    bool gathered = true;
    float reach = 0;
    std::vector<std::pair<int, float>> borrow;
    // Its own reach as the shared gathers probed it (probe_reach; -1: not asked for in its
    // trace), and where each probe ray ended (shared_gather.cpp's probe_end): a retrace keeps
    // the value where no probe ray meets a moved box. Neither reset nor released: the probe
    // is made before the point is traced, and a retrace reads the old one's.
    double probed = -1;
    std::array<uint8_t, 16> probe_ends{};
};
// One output point to trace: a corner, or the corners of one vertex sharing a normal and
// a contact state (final_gather.cpp make_jobs).
struct Job {
    int object = -1, prim = -1, k = 0;
    Vec3 x, n;
    int leaf = -1, surface = -1;
    bool covered = false;
    int beyond = -1;  // corner_covered
    uint64_t seed = 0;
};

// A link that brings a point's leaf its light (uses): its light at stake (for the ray budget).
struct Use { int link; bool own; double weight; };

// Per receiving node, the fully occluded links into it (not in its in_links), for the
// duration of a run.
struct OccludedLinks {
    std::vector<int32_t> begin, links;  // links[begin[node] .. begin[node + 1])
    void build(const Hierarchy& h, const LinkStore& links);
};

// One trace or retrace, as every point it traces reads it.
struct Run {
    const Solution& s;
    const Config& c;
    const Moves* moves = nullptr;  // a retrace's
    OccludedLinks occluded;        // links_reaching's
    bool sealed_rule = false;      // Config::sealed_solids, and no light sealed in a solid
};

// Lists one thread reuses from point to point while it traces (their capacity stays, so a
// point allocates nothing), made per run.
struct Scratch {
    std::vector<Use> use;                        // trace_point: the point's links
    std::vector<std::pair<int, bool>> reaching;  // uses()
    NearScratch near;
};

// The links that reach a leaf: at it (own), at its element ancestors and at the clusters
// above its surface, and with `occluded` (a run's), the fully occluded ones too.
void links_reaching(const Solution& s, const OccludedLinks* occluded, int leaf,
                    std::vector<std::pair<int, bool>>& out);
// A point traced afresh, or (with `old`, in a retrace) re-traced after the run's moves; with
// `emitters_only`, only its lamps and the links from emitting senders (a shared point).
void trace_point(const Run& run, Point& pt, const Point* old, Counts& counts, Scratch& scratch, bool emitters_only);
// What one record's samples read of the current solution (irradiance / pi, before closure).
Rgb record_light(const Hierarchy& h, const Point& p, const Record& r);
// What a point's lamps and emitting senders bring (irradiance / pi, through its closure):
// shared_gather.cpp.
Rgb emitted_part(const Hierarchy& h, const Point& p);
// A gathered point's reach: the harmonic mean distance of what its rays found, or the
// distance to the nearest dark sender (`dark`, found by trace_point) when that is less;
// 0 when it lends nothing (covered, sealed, nothing seen): shared_gather.cpp.
float lend_reach(const Point& pt, double dark);
// The seed of a point's transfer from sender node `src`: the point's and the sender's alone
// (not the link's), so the same transfer draws the same rays whichever link holds it.
inline uint64_t transfer_seed(const Hierarchy& h, uint64_t point_seed, int src) {
    return Hierarchy::mix(point_seed, Hierarchy::mix(h.nodes[size_t(src)].key, 0x5e4d3ull));
}
// A transfer's share of a point's ray budget: `budget` x weight / total in powers of two,
// within [lo, hi] (lo when it brings nothing).
int ray_share(int budget, double weight, double total, int lo, int hi);

}  // namespace fg

// What the last trace keeps, and the steps that make and read it.
struct FinalGather::Impl {
    bool traced = false;
    Config config;
    std::vector<LightDesc> lights;  // as last traced (a light changed: every point's lamps again)
    std::vector<fg::Point> points;
    std::vector<std::vector<int>> corner_point;  // per object, per corner: its point (-1: none)
    Counts counts;
    size_t bytes = 0;
    // The live drag's last previews (preview.cpp): per point the change shown and whether it
    // showed the point covered (unlit), those points, the points whose change was ever
    // non-zero (`touched`, and per point whether it is one), the objects dragged, where among
    // the dragged objects' points the next step starts; per node whether it emits or holds an
    // emitter, where the points are (preview_order.h) and what arrives at them in the bake; the
    // last three kept for the trace.
    struct PreviewState {
        std::vector<Rgb> shown;
        std::vector<char> unlit;
        std::vector<uint32_t> unlit_points;
        std::vector<uint32_t> touched;
        std::vector<char> is_touched;
        std::vector<char> moved;
        size_t turn = 0;
        std::vector<char> emits;
        std::shared_ptr<const PointIndex> index;
        std::vector<Rgb> arriving;        // per point: what arrives in the bake (arriving()), ...
        std::vector<char> has_arriving;   // ... where made
    } preview_state;

    // The points to trace, one per corner or per vertex's corners alike; fills corner_point.
    std::vector<fg::Job> make_jobs(const Solution& s);
    void run(const Solution& s, const Config& c, std::vector<fg::Job>& jobs, const Moves* moves,
             const std::function<void(double)>& progress);
    // Decides, level by level, which points gather fully and which share (Config::share);
    // `trace(i, emitters_only)` traces point i. Fills the shared points' borrow lists and the
    // probes of the points' own reach (in a retrace, `old[i]`'s kept where `moves` cannot
    // change it; old[i] is point i's last trace or null); adds the rays it cast itself and the
    // probes kept to `counts`: shared_gather.cpp.
    void share_gathers(const Solution& s, const Config& c, const std::vector<fg::Job>& jobs,
                       const std::vector<fg::Point*>& old, const Moves* moves, Counts& counts,
                       const std::function<void(size_t, bool)>& trace, const std::function<void(double)>& progress);
    size_t measure_bytes() const;
    std::vector<float> values(const Hierarchy& h, int object, bool irradiance) const;
    // What arrives at a point (irradiance / pi) from its trace and the current leaf
    // radiances, before it is clamped at 0. `bounced` (values()'s cache, per point): a
    // lender's bounced light, made when first read.
    Rgb arriving(const Hierarchy& h, const fg::Point& p, std::vector<std::pair<bool, Rgb>>* bounced = nullptr) const;
    // What a point shows when `e` arrives: irradiance / pi, or the radiance it leaves with.
    static Rgb shown_value(const Hierarchy& h, const fg::Point& p, const Rgb& e, bool irradiance);
    Rgb point_value(const Hierarchy& h, const fg::Point& p, bool irradiance, const Rgb& change = Rgb{},
                    std::vector<std::pair<bool, Rgb>>* bounced = nullptr) const {
        return shown_value(h, p, arriving(h, p, bounced) + change, irradiance);
    }
    // A gathered point's irradiance / pi without what emitted_part gives: what it lends
    // (shared_gather.cpp).
    Rgb bounced_part(const Hierarchy& h, const fg::Point& p) const;
    // A preview's corners (preview.cpp): those of the points `changed` whose change d[i] is
    // not zero, with what each shows now, by object and corner.
    std::vector<CornerChange> corner_changes(const Hierarchy& h, const std::vector<uint32_t>& changed,
                                             const std::vector<Rgb>& d);
};

}  // namespace radiosity
