// The live drag's preview: while the user drags an object, each step must show something
// within a tenth of a second, and a real update takes seconds. What the eye follows during a
// drag is the direct light -- the shadow the object casts and the light on its own faces --
// so a step re-traces only that, from the output's own trace: the lamps' shadow rays and the
// transfers from emitting senders of the points a moved box can touch, and of the moved
// objects' points carried with them. Bounced light stays as solved until the drag pauses and
// the update runs. FinalGather's part of a step is here (it reads the trace, never changes
// it); the solver's (placing the dragged objects, LiveDrag) is solver_preview.cpp.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <utility>

#include <tbb/enumerable_thread_specific.h>

#include "final_gather_trace.h"
#include "preview_order.h"
#include "radiosity/lights.h"
#include "radiosity/parallel.h"
#include "radiosity/final_gather.h"
#include "radiosity/transfer.h"

namespace radiosity {

namespace {

// The lists one thread reuses from point to point in a preview.
struct PreviewScratch {
    std::vector<std::pair<int, float>> fresh, samples;
    std::vector<std::pair<int, bool>> reaching;
    std::vector<std::pair<int, double>> use;
    LampRays lamp_rays;
};

// Irradiance / pi at a point gathered afresh from the active links reaching its leaf and the
// lamps, without retraces, closure or near field (a footprint uncovered).
Rgb fresh_irradiance(const FinalGather::Solution& s, const FinalGather::Config& config, const fg::Point& pt,
                     const Vec3& x, const Vec3& n, PreviewScratch& scratch, int64_t& rays) {
    // The links reaching the point's leaf (links_reaching), each from the point (at x, facing
    // n: where the drag has it) as trace_point does, without its shadow-edge retraces, closure
    // and near field (a preview's approximation), budgets shared by the light they bring.
    const Hierarchy& h = s.h;
    const int leaf = h.live_element(pt.leaf);
    std::vector<std::pair<int, bool>>& reaching = scratch.reaching;
    std::vector<std::pair<int, double>>& use = scratch.use;
    fg::links_reaching(s, nullptr, leaf, reaching);
    use.clear();
    double total = 0;
    for (const auto& link_own : reaching) {
        const Link& l = s.links[size_t(link_own.first)];
        const Node& src = h.nodes[size_t(l.src)];
        const double w = l.K_unoccluded * std::max(src.Lmax.max(), src.L.max());
        if (!(w > 0)) continue;
        use.emplace_back(link_own.first, w);
        total += w;
    }
    const PointLight lamp = direct_light_at(s.scene, h, s.vis, x, n, false, config.light_samples, pt.seed);
    rays += lamp.rays;
    Rgb E = lamp.E;
    // A quarter of the trace's budget, one ray for the faint: a preview of a footprint, seen
    // while it moves.
    const int budget = std::max(config.rays / 4, config.min_rays);
    std::vector<std::pair<int, float>>& samples = scratch.samples;
    for (const auto& [li, w] : use) {
        const Link& l = s.links[size_t(li)];
        samples.clear();
        PointRayStream rs(s.vis);
        point_transfer(h, rs, l.src, x, n, leaf, fg::ray_share(budget, w, total, 1, budget),
                       fg::transfer_seed(h, pt.seed, l.src), samples);
        for (const auto& [node, sw] : samples) E += h.nodes[size_t(h.live_element(node))].L * double(sw);
        rays += rs.cast;
    }
    return E;
}

// Irradiance / pi at x (facing n) of a dragged object's face lifted off what it stood on in
// the bake: it has no links of its own to gather there (nothing faced it), so it reads the
// solution's leaves where cosine-distributed rays from it land, and its lamps.
Rgb hemisphere_irradiance(const FinalGather::Solution& s, const FinalGather::Config& config, const fg::Point& pt,
                          const Vec3& x, const Vec3& n, int64_t& rays) {
    const Hierarchy& h = s.h;
    const PointLight lamp = direct_light_at(s.scene, h, s.vis, x, n, false, config.light_samples, pt.seed);
    rays += lamp.rays;
    Rgb E = lamp.E;
    if (!s.tri_prim) return E;
    const double far = 4.0 * h.scene_diag, lift = 1e-5 * h.scene_diag;
    Rng rng(Hierarchy::mix(pt.seed, 0x11f7edu));
    const CosineStrata strata(n, 6);
    const Vec3 o = x + n * lift;
    Rgb sum;
    for (int i = 0; i < strata.count(); ++i) {
        const Vec3 d = strata.direction(i, rng);
        ++rays;
        Vec3 at;
        const int prim = s.prim_hit(o, o + d * far, at);
        if (prim < 0) continue;
        const int side = h.side_met(prim, d);
        if (side >= 0) sum += h.nodes[size_t(h.leaf_at(h.surfaces[size_t(side)].root, at))].L;
    }
    return E + sum / double(strata.count());
}

// Adds to dE the change of what the point's emitting senders (`emits`, per node) bring it at
// its new place (x, n): each transfer whose rays may meet a moved box, or every one when the
// point or the sender moved, traced again. Returns the transfers re-traced.
int64_t add_emitter_changes(const FinalGather::Solution& s, const FinalGather::Preview& p,
                            const FinalGather::Config& config, const fg::Point& pt, const Vec3& x, const Vec3& n,
                            bool moved, const std::vector<char>& emits, std::vector<std::pair<int, float>>& fresh, Rgb& dE,
                            int64_t& rays) {
    const Hierarchy& h = s.h;
    int64_t transfers = 0;
    for (const fg::Record& r : pt.records) {
        if (!emits[size_t(r.src)]) continue;
        const Node& src = h.nodes[size_t(r.src)];
        // (The hierarchy has the moved objects at their new places: a sender in one, or a
        // cluster holding one, draws other rays now; none replays a recorded outcome.)
        const bool src_moved = (src.object >= 0 && size_t(src.object) < p.moved.size() && p.moved[size_t(src.object)]) ||
                               std::binary_search(p.moved_nodes.begin(), p.moved_nodes.end(), r.src);
        if (!moved && !src_moved && !hull_meets(x, src.box, p.clips)) continue;
        const Rgb was = fg::record_light(h, pt, r);
        // trace_point's seed for this transfer (a shadow edge's retrace: +1, a deep
        // penumbra's, with more rays than the budget: +2), so that the rays through no moved
        // box are the ones recorded and replay their outcomes.
        const uint64_t seed =
            fg::transfer_seed(h, pt.seed, r.src) + (r.refined ? (int(r.rays) > config.rays ? 2 : 1) : 0);
        fresh.clear();
        const PointRays recorded = r.outcome();
        PointRayStream rs(s.vis, moved || src_moved ? nullptr : &recorded, &p.clips);
        point_transfer(h, rs, r.src, x, n, pt.leaf, int(r.rays), seed, fresh);
        Rgb now;
        for (const auto& [node, w] : fresh) now += h.nodes[size_t(h.live_element(node))].L * double(w);
        // Through the point's closure factors, as values() weighs this record's samples.
        dE += (now - was) * (r.own ? pt.c_own : pt.c_inherited);
        rays += rs.cast;
        ++transfers;
    }
    return transfers;
}

// Per node: it emits, or holds an emitting element below it.
std::vector<char> emitting_senders(const Hierarchy& h) {
    std::vector<char> emits(h.nodes.size(), 0);
    for (size_t i = 0; i < h.nodes.size(); ++i) {
        const Node& m = h.nodes[i];
        if (m.dead || m.is_cluster() || !(m.emission.max() > 0)) continue;
        for (int a = int(i); a >= 0 && !emits[size_t(a)]; a = h.nodes[size_t(a)].parent) emits[size_t(a)] = 1;
    }
    return emits;
}

// One preview step: each relit point's change of irradiance / pi at the new placements (into
// d, per point), whether the dragged object covers it now (unlit), and what the step
// re-traced and cost (work: shadow rays streamed from records, each one cast counting 5).
class PreviewStep {
public:
    PreviewStep(const FinalGather::Solution& s, const FinalGather::Preview& p, const FinalGather::Config& config,
                const std::vector<fg::Point>& points, const std::vector<char>& emits,
                std::function<Rgb(const fg::Point&)> bake_value, std::vector<Rgb>& d, std::vector<char>& unlit)
        : d(d), unlit(unlit), s_(s), p_(p), config_(config), points_(points), emits_(emits),
          bake_value_(std::move(bake_value)) {}
    // Point i's change into d[i] (and unlit[i]); adds what it cost to work().
    void relight(size_t i);
    void tally(FinalGather::PreviewCounts& k) const {
        k.points = n_points_;
        k.lamps = n_lamps_;
        k.transfers = n_transfers_;
        k.rays = n_rays_;
        k.uncovered = n_uncovered_;
        k.covered = n_covered_;
    }
    int64_t work() const { return work_; }
    std::vector<Rgb>& d;
    std::vector<char>& unlit;

private:
    bool footprint(size_t i, const Vec3& x, const Vec3& n, PreviewScratch& sc);
    bool lifted_off(size_t i, const Vec3& x, const Vec3& n);
    const FinalGather::Solution& s_;
    const FinalGather::Preview& p_;
    const FinalGather::Config& config_;
    const std::vector<fg::Point>& points_;
    const std::vector<char>& emits_;
    std::function<Rgb(const fg::Point&)> bake_value_;  // what the bake shows at a point
    tbb::enumerable_thread_specific<PreviewScratch> scratch_;
    std::atomic<int64_t> n_points_{0}, n_lamps_{0}, n_transfers_{0}, n_rays_{0}, n_uncovered_{0}, n_covered_{0},
        work_{0};
};

bool inside_any(const std::vector<Aabb>& boxes, const Vec3& x) {
    for (const Aabb& b : boxes)
        if (b.contains(x)) return true;
    return false;
}

// The footprint the dragged object leaves: a point it covered (unlit, no record of what it
// sees) is gathered afresh, roughly; and one it covers now goes unlit. False: neither.
bool PreviewStep::footprint(size_t i, const Vec3& x, const Vec3& n, PreviewScratch& sc) {
    const fg::Point& pt = points_[i];
    const Hierarchy& h = s_.h;
    const int surface = h.nodes[size_t(h.live_element(pt.leaf))].surface;
    if (pt.covered && inside_any(p_.clips, x) && !p_.covered(surface, x, n)) {
        int64_t rays = 0;
        d[i] = fresh_irradiance(s_, config_, pt, x, n, sc, rays) - bake_value_(pt);
        n_rays_ += rays;
        work_ += 5 * rays;
        ++n_uncovered_;
        ++n_points_;
        return true;
    }
    if (!pt.covered && inside_any(p_.now, x) && p_.covered(surface, x, n)) {
        d[i] = Rgb{} - bake_value_(pt);
        unlit[i] = 1;
        ++n_covered_;
        ++n_points_;
        return true;
    }
    return false;
}

// A dragged object's face lifted off what it stood on (a box's bottom, the corners on its rim
// included): what the bake has there is the contact's dark, so it gathers afresh.
bool PreviewStep::lifted_off(size_t i, const Vec3& x, const Vec3& n) {
    const fg::Point& pt = points_[i];
    const Hierarchy& h = s_.h;
    if (pt.sealed || !p_.lifted(h.nodes[size_t(h.live_element(pt.leaf))].surface, x)) return false;
    int64_t rays = 0;
    d[i] = hemisphere_irradiance(s_, config_, pt, x, n, rays) - bake_value_(pt);
    n_rays_ += rays;
    work_ += 5 * rays;
    ++n_uncovered_;
    ++n_points_;
    return true;
}

void PreviewStep::relight(size_t i) {
    const fg::Point& pt = points_[i];
    PreviewScratch& sc = scratch_.local();
    d[i] = Rgb{};
    unlit[i] = 0;
    if (pt.object < 0 || size_t(pt.object) >= p_.moved.size()) return;
    const bool moved = p_.moved[size_t(pt.object)] != 0;
    const Vec3 x = moved ? p_.carry[size_t(pt.object)].point(pt.x) : pt.x;
    const Vec3 n = moved ? p_.carry[size_t(pt.object)].dir(pt.n) : pt.n;
    if (!moved && p_.covered && footprint(i, x, n, sc)) return;
    if (moved && p_.lifted && lifted_off(i, x, n)) return;
    // (A covered point is sealed too under a closed solid: the footprint's rule comes first.)
    if (pt.covered || pt.sealed) return;
    Rgb dE;
    int64_t rays = 0, streamed = 0;
    bool changed = false;
    if (!s_.scene.lights().empty() && (moved || lamps_meet(s_.scene, s_.h, x, n, p_.clips))) {
        // An unmoved point's shadow rays through neither box keep their recorded outcome; a
        // moved point's are all new, a quarter of them (a preview's approximation, as for a
        // footprint uncovered).
        const int samples = moved ? std::max(4, config_.light_samples / 4) : config_.light_samples;
        const PointLight lamp = direct_light_replay(s_.scene, s_.h, s_.vis, x, n, samples, pt.seed,
                                                    moved ? nullptr : &pt.lamp_rays, &p_.clips, sc.lamp_rays);
        dE += lamp.E - pt.direct;
        rays += lamp.rays;
        streamed += sc.lamp_rays.count;
        ++n_lamps_;
        changed = true;
    }
    const int64_t transfers = add_emitter_changes(s_, p_, config_, pt, x, n, moved, emits_, sc.fresh, dE, rays);
    n_transfers_ += transfers;
    d[i] = dE;
    n_points_ += changed || transfers > 0;
    n_rays_ += rays;
    work_ += streamed + 4 * rays;
}

// A step that stops at `limit` work: the points inside the boxes all, then chunks from the
// dragged objects' points and from the others (nearest first), the side that has had less
// work first, so that the shadow a dragged armchair casts follows it even where its own points
// alone would take all the work. Appends the points relit to `relit`; returns how many of the
// dragged points were.
size_t relight_in_order(PreviewStep& step, PreviewOrder& order, size_t points, int64_t limit, int threads,
                        std::vector<uint32_t>& relit, size_t& deferred) {
    // (Chunks of up to 256 points, a sixteenth of a small scene's: the work is checked
    // between chunks.)
    const size_t chunk = std::clamp<size_t>(points / 16, 16, 256);
    auto run = [&](const uint32_t* first, size_t n) {
        parallel_for(n, threads, [&](size_t j) { step.relight(first[j]); }, 8);
        relit.insert(relit.end(), first, first + n);
    };
    const std::vector<uint32_t>& inside = order.inside();
    for (size_t k = 0; k < inside.size(); k += chunk) run(inside.data() + k, std::min(chunk, inside.size() - k));
    const std::vector<uint32_t>& dragged = order.dragged();
    size_t mv = 0;
    std::vector<uint32_t> next;
    int64_t spent[2] = {step.work(), 0};  // by the others (the boxes' insides too), by the dragged points
    while (step.work() < limit && (mv < dragged.size() || order.others_left() > 0)) {
        const bool drag = mv < dragged.size() && (order.others_left() == 0 || spent[1] <= spent[0]);
        const int64_t before = step.work();
        if (drag) {
            const size_t n = std::min(chunk, dragged.size() - mv);
            run(dragged.data() + mv, n);
            mv += n;
        } else {
            next.clear();
            if (!order.next(chunk, next)) break;
            run(next.data(), next.size());
        }
        spent[drag] += step.work() - before;
    }
    deferred = (dragged.size() - mv) + order.others_left();
    return mv;
}

}  // namespace

std::vector<FinalGather::CornerChange> FinalGather::preview(const Solution& s, const Preview& p,
                                                            PreviewCounts& counts) {
    if (!traced()) return {};
    Impl& t = *impl_;
    const std::vector<fg::Point>& points = t.points;
    Impl::PreviewState& shown = t.preview_state;
    if (shown.moved != p.moved || shown.shown.size() != points.size()) {
        shown.moved = p.moved;
        shown.shown.assign(points.size(), Rgb{});
        shown.unlit.assign(points.size(), 0);
        shown.unlit_points.clear();
        shown.touched.clear();
        shown.is_touched.assign(points.size(), 0);
        shown.turn = 0;
    }
    // Only emitting senders' transfers are re-traced (a dark sender's light is bounced light,
    // left as solved); which they are, and where the points are, is found once per trace.
    if (shown.emits.size() != s.h.nodes.size()) shown.emits = emitting_senders(s.h);
    if (!shown.index) shown.index = std::make_shared<const PointIndex>(points, t.corner_point);
    const PointIndex& index = *shown.index;
    auto bake_value = [&](const fg::Point& pt) { return t.point_value(s.h, pt, true); };
    std::vector<uint32_t> changed;  // the points whose change may be non-zero
    std::vector<Rgb> all;
    const std::vector<Rgb>* d = &shown.shown;
    if (p.work <= 0) {
        all.resize(points.size());
        std::vector<char> unlit(points.size(), 0);
        PreviewStep step(s, p, t.config, points, shown.emits, bake_value, all, unlit);
        parallel_for(points.size(), t.config.threads, [&](size_t i) { step.relight(i); }, 8);
        step.tally(counts);
        for (size_t i = 0; i < points.size(); ++i)
            if (!all[i].is_zero()) changed.push_back(uint32_t(i));
        d = &all;
    } else {
        // The points not relit show what an earlier step of the drag showed.
        PreviewStep step(s, p, t.config, points, shown.emits, bake_value, shown.shown, shown.unlit);
        PreviewOrder order(s, points, index, p, shown.unlit, shown.unlit_points, shown.turn, t.config.threads);
        std::vector<uint32_t> relit;
        size_t deferred = 0;
        shown.turn += relight_in_order(step, order, points.size(), p.work, t.config.threads, relit, deferred);
        step.tally(counts);
        counts.deferred = int64_t(deferred);
        std::vector<uint32_t> unlit_points;
        for (const std::vector<uint32_t>* list : {&shown.unlit_points, &relit})
            for (uint32_t i : *list)
                if (shown.unlit[i]) unlit_points.push_back(i);
        std::sort(unlit_points.begin(), unlit_points.end());
        unlit_points.erase(std::unique(unlit_points.begin(), unlit_points.end()), unlit_points.end());
        shown.unlit_points.swap(unlit_points);
        for (uint32_t i : relit)
            if (!shown.is_touched[i] && !shown.shown[i].is_zero()) {
                shown.is_touched[i] = 1;
                shown.touched.push_back(i);
            }
        changed = shown.touched;
    }
    return t.corner_changes(s.h, changed, *d);
}

std::vector<FinalGather::CornerChange> FinalGather::Impl::corner_changes(const Hierarchy& h,
                                                                         const std::vector<uint32_t>& changed,
                                                                         const std::vector<Rgb>& d) {
    PreviewState& shown = preview_state;
    // What the bake has arriving at a point, made when first asked for.
    if (shown.arriving.size() != points.size()) {
        shown.arriving.assign(points.size(), Rgb{});
        shown.has_arriving.assign(points.size(), 0);
    }
    // Each changed point's values (in parallel: a point's own slots), then its corners in order.
    std::vector<std::pair<Rgb, Rgb>> values(changed.size());
    parallel_for(changed.size(), config.threads, [&](size_t j) {
        const uint32_t i = changed[j];
        if (d[i].is_zero()) return;
        const fg::Point& pt = points[i];
        if (!shown.has_arriving[i]) {
            shown.arriving[i] = arriving(h, pt);
            shown.has_arriving[i] = 1;
        }
        const Rgb e = shown.arriving[i] + d[i];
        values[j] = {shown_value(h, pt, e, true), shown_value(h, pt, e, false)};
    }, 256);
    std::vector<CornerChange> out;
    for (size_t j = 0; j < changed.size(); ++j) {
        const uint32_t i = changed[j];
        if (d[i].is_zero()) continue;
        const auto [first, last] = shown.index->corners(i);
        for (auto c = first; c != last; ++c) out.push_back({c->first, c->second, values[j].first, values[j].second});
    }
    std::sort(out.begin(), out.end(), [](const CornerChange& a, const CornerChange& b) {
        return a.object != b.object ? a.object < b.object : a.corner < b.corner;
    });
    return out;
}

}  // namespace radiosity
