#include "radiosity/final_gather.h"
#include "final_gather_trace.h"
#include "point_couplings.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_map>

#include <tbb/enumerable_thread_specific.h>

#include "radiosity/gather_plan.h"
#include "radiosity/lights.h"
#include "radiosity/parallel.h"
#include "radiosity/random.h"
#include "radiosity/transfer.h"

namespace radiosity {
namespace fg {
namespace {

// Corners of one vertex with the same normal and contact state share one point (traced at the
// first one's sample point): a gridded floor's four corners then cost one gather, not four.
// Where Cycles' corners of one vertex differ most, at the foot of a box, their contact states
// differ and they do not share.
constexpr bool kShareVertexPoints = true;

// Where the corner is baked (internal frame): as Cycles does, just inside the first of the
// polygon's loop triangles that holds the corner (a quad splits into corners 0-1-2 and 0-2-3),
// moved from the vertex toward that triangle's centroid. Cycles moves it by
// min(distance, 1e-4 x max(largest |world coordinate|, 1)), 0.1-0.5 mm in a room modelled in
// metres. Where light changes within a millimetre (a lamp hung 1 mm under a ceiling: the
// form factor differs by 1 % between the four corners' points of one vertex) only the same
// point gives the same value, so by default (Config::cycles_points) the step is Cycles' own,
// at most 1 % of the distance (Cycles', at a scale of millimetres, would reach the centroid).
// Otherwise it is 3e-5 of the scene's size: the same at any scale and offset, as the rest of
// the solver. Either puts the floor corners of faces under a box on the unlit side of the
// box's edge, and those of faces beside it on the lit side.
Vec3 sample_point(const ObjectDesc& o, const Primitive& p, int k, const Hierarchy& h, bool cycles_points) {
    const Vec3 v = p.poly.v[size_t(k)];
    Vec3 c = p.poly.centroid();
    const int total = o.loop_totals[size_t(p.face)];
    if (total == 4 && p.poly.n == 4) {
        // The quad's own corners in Blender's order (the primitive may start elsewhere).
        const int j = p.corner[size_t(k)] - o.loop_starts[size_t(p.face)];
        std::array<Vec3, 4> q{};
        for (int i = 0; i < 4; ++i) q[size_t((p.corner[size_t(i)] - o.loop_starts[size_t(p.face)]) & 3)] = p.poly.v[size_t(i)];
        c = j == 3 ? (q[0] + q[2] + q[3]) / 3.0 : (q[0] + q[1] + q[2]) / 3.0;
    } else if (p.poly.n == 3) {
        c = (p.poly.v[0] + p.poly.v[1] + p.poly.v[2]) / 3.0;
    }
    const Vec3 to_c = c - v;
    const double d = length(to_c);
    if (!(d > 0)) return v;
    double step = 3e-5 * h.scene_diag;
    if (cycles_points) {
        const Vec3 w = o.vertices[size_t(o.corner_verts[size_t(p.corner[size_t(k)])])];
        const double m = std::max({std::fabs(w.x), std::fabs(w.y), std::fabs(w.z), 1.0});
        step = std::min(1e-4 * m / h.unit, 0.01 * d);
    }
    return v + to_c * (std::min(d, step) / d);
}

// Whether a corner lies on the faces of other objects turned against its own (a floor vertex
// under a box, the corners of the box's bottom): Cycles bakes such corners unlit. Cycles
// shades a corner inside its own face, so at the foot of a box the floor corners of faces
// under the box are unlit and those of faces beside it lit (their rays find the box in one
// half of the hemisphere and the room in the other): the test looks at the sample
// point, just inside the face.
// Returns the node beyond the contact (the covering polygon's other side's leaf there, or -2
// for a one-sided one), or -1 when the corner is not covered.
int corner_covered(const Solution& s, const Primitive& p, const Vec3& inside) {
    if (!s.contact) return -1;
    const int t = s.contact(p.front, inside);
    if (t < 0) return -1;
    const Surface& cs = s.h.surfaces[size_t(t)];
    const Primitive& cp = s.h.prims[size_t(cs.prim)];
    const int other = cs.back ? cp.front : cp.back;
    if (other < 0) return -2;
    return s.h.leaf_at(s.h.surfaces[size_t(other)].root, inside);
}

}  // namespace
}  // namespace fg

// The closure at an output point: its couplings must sum to 1 where the point sees no open
// space. A shortfall is filled as at a leaf (closure_factors: with the leaf's own radiance).
// An excess is not the leaf's: there the inherited links carry couplings averaged over a
// larger receiver, but at a point every link is evaluated from the point itself, and the
// error is the estimate's. Element senders' couplings are exact (Lambert's closed form, only
// visibility sampled); cluster senders' are Monte Carlo sums over their surfaces. So the
// excess is taken from the sampled couplings, own or inherited alike (all couplings alike when
// those are too small to hold it). Taking it from the inherited links, as a leaf does, would
// cut a point's exact lamp links where its own cluster links sum a little over 1
// (docs/decisions.md, "Closure at output points").
// Expressed as the factors on the own and inherited parts (values() splits by those).
ClosureFactors point_closure_factors(double own, double inherited, double s_own, double s_inherited) {
    const double f = own + inherited;
    if (!(f > 1.0 && f < 4.0)) return closure_factors(own, inherited);  // gather_plan.h
    ClosureFactors c;
    const double excess = f - 1.0, sampled = s_own + s_inherited;
    if (sampled > excess) {
        const double k = (sampled - excess) / sampled;
        c.c_own = own > 0 ? (own - s_own * (1.0 - k)) / own : 1.0;
        c.c_inherited = inherited > 0 ? (inherited - s_inherited * (1.0 - k)) / inherited : 1.0;
    } else {
        c.c_own = c.c_inherited = 1.0 / f;
    }
    return c;
}


namespace fg {
namespace {

constexpr int kDeepRays = 8;

// The point's lamps (kept after a move that cannot shade them).
void trace_lamps(const Run& run, Point& pt, const Point* old, Counts& counts) {
    const Solution& s = run.s;
    const Moves* moves = run.moves;
    const Hierarchy& h = s.h;
    const Vec3& x = pt.x;
    const Vec3& n = pt.n;
    // Lamps: after a move, a shadow ray that meets no moved box keeps its recorded outcome
    // (the sun's and the sky's rays from a wall that misses the moved armchair's old and new
    // boxes). Where no lamp's ray can meet one (only point and spot lights, each one's
    // segment hull from the point missing the boxes), the lamps are not even re-sampled.
    const bool replay = old != nullptr && !old->sealed && !moves->cast_all && !moves->lights_changed &&
                        old->lamp_rays.count > 0;
    // Every shadow ray leaves the point's plane upward: all that moved below it shades none.
    const bool below = replay && std::all_of(moves->clips.begin(), moves->clips.end(),
                                             [&](const Aabb& b) { return b.max_along(n) < dot(n, x); });
    bool lamps_kept = replay;
    if (replay && !below) {
        for (const LightDesc& d : s.scene.lights()) {
            if (d.intensity.max() <= 0) continue;
            if (d.type == LightDesc::Type::Sun || d.type == LightDesc::Type::Sky) { lamps_kept = false; break; }
            const Vec3 q = h.to_internal(d.position);
            const double r = d.radius / h.unit;
            if (hull_meets(x, Aabb::around(q, r), moves->clips)) { lamps_kept = false; break; }
        }
    }
    if (lamps_kept) {
        pt.direct = old->direct;
        pt.lamp_rays = old->lamp_rays;
    } else {
        const PointLight lamp = direct_light_replay(s.scene, h, s.vis, x, n, run.c.light_samples, pt.seed,
                                                    replay ? &old->lamp_rays : nullptr, replay ? &moves->clips : nullptr,
                                                    pt.lamp_rays);
        pt.direct = lamp.E;
        counts.rays += lamp.rays;
        counts.lamp_rays += lamp.rays;
    }
}

// trace_transfer's transfer traced afresh with `rays` (its share of the budget), again with more
// where a shadow edge crosses it: fills rec's coupling, rays and outcomes.
void trace_afresh(const Run& run, Point& pt, Counts& counts, Record& rec, uint32_t begin, uint64_t lseed, int rays,
                  int refined_rays, double weight, double total, size_t links) {
    const Solution& s = run.s;
    const Config& c = run.c;
    const Hierarchy& h = s.h;
    const Vec3& x = pt.x;
    const Vec3& n = pt.n;
    const int src = rec.src;
    PointRayStream rs(s.vis);
    PointTransfer t = point_transfer(h, rs, src, x, n, pt.leaf, rays, lseed, pt.samples);
    counts.rays += rs.cast;
    rec.set_outcome(rs.out);
    // The transfer again with more rays (and another seed), in place of the last.
    auto retrace_with = [&](int more, uint64_t seed_step) {
        pt.samples.resize(begin);
        rays = more;
        PointRayStream again(s.vis);
        t = point_transfer(h, again, src, x, n, pt.leaf, rays, lseed + seed_step, pt.samples);
        counts.rays += again.cast;
        rec.set_outcome(again.out);
        rec.refined = true;
        ++counts.refined;
    };
    // A shadow edge crosses what this point sees of a sender that matters: four times
    // the rays (a corner at the rim of a lamp's footprint needs more than one mid-wall).
    if (t.partial && rays < c.rays && total > 0 && weight > total / (4.0 * double(links)))
        retrace_with(refined_rays, 1);
    // Deep in a penumbra of the sender that brings most of the point's light (under a
    // tenth of it seen), the estimate rests on the few rays that get through (its error
    // goes as 1 / sqrt(rays seen)): eight times the budget there.
    if (t.partial && total > 0 && weight > 0.5 * total && t.F < 0.1 * t.F_unoccluded &&
        rays < kDeepRays * c.rays)
        retrace_with(std::min(kDeepRays * c.rays, 65535), 2);
    rec.F = float(t.F);
    rec.inv_dist = float(t.inv_dist);
    rec.rays = uint16_t(std::min(rays, 65535));
}

// One sender's transfer to the point (`weight` its light at stake, of `total` over `links`
// links): kept from the last trace when no ray of it can meet a moved box, its rays replayed
// when some can, else traced afresh with the point's share of the budget for it (more where a
// shadow edge crosses it). Appends its samples.
Record trace_transfer(const Run& run, Point& pt, const Point* old, Counts& counts, int src, double weight, double total,
                      size_t links) {
    const Solution& s = run.s;
    const Config& c = run.c;
    const Moves* moves = run.moves;
    const Hierarchy& h = s.h;
    const Vec3& x = pt.x;
    const Vec3& n = pt.n;
    // Seeded by the point and the sender alone: what the point's rays find of a sender does
    // not depend on which receiver node holds the link, so when an update splits a link on
    // the receiver side (a closure split), the link that now reaches the point from the
    // same sender is the same transfer, and its record is kept or replayed (below).
    const uint64_t lseed = transfer_seed(h, pt.seed, src);
    Record rec;
    rec.src = src;
    const uint32_t begin = uint32_t(pt.samples.size());  // (where the last record ends)
    const Record* was = nullptr;
    // The link's share of the budget, in powers of two: a small change of the light (an
    // update's solution against a full solve's) then rarely changes a link's rays, so the
    // two gather the same rays where their links agree.
    int rays = ray_share(c.rays, weight, total, c.min_rays, std::max(c.rays, c.min_rays));
    // A sender wholly behind the point's tangent plane brings it nothing: its record is what a
    // trace would make (no coupling, no samples, no rays), without a sampler built or drawn.
    if (plane_reach(h.nodes[size_t(src)].box, x, n) <= 0) {
        rec.rays = uint16_t(std::min(rays, 65535));
        return rec;
    }
    const int refined_rays = std::min(c.rays, 4 * rays);
    // The same link, or one new since (split on the receiver side, or made again) from a
    // sender the point read before: the same transfer.
    // (Looked for first where it stood: an unchanged point reads its senders in the same order.)
    if (old) {
        const size_t at = pt.records.size();
        if (at < old->records.size() && old->records[at].src == src) {
            was = &old->records[at];
        } else {
            for (const Record& r : old->records)
                if (r.src == src) { was = &r; break; }
        }
    }
    // Replayed only with the budget a fresh trace would give it now.
    if (was && int(was->rays) != (was->refined ? refined_rays : rays)) was = nullptr;
    // Its samples name leaves that are still leaves: the same rays would land on them again.
    auto samples_current = [&](const Record& r) {
        for (uint32_t i = old->begin_of(r); i < r.end; ++i) {
            const Node& m = h.nodes[size_t(old->samples[i].first)];
            if (m.dead || !m.children.empty()) return false;
        }
        return true;
    };
    if (was && !moves->cast_all && !hull_meets(x, h.nodes[size_t(src)].box, moves->clips) && samples_current(*was)) {
        // No ray of this transfer can meet a moved box: as it was.
        pt.samples.insert(pt.samples.end(), old->samples.begin() + old->begin_of(*was), old->samples.begin() + was->end);
        rec.F = was->F;
        rec.inv_dist = was->inv_dist;
        rec.rays = was->rays;
        rec.refined = was->refined;
        rec.set_outcome(was->outcome());
        ++counts.kept;
    } else if (was) {
        // Its rays again, with the same budget and seed; those through no moved box keep
        // their recorded outcome.
        const PointRays recorded = was->outcome();
        PointRayStream rs(s.vis, moves->cast_all ? nullptr : &recorded, &moves->clips);
        const PointTransfer t = point_transfer(h, rs, src, x, n, pt.leaf, was->rays, lseed + (was->refined ? 1 : 0), pt.samples);
        rec.F = float(t.F);
        rec.inv_dist = float(t.inv_dist);
        rec.rays = was->rays;
        rec.refined = was->refined;
        rec.set_outcome(rs.out);
        counts.rays += rs.cast;
        ++counts.replayed;
    } else {
        trace_afresh(run, pt, counts, rec, begin, lseed, rays, refined_rays, weight, total, links);
    }
    return rec;
}

void uses(const Run& run, int leaf, std::vector<std::pair<int, bool>>& reaching, std::vector<Use>& use) {
    // The links that bring the leaf its light: at the leaf itself (its own), at its element
    // ancestors and at the clusters above its surface (inherited). Together they cover what
    // the leaf sees once, the invariant of hierarchical radiosity, and so do they for a point.
    const Solution& s = run.s;
    use.clear();
    links_reaching(s, &run.occluded, leaf, reaching);
    for (const auto& [li, own] : reaching) {
        const Link& l = s.links[size_t(li)];
        const Node& src = s.h.nodes[size_t(l.src)];
        // The light at stake, for sharing the ray budget: the coupling as the link saw it
        // unoccluded, times the sender's brightest leaf.
        use.push_back({li, own, l.K_unoccluded * std::max(src.Lmax.max(), src.L.max())});
    }
}

double nearest_dark(const Solution& s, const std::vector<Use>& use, const Vec3& x) {
    // The nearest sender that brings no light (no samples tell where it is): a black sofa
    // beside a floor point shades the floor near it all the same. (A cluster around the
    // point says nothing of where its surfaces are.)
    double dark = std::numeric_limits<double>::infinity();
    for (const Use& u : use) {
        const Link& l = s.links[size_t(u.link)];
        if (u.weight > 0 || !(l.K_unoccluded > 0)) continue;  // lit, or out of sight
        const Node& src = s.h.nodes[size_t(l.src)];
        // (An element's centre, not its polygon: the faces beside the point's own, dark or
        // not, meet it at distance 0 and shade it little.)
        if (!src.is_cluster()) dark = std::min(dark, length(src.center - x));
        else if (!src.box.contains(x)) dark = std::min(dark, distance_to_box(src.box, x));
    }
    return dark;
}

// Whether a move left the point's near field as it was.
bool near_unchanged(const Run& run, const Point& pt, const Point* old) {
    const Moves* moves = run.moves;
    // (Also when every ray is cast again, Settings::replay_rays off: that mode checks that
    // replayed rays are exact, not this.)
    if (!(old != nullptr && old->gathered && !old->sealed && !moves->lights_changed && !moves->materials_changed))
        return false;
    // Nothing moved within 5 % of the scene's size of the point.
    const Aabb vicinity = Aabb::around(pt.x, 0.05 * run.s.h.scene_diag);
    for (const Aabb& b : moves->clips)
        if (b.overlaps(vicinity)) return false;
    return true;
}

// The transfers traced from the links `use` (their couplings, for the closure).
PointCouplings trace_transfers(const Run& run, Point& pt, const Point* old, Counts& counts, const std::vector<Use>& use,
                               bool enclosed, bool emitters_only) {
    const Solution& s = run.s;
    const Hierarchy& h = s.h;
    double total = 0;
    for (const Use& u : use) total += u.weight;
    PointCouplings couplings;
    for (const Use& u : use) {
        // A dark sender brings nothing, but in a closed pocket its coupling still counts
        // toward the closure.
        const Link& l = s.links[size_t(u.link)];
        // A link whose point model failed and whose coupling the solver could not estimate
        // (Link::must_refine into a cluster at the resolution limit) is traced all the same,
        // with the fewest rays -- unless its sender lies wholly behind the point's tangent
        // plane: then it brings the point nothing, not even toward the closure.
        const bool unknown = l.must_refine && !(l.K_unoccluded > 0);
        if (unknown && plane_reach(h.nodes[size_t(l.src)].box, pt.x, pt.n) <= 0) continue;
        if (!(u.weight > 0) && !enclosed && !unknown) continue;
        // A shared point traces these alone, with the budget of a full trace, so that the
        // two draw the same rays.
        const bool emits = h.emits(l.src, Hierarchy::Unknown::Emits);  // a sender made since counts as emitting
        if (emitters_only && !emits) continue;
        Record rec = trace_transfer(run, pt, old, counts, l.src, u.weight, total, use.size());
        rec.own = u.own;
        rec.emits = emits;
        ++counts.links;
        rec.end = uint32_t(pt.samples.size());
        pt.records.push_back(rec);
        const uint32_t begin = pt.begin_of(pt.records.back());
        couplings.add(closing_coupling(h, l.src, rec.F, pt.samples.data() + begin, rec.end - begin), u.own,
                      h.nodes[size_t(l.src)].is_cluster());
    }
    return couplings;
}

// Whether an escape ray from x finds open space (the point is not enclosed).
bool point_escapes(const Solution& s, const Vec3& x, const Vec3& n, uint64_t seed, Counts& counts) {
    // Cosine-distributed, stratified over an 8 x 8 grid of the unit square: a gap of a fraction
    // g of the projected hemisphere goes unseen with probability about (1 - g)^64, and what it
    // then costs (a fill of g) is at most 1 / (64 e) = 0.6 % of the leaf's radiance.
    const double far = 4.0 * s.h.scene_diag;
    const double lift = 1e-5 * s.h.scene_diag;
    Rng rng(Hierarchy::mix(seed, 0xe5ca9eu));
    const CosineStrata strata(n, 8);
    const Vec3 o = x + n * lift;
    for (int i = 0; i < strata.count(); ++i) {
        const Vec3 d = strata.direction(i, rng);
        ++counts.rays;
        if (!s.vis.occluded(o, o + d * far, 0.0)) return true;
    }
    return false;
}

// What a ray from o along d meets, for the sealed rule: the inside of a solid (kBack: the back
// of a face, its front's normal in `fn`), or what says o is outside every solid there (kOpen:
// nothing, an emitting face, a face's front out in the open). A front met inside another
// solid (an eye's hidden half, sunk into a head) is the inside of that solid: a ray from it
// along its normal (`probe`) meets a back there.
enum class SolidSide { kOpen, kBack };
SolidSide solid_side(const Solution& s, const Vec3& o, const Vec3& d, double far, Vec3& fn, bool probe, Counts& counts) {
    const Hierarchy& h = s.h;
    ++counts.rays;
    Vec3 at;
    const int prim = s.prim_hit(o, o + d * far, at);
    if (prim < 0) return SolidSide::kOpen;
    const Primitive& p = h.prims[size_t(prim)];
    for (int side : {p.front, p.back})
        if (side >= 0 && h.nodes[size_t(h.surfaces[size_t(side)].root)].emission.max() > 0) return SolidSide::kOpen;
    // The face's orientation as placed now (a moved object's surfaces turn with it).
    fn = p.front >= 0 ? h.nodes[size_t(h.surfaces[size_t(p.front)].root)].normal : p.poly.normal();
    // The front of a face covered there by another turned against it (a plinth's top
    // under a cabinet's bottom: the ray meets either of the two coplanar faces) is the
    // back of the covering one.
    if (!(dot(d, fn) > 0) && p.front >= 0 && s.contact && s.contact(p.front, at) >= 0) fn = fn * -1.0;
    if (dot(d, fn) > 0) return SolidSide::kBack;
    if (!probe) return SolidSide::kOpen;
    const Vec3 front = fn;
    return solid_side(s, at + front * (1e-5 * h.scene_diag), front, far, fn, false, counts);
}

// Whether each of 64 stratified cosine rays from o (already off its surface) over the
// hemisphere of n meets the inside of a solid (solid_side), the backs met facing at least
// three ways: one plane seen from behind (a lamp hung under a ceiling, a rug a hair above the
// floor) covers a point's hemisphere without enclosing anything, and Cycles lights what lies
// behind it (an emitter's back glows).
bool point_sealed(const Solution& s, const Vec3& o, const Vec3& n, uint64_t seed, Counts& counts) {
    // As point_escapes: stratified and cosine-distributed; a gap in the solid (a crack under
    // a wall standing a hair above the floor) lets light in and is found with the same odds.
    const double far = 4.0 * s.h.scene_diag;
    Rng rng(seed);
    const CosineStrata strata(n, 8);
    Vec3 ways[3];
    int nways = 0;
    for (int i = 0; i < strata.count(); ++i) {
        const Vec3 d = strata.direction(i, rng);
        Vec3 fn;
        if (solid_side(s, o, d, far, fn, true, counts) != SolidSide::kBack) return false;
        bool seen = false;
        for (int k = 0; k < nways && !seen; ++k) seen = dot(ways[k], fn) > 0.99;
        if (!seen && nways < 3) ways[nways++] = fn;
    }
    return nways >= 3;
}

// Whether the sealed rule holds for this scene: no lamp and no emitting face lies inside a
// closed solid (a lamp in a closed box, a room whose normals all point outward).
bool light_sealed_in(const Solution& s, Counts& counts) {
    const Hierarchy& h = s.h;
    const double lift = 1e-5 * h.scene_diag;
    // A lamp at a point: inside a solid when both hemispheres are sealed.
    for (const LightDesc& d : s.scene.lights()) {
        if (d.intensity.max() <= 0 || d.type == LightDesc::Type::Sun || d.type == LightDesc::Type::Sky) continue;
        const Vec3 q = h.to_internal(d.position);
        const Vec3 z{0, 0, 1};
        if (point_sealed(s, q, z, 0x1a3bu, counts) && point_sealed(s, q, z * -1.0, 0x1a3cu, counts)) return true;
    }
    // Emitting faces, from their centroid on each emitting side (at most 512 faces, evenly
    // spread: a lamp is a few faces, an emissive wall many alike).
    std::vector<int> emitting;
    for (size_t i = 0; i < h.surfaces.size(); ++i) {
        const Surface& sf = h.surfaces[i];
        if (sf.root < 0 || h.surface_dead(int(i))) continue;
        if (h.nodes[size_t(sf.root)].emission.max() > 0) emitting.push_back(int(i));
    }
    const size_t step = std::max<size_t>(1, emitting.size() / 512);
    for (size_t k = 0; k < emitting.size(); k += step) {
        const Node& r = h.nodes[size_t(h.surfaces[size_t(emitting[k])].root)];
        if (point_sealed(s, r.poly.centroid() + r.normal * lift, r.normal, 0x1a3du + k, counts)) return true;
    }
    return false;
}

}  // namespace

void links_reaching(const Solution& s, const OccludedLinks* occluded, int leaf, std::vector<std::pair<int, bool>>& out) {
    const Hierarchy& h = s.h;
    out.clear();
    auto take = [&](int node, bool own) {
        for (int li : h.nodes[size_t(node)].in_links) {
            const Link& l = s.links[size_t(li)];
            if (!l.dead && l.active && !l.occluded) out.emplace_back(li, own);
        }
        // Links the solver found fully occluded from the receiver's cubature points are still
        // part of what the receiver covers (they are kept for a move to reopen): a point of
        // it may see the sender all the same, e.g. a corner on the rim of a shadow that covers
        // the rest of a large leaf. (Known during a trace only: a preview goes without.)
        if (!occluded || occluded->begin.empty()) return;
        for (int32_t k = occluded->begin[size_t(node)]; k < occluded->begin[size_t(node) + 1]; ++k)
            out.emplace_back(occluded->links[size_t(k)], own);
    };
    for (int a = leaf; a >= 0 && !h.nodes[size_t(a)].is_cluster(); a = h.nodes[size_t(a)].parent) take(a, a == leaf);
    for (int a : h.ancestors_of_surface(h.nodes[size_t(leaf)].surface)) take(a, false);
}

int ray_share(int budget, double weight, double total, int lo, int hi) {
    int n = lo;
    if (total > 0 && weight > 0) {
        const double want = budget * weight / total;
        n = want >= 1 ? 1 << int(std::lround(std::log2(want))) : 1;
    }
    return std::min(std::max(n, lo), hi);
}

Rgb record_light(const Hierarchy& h, const Point& p, const Record& r) {
    Rgb g;
    for (uint32_t i = p.begin_of(r); i < r.end; ++i)
        g += h.nodes[size_t(h.live_element(p.samples[i].first))].L * double(p.samples[i].second);
    return g;
}

void trace_point(const Run& run, Point& pt, const Point* old, Counts& counts, Scratch& scratch, bool emitters_only) {
    const Solution& s = run.s;
    const Config& c = run.c;
    pt.reset(!emitters_only);
    // Inside a closed solid (the floor inside a bottomless block, under a box's bottom):
    // nothing lights it, whatever the leaves around say. One ray tells most points they are
    // not (it escapes or meets a face's front).
    if (run.sealed_rule && (!pt.covered || pt.beyond >= 0) &&
        point_sealed(s, pt.x + pt.n * (1e-5 * s.h.scene_diag), pt.n, Hierarchy::mix(pt.seed, 0x5ea1edu), counts)) {
        pt.sealed = true;
        pt.beyond = -1;
        return;
    }
    if (pt.covered) return;
    trace_lamps(run, pt, old, counts);
    std::vector<Use>& use = scratch.use;
    uses(run, pt.leaf, scratch.reaching, use);
    // (A shared point's closure and near field are its lenders'.)
    const bool enclosed = s.enclosure.enclosed(pt.leaf) == 1 && !emitters_only;
    const double dark = c.share > 0 && !emitters_only ? nearest_dark(s, use, pt.x) : std::numeric_limits<double>::infinity();
    const bool unchanged = near_unchanged(run, pt, old);
    const PointCouplings couplings = trace_transfers(run, pt, old, counts, use, enclosed, emitters_only);
    if (emitters_only) return;
    if (c.share > 0) pt.reach = lend_reach(pt, dark);
    // Closure at the point, as the solver's at the leaf: where no escape ray of the leaf found
    // open space, the point's couplings must sum to 1 -- unless the point itself sees out.
    // A ceiling leaf over a lamp hung 1 mm below it finds no way out with its escape rays, but
    // its points near the lamp's rim see a little of their hemisphere through the gap, dark:
    // filling that with the leaf's own radiance would read them too bright.
    if (enclosed)
        pt.escapes = unchanged && old->escapes >= 0 ? old->escapes : int8_t(point_escapes(s, pt.x, pt.n, pt.seed, counts));
    if (enclosed && pt.escapes == 0) {
        const ClosureFactors cf = couplings.closure();
        pt.c_own = cf.c_own;
        pt.c_inherited = cf.c_inherited;
        pt.fill = cf.fill;
    }
    // Kept after a move that comes nowhere near the point: the senders it corrects lie within
    // 20 d of it, and what a distant move changes there it changes about as much in their
    // leaves' averages, which the samples read afresh; the correction is the difference of
    // the two (L(s*) - the average), so keeping it errs by the difference of the changes.
    if (unchanged && old->leaf == pt.leaf)  // (the correction reads the leaf's own values)
        pt.near = old->near;
    else {
        const int64_t before = counts.rays;
        near_field(run, pt, counts, scratch.near);  // after the closure: it reads the point's full irradiance
        counts.near_rays += counts.rays - before;
    }
}

void OccludedLinks::build(const Hierarchy& h, const LinkStore& links) {
    begin.assign(h.nodes.size() + 1, 0);
    for (const Link& l : links)
        if (!l.dead && l.occluded && !l.active && size_t(l.rcv) < h.nodes.size()) ++begin[size_t(l.rcv) + 1];
    for (size_t i = 1; i < begin.size(); ++i) begin[i] += begin[i - 1];
    this->links.assign(size_t(begin.back()), -1);
    std::vector<int32_t> at(begin.begin(), begin.end() - 1);
    for (size_t i = 0; i < links.size(); ++i) {
        const Link& l = links[i];
        if (!l.dead && l.occluded && !l.active && size_t(l.rcv) < h.nodes.size()) this->links[size_t(at[size_t(l.rcv)]++)] = int32_t(i);
    }
}

}  // namespace fg

FinalGather::FinalGather() : impl_(std::make_unique<Impl>()) {}
FinalGather::~FinalGather() = default;
FinalGather::FinalGather(FinalGather&&) noexcept = default;
FinalGather& FinalGather::operator=(FinalGather&&) noexcept = default;

// (A moved-from FinalGather holds no trace: the calls below that read one ask traced() first.)
bool FinalGather::traced() const { return impl_ && impl_->traced; }

const FinalGather::Counts& FinalGather::counts() const {
    static const Counts none;
    return impl_ ? impl_->counts : none;
}

size_t FinalGather::bytes() const { return impl_ ? impl_->bytes : 0; }

void FinalGather::clear() {
    if (!impl_) impl_ = std::make_unique<Impl>();
    Impl& t = *impl_;
    t.traced = false;
    t.points.clear();
    t.corner_point.clear();
    t.counts = Counts{};
    t.bytes = 0;
    t.preview_state = Impl::PreviewState{};
}

int FinalGather::corner_point(int object, size_t corner) const {
    if (!traced() || object < 0 || size_t(object) >= impl_->corner_point.size()) return -1;
    const auto& cp = impl_->corner_point[size_t(object)];
    return corner < cp.size() ? cp[corner] : -1;
}

std::vector<double> FinalGather::probes() const {
    std::vector<double> out;
    if (!traced()) return out;
    for (const fg::Point& p : impl_->points) out.push_back(p.probed);
    return out;
}

std::vector<float> FinalGather::corner_radiance(const Hierarchy& h, int object) const {
    return traced() ? impl_->values(h, object, false) : std::vector<float>{};
}

std::vector<float> FinalGather::corner_irradiance(const Hierarchy& h, int object) const {
    return traced() ? impl_->values(h, object, true) : std::vector<float>{};
}

void FinalGather::trace(const Solution& s, const Config& c, const std::function<void(double)>& progress) {
    clear();
    Impl& t = *impl_;
    t.config = c;
    t.lights = s.scene.lights();
    std::vector<fg::Job> jobs = t.make_jobs(s);
    t.run(s, c, jobs, nullptr, progress);
}

void FinalGather::retrace(const Solution& s, const Config& c, const Moves& moves,
                          const std::function<void(double)>& progress) {
    if (!traced()) {
        trace(s, c, progress);
        return;
    }
    Impl& t = *impl_;
    const Config& was = t.config;
    const bool same_config = was.rays == c.rays && was.share == c.share && was.min_rays == c.min_rays &&
                             was.light_samples == c.light_samples && was.seed == c.seed &&
                             was.cycles_points == c.cycles_points;
    if (!same_config || moves.moved.size() != s.scene.objects().size()) {
        trace(s, c, progress);
        return;
    }
    Moves m = moves;
    const auto& now = s.scene.lights();
    m.lights_changed = now.size() != t.lights.size();
    for (size_t i = 0; i < now.size() && !m.lights_changed; ++i) m.lights_changed = !now[i].same_light(t.lights[i]);
    t.lights = now;
    std::vector<fg::Job> jobs = t.make_jobs(s);
    t.run(s, c, jobs, &m, progress);
}

double FinalGather::trace_bytes(double points, double records) {
    constexpr double kSamplesPerRecord = 4.0;
    return points * double(sizeof(fg::Point) + 2 * sizeof(int)) +
           records * double(sizeof(fg::Record) + kSamplesPerRecord * sizeof(std::pair<int, float>));
}

size_t FinalGather::Impl::measure_bytes() const {
    size_t b = points.capacity() * sizeof(fg::Point);
    for (const fg::Point& p : points)
        b += (p.samples.capacity() + p.borrow.capacity()) * sizeof(std::pair<int, float>) +
             p.records.capacity() * sizeof(fg::Record) + p.lamp_rays.blocked.capacity() * sizeof(uint64_t);
    for (const auto& v : corner_point) b += v.capacity() * sizeof(int);
    return b;
}

namespace {

// An output corner to place a point at: corner `corner` of its object, at vertex `vertex`,
// the k-th of primitive `prim`; its sample point x and the leaf across the contact it lies
// on (fg::corner_covered; -1: none).
struct Corner {
    int prim, k, corner, vertex;
    Vec3 x;
    int beyond;
};

// Every output corner once (an n-gon's corner is in several fan pieces: Cycles bakes it in
// the first triangle that holds it, here the first piece), with its sample point and contact
// state; `touched` gets, per object with output, per vertex, whether a corner of it lies on a
// contact. Corners whose colour is not read (ObjectDesc::written) count for `touched` (so a
// read corner shares a point as it would were every corner read) but get no entry.
std::vector<Corner> output_corners(const fg::Solution& s, bool cycles_points, std::vector<std::vector<char>>& touched) {
    const Hierarchy& h = s.h;
    const auto& objects = s.scene.objects();
    std::vector<Corner> corners;
    touched.assign(objects.size(), {});
    std::vector<std::vector<char>> seen(objects.size());
    for (size_t pi = 0; pi < h.prims.size(); ++pi) {
        const Primitive& p = h.prims[pi];
        if (p.object < 0 || p.front < 0 || !objects[size_t(p.object)].output) continue;
        const ObjectDesc& o = objects[size_t(p.object)];
        std::vector<char>& done = seen[size_t(p.object)];
        if (done.empty()) {
            done.assign(o.corner_count(), 0);
            touched[size_t(p.object)].assign(o.vertices.size(), 0);
        }
        for (int k = 0; k < p.poly.n; ++k) {
            const int corner = p.corner[size_t(k)];
            if (done[size_t(corner)]) continue;
            done[size_t(corner)] = 1;
            Corner c{int(pi), k, corner, o.corner_verts[size_t(corner)], fg::sample_point(o, p, k, h, cycles_points), -1};
            c.beyond = fg::corner_covered(s, p, c.x);
            if (c.beyond != -1) touched[size_t(p.object)][size_t(c.vertex)] = 1;
            if (o.written(size_t(corner))) corners.push_back(c);
        }
    }
    return corners;
}

}  // namespace

std::vector<fg::Job> FinalGather::Impl::make_jobs(const Solution& s) {
    const Hierarchy& h = s.h;
    const auto& objects = s.scene.objects();
    corner_point.assign(objects.size(), {});
    // An object without output gets no points and no corner map: its corners read the leaves
    // (Solver::corner_radiance), and the counts hold only the corners whose colour is read.
    for (size_t o = 0; o < objects.size(); ++o)
        if (objects[o].output) corner_point[o].assign(objects[o].corner_count(), -1);
    // Every corner's sample point and contact state first: whether its vertex may share a
    // point depends on all of the vertex's corners.
    std::vector<std::vector<char>> touched;  // per object, per vertex: lies on a contact
    const std::vector<Corner> corners = output_corners(s, config.cycles_points, touched);
    std::vector<fg::Job> jobs;
    std::vector<std::vector<std::vector<int>>> at_vertex(objects.size());
    counts.covered = 0;
    for (const Corner& c : corners) {
        const Primitive& p = h.prims[size_t(c.prim)];
        auto& by_vertex = at_vertex[size_t(p.object)];
        if (by_vertex.empty()) by_vertex.resize(objects[size_t(p.object)].vertices.size());
        const int root = h.surfaces[size_t(p.front)].root;
        const Vec3 n = h.nodes[size_t(root)].normal;
        const bool cov = c.beyond != -1;
        int found = -1;
        // A vertex on a contact line (some corner of it covered) shares no point: the side
        // of the contact a corner's sample point lies on decides what it sees (lit, or in the
        // shadow of the object standing there), as it does in Cycles.
        if (fg::kShareVertexPoints && !touched[size_t(p.object)][size_t(c.vertex)])
            for (int j : by_vertex[size_t(c.vertex)])
                if (dot(jobs[size_t(j)].n, n) > 1.0 - 1e-9 && jobs[size_t(j)].covered == cov) { found = j; break; }
        if (found < 0) {
            fg::Job j;
            j.object = p.object;
            j.prim = c.prim;
            j.k = c.k;
            j.x = c.x;
            j.n = n;
            j.leaf = h.leaf_at(root, c.x);
            j.surface = p.front;
            j.covered = cov;
            j.beyond = c.beyond >= 0 ? c.beyond : -1;
            j.seed = Hierarchy::mix(config.seed, Hierarchy::mix(h.nodes[size_t(root)].key, uint64_t(c.k) + 0x6a7u));
            found = int(jobs.size());
            jobs.push_back(j);
            by_vertex[size_t(c.vertex)].push_back(found);
        }
        corner_point[size_t(p.object)][size_t(c.corner)] = found;
        counts.covered += cov;
    }
    // Corners of zero-area faces (no primitive) take a point of their vertex, if any.
    for (size_t o = 0; o < objects.size(); ++o) {
        if (at_vertex[o].empty()) continue;
        for (size_t ci = 0; ci < corner_point[o].size(); ++ci) {
            const auto& at = at_vertex[o][size_t(objects[o].corner_verts[ci])];
            if (corner_point[o][ci] < 0 && !at.empty() && objects[o].written(ci)) corner_point[o][ci] = at.front();
        }
    }
    return jobs;
}

namespace {

// What a run's points add up to, from every thread.
struct Tally {
    std::atomic<int64_t> links{0}, rays{0}, refined{0}, samples{0}, kept{0}, replayed{0}, fresh{0}, near{0}, sealed{0},
        near_rays{0}, lamp_rays{0};
    std::vector<std::atomic<int64_t>> object_rays;
    explicit Tally(size_t objects) : object_rays(objects) {}
    void add(const FinalGather::Counts& local, const fg::Point& pt, bool fresh_point) {
        links += local.links;
        rays += local.rays;
        object_rays[size_t(pt.object)] += local.rays;
        refined += local.refined;
        near += local.near;
        near_rays += local.near_rays;
        lamp_rays += local.lamp_rays;
        sealed += pt.sealed;
        kept += local.kept;
        replayed += local.replayed;
        fresh += fresh_point;
        samples += int64_t(pt.samples.size());
    }
    void store(FinalGather::Counts& k) const {
        k.links = links;
        k.rays = rays;
        k.refined = refined;
        k.samples = samples;
        k.kept = kept;
        k.replayed = replayed;
        k.fresh_points = fresh;
        k.near = near;
        k.near_rays = near_rays;
        k.lamp_rays = lamp_rays;
        k.sealed = sealed;
        k.object_rays.assign(object_rays.size(), 0);
        for (size_t o = 0; o < object_rays.size(); ++o) k.object_rays[o] = object_rays[o];
    }
};

}  // namespace

void FinalGather::Impl::run(const Solution& s, const Config& c, std::vector<fg::Job>& jobs, const Moves* moves,
                            const std::function<void(double)>& progress) {
    preview_state = PreviewState{};
    counts.probe_rays = counts.probes_kept = 0;
    std::vector<fg::Point> old;
    if (moves) old.swap(points);
    fg::Run r{s, c, moves, {}, false};
    r.occluded.build(s.h, s.links);
    auto key_of = [](int object, int prim, int k) { return (uint64_t(uint32_t(object)) << 40) ^ (uint64_t(uint32_t(prim)) << 4) ^ uint64_t(k); };
    std::unordered_map<uint64_t, size_t> old_at;
    old_at.reserve(old.size());
    for (size_t i = 0; i < old.size(); ++i) old_at.emplace(key_of(old[i].object, old[i].prim, old[i].k), i);
    points.assign(jobs.size(), fg::Point{});
    Tally tally(s.scene.objects().size());
    {
        Counts guard;
        r.sealed_rule = c.sealed_solids && s.tri_prim != nullptr && !fg::light_sealed_in(s, guard);
        tally.rays += guard.rays;
    }
    // Per point, the same corner unmoved in the last trace: re-traced from what it had. Also
    // when the update split or merged its leaf: its links are matched one by one (a link at an
    // ancestor or a cluster above still reaches it; what the point's rays met does not depend
    // on which leaf of its surface holds it), and the rest is traced anew. Found by its
    // corner, not its index: points before it may have been added or dropped (a vertex that
    // comes onto a contact line shares no point any more).
    std::vector<fg::Point*> was(jobs.size(), nullptr);
    for (size_t i = 0; i < jobs.size() && moves; ++i) {
        const fg::Job& j = jobs[i];
        const auto at = old_at.find(key_of(j.object, j.prim, j.k));
        if (at == old_at.end()) continue;
        fg::Point& o = old[at->second];
        if (o.object == j.object && o.prim == j.prim && o.k == j.k && o.covered == j.covered &&
            !moves->moved[size_t(j.object)] && o.x.x == j.x.x && o.x.y == j.x.y && o.x.z == j.x.z)
            was[i] = &o;
    }
    tbb::enumerable_thread_specific<fg::Scratch> scratch;
    auto trace_one = [&](size_t idx, bool emitters_only) {
        const fg::Job& j = jobs[idx];
        fg::Point& pt = points[idx];
        pt.object = j.object;
        pt.prim = j.prim;
        pt.k = j.k;
        pt.x = j.x;
        pt.n = j.n;
        pt.seed = j.seed;
        pt.leaf = j.leaf;
        pt.covered = j.covered;
        pt.beyond = j.beyond;
        Counts local;
        fg::trace_point(r, pt, was[idx], local, scratch.local(), emitters_only);
        pt.samples.shrink_to_fit();
        // Each point is traced once: what it kept of its old self is copied, and the old one
        // goes now rather than after the whole trace, so an update never holds both traces.
        if (was[idx]) was[idx]->release();
        tally.add(local, pt, was[idx] == nullptr);
    };
    if (c.share > 0) {
        share_gathers(s, c, jobs, was, moves, counts, trace_one, progress);
        tally.rays += counts.probe_rays;
    } else {
        const size_t block = 512;
        for (size_t b = 0; b < jobs.size(); b += block) {
            if (progress) progress(double(b) / double(jobs.size()));
            const size_t e = std::min(jobs.size(), b + block);
            parallel_for(e - b, c.threads, [&](size_t i) { trace_one(b + i, false); }, 4);
        }
    }
    if (progress) progress(1.0);
    bytes = measure_bytes();
    counts.points = int64_t(jobs.size());
    counts.corners = 0;
    const auto& objects = s.scene.objects();
    for (size_t o = 0; o < corner_point.size(); ++o)
        for (size_t ci = 0; ci < corner_point[o].size(); ++ci) counts.corners += objects[o].written(ci);
    tally.store(counts);
    counts.shared = 0;
    for (const fg::Point& p : points) counts.shared += !p.gathered;
    traced = true;
}

std::vector<float> FinalGather::Impl::values(const Hierarchy& h, int object, bool irradiance) const {
    if (!traced || object < 0 || size_t(object) >= corner_point.size()) return {};
    const std::vector<int>& cp = corner_point[size_t(object)];
    std::vector<float> out(cp.size() * 3, 0.f);
    std::vector<std::pair<bool, Rgb>> bounced;  // lenders' bounced light, each made once
    for (size_t ci = 0; ci < cp.size(); ++ci) {
        if (cp[ci] < 0) continue;  // no face of this vertex has an area: 0
        const Rgb v = point_value(h, points[size_t(cp[ci])], irradiance, Rgb{}, &bounced);
        out[3 * ci] = float(v.r);
        out[3 * ci + 1] = float(v.g);
        out[3 * ci + 2] = float(v.b);
    }
    return out;
}

Rgb FinalGather::Impl::arriving(const Hierarchy& h, const fg::Point& p,
                                std::vector<std::pair<bool, Rgb>>* bounced) const {
    const Node& leaf = h.nodes[size_t(h.live_element(p.leaf))];
    Rgb e;
    if (!p.gathered && !p.sealed) {  // (a sealed one reads nothing, below)
        // A shared point: its own lamps and emitting senders, its lenders' bounced light.
        e = fg::emitted_part(h, p);
        for (const auto& [q, w] : p.borrow) {
            if (bounced && bounced->empty()) bounced->assign(points.size(), {false, Rgb{}});
            if (bounced && !(*bounced)[size_t(q)].first) (*bounced)[size_t(q)] = {true, bounced_part(h, points[size_t(q)])};
            e += (bounced ? (*bounced)[size_t(q)].second : bounced_part(h, points[size_t(q)])) * double(w);
        }
    } else if (!p.covered) {
        Rgb own, all;
        for (const fg::Record& r : p.records) {
            const Rgb g = fg::record_light(h, p, r);
            all += g;
            if (r.own) own += g;
        }
        all += p.near;
        e = p.direct + closure_gathered(own, all, p.c_own, p.c_inherited, p.fill, leaf.L);
    } else {
        e = p.beyond >= 0 ? h.nodes[size_t(h.live_element(p.beyond))].L : Rgb{};
    }
    return e;
}

Rgb FinalGather::Impl::shown_value(const Hierarchy& h, const fg::Point& p, const Rgb& e, bool irradiance) {
    // Irradiance is not negative: differences (a shared point's lenders' bounced light, a near
    // field's correction) may round a dark point below 0 by ~1e-11.
    const Rgb c = cmax(e, Rgb{});
    if (irradiance) return c;
    const Node& leaf = h.nodes[size_t(h.live_element(p.leaf))];
    return leaf.emission + leaf.rho * c;
}

}  // namespace radiosity
