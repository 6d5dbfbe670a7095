// Closed pockets: sets of surfaces that see only each other -- the inside of a closed crate
// together with the outside of a cube lying in it. Light passes only between surfaces of one
// pocket (transfer.cpp, gather_plan.cpp): a cluster link from the room into the crate's cluster
// then neither samples nor lights the crate's inner faces or the cube, which the oracle's
// cosine sharing would otherwise do under its threshold (docs/decisions.md, "Closed pockets").
//
// Which surfaces see which is sampled with escape rays: a surface's rays that hit another
// surface join the two (sight is mutual, so the graph is undirected); the connected
// components are the pockets. A component with a ray that escapes (hit nothing, or the back of
// a one-sided polygon, which lets nothing through) is open: every open surface shares pocket
// 0. A closed room is a closed component too, with everything in it: its furniture's outer
// faces meet its walls' rays, so the room is never cut off from its contents. A closed
// component is confirmed with more rays (all but the largest, the room, whose confirmation
// would cost the most and change nothing): one ray through a gap merges it with what it
// sees, so a false pocket needs every confirmation ray to miss the gap.
#include "radiosity/pockets.h"

#include <cmath>
#include <numeric>

#include "radiosity/parallel.h"
#include "radiosity/random.h"

namespace radiosity {

namespace {

constexpr int kPocketRays = 16;   // per surface
constexpr int kConfirmRays = 64;  // per surface of a closed component that is not the largest

struct DisjointSets {
    std::vector<int> up;
    explicit DisjointSets(size_t n) : up(n) { std::iota(up.begin(), up.end(), 0); }
    int find(int a) {
        while (up[size_t(a)] != a) a = up[size_t(a)] = up[size_t(up[size_t(a)])];
        return a;
    }
    void unite(int a, int b) {
        a = find(a), b = find(b);
        if (a != b) up[size_t(std::max(a, b))] = std::min(a, b);
    }
};

// The pocket each of the first `count` surfaces is in now (0 for a removed one's).
std::vector<int> surface_pockets(const Hierarchy& h, size_t count) {
    std::vector<int> out(count, 0);
    for (size_t s = 0; s < count; ++s)
        if (!h.surface_dead(int(s))) out[s] = h.nodes[size_t(h.surfaces[s].root)].pocket;
    return out;
}

}  // namespace

void Pockets::rays(const Hierarchy& h, const Sight& sight, int s, int count, uint64_t stream, std::vector<Ray>& hits,
                   const std::vector<Aabb>* changed, const std::vector<Ray>* old) const {
    const Node& n = h.nodes[size_t(h.surfaces[size_t(s)].root)];
    const double far = 4.0 * h.scene_diag, lift = 1e-5 * h.scene_diag;
    Rng rng(Hierarchy::mix(sight.settings.seed ^ 0x5EA1ED ^ stream, n.key));
    Vec3 u, v;
    frame(n.normal, u, v);
    const double share = n.poly.first_share();
    for (int r = 0; r < count; ++r) {
        // Cosine-distributed: the directions that carry the most light are tried most.
        const double r1 = rng.next(), r2 = rng.next();
        const Vec3 d = cosine_direction(u, v, n.normal, r1, r2);
        const double s2 = rng.next(), s1 = rng.next();  // named: the order is every compiler's
        const Vec3 o = n.poly.sample(share, s1, s2) + n.normal * lift;
        if (old && size_t(r) < old->size()) {
            // Nothing changed between o and what it hit (or the ray's end): the same hit.
            if (!meets_any(*changed, o, o + d * (*old)[size_t(r)].reach)) {
                hits.push_back((*old)[size_t(r)]);
                continue;
            }
        }
        int tri = -1;
        Vec3 at;
        const int obj = sight.vis.hit_object(o, o + d * far, 0.0, &at, &tri);
        int side = -1;
        if (obj >= 0 && size_t(obj) < sight.tri_prim.size() && !sight.tri_prim[size_t(obj)].empty()) {
            const auto& tp = sight.tri_prim[size_t(obj)];
            side = h.side_met(tp[std::min<size_t>(size_t(std::max(tri, 0)), tp.size() - 1)], d);
        }
        // A hair beyond the hit, so that a box the hit point lies on counts as met.
        hits.push_back({side, obj >= 0 ? length(at - o) * (1 + 1e-9) + lift : far});
    }
}

void Pockets::compute(Hierarchy& h, const Sight& sight, const std::vector<Aabb>* changed, const std::vector<char>* moved) {
    const size_t ns = h.surfaces.size();
    const std::vector<int> was = surface_pockets(h, ns);  // before label() writes the new ones
    std::vector<std::vector<Ray>> hits(ns);
    parallel_for(ns, sight.settings.threads, [&](size_t s) {
        if (h.surface_dead(int(s))) return;
        // A surface that moved casts all its rays again; another keeps those that meet no box
        // where the geometry changed before their hit.
        const int obj = h.nodes[size_t(h.surfaces[s].root)].object;
        const bool keep = changed && moved && s < records_.size() && !(obj >= 0 && size_t(obj) < moved->size() && (*moved)[size_t(obj)]);
        rays(h, sight, int(s), kPocketRays, 0, hits[s], changed, keep ? &records_[s] : nullptr);
    }, 32);
    records_ = hits;  // before confirmation rays replace some
    DisjointSets sets(ns);
    std::vector<char> escaped(ns, 0);
    auto join = [&](const std::vector<size_t>& which) {
        for (size_t s : which)
            for (const Ray& t : hits[s]) {
                if (t.side < 0) escaped[s] = 1;
                else sets.unite(int(s), t.side);
            }
    };
    std::vector<size_t> live;
    for (size_t s = 0; s < ns; ++s)
        if (!h.surface_dead(int(s))) live.push_back(s);
    join(live);
    // Per component (its representative): open, area.
    auto components = [&](std::vector<char>& open, std::vector<double>& area) {
        open.assign(ns, 0);
        area.assign(ns, 0.0);
        for (size_t s : live) {
            const int c = sets.find(int(s));
            open[size_t(c)] |= escaped[s];
            area[size_t(c)] += h.nodes[size_t(h.surfaces[s].root)].area;
        }
    };
    std::vector<char> open;
    std::vector<double> area;
    components(open, area);
    int largest = -1;
    for (size_t s : live)
        if (size_t(sets.find(int(s))) == s && !open[s] && (largest < 0 || area[s] > area[size_t(largest)])) largest = int(s);
    // Confirmation of the smaller closed components; after a move, not of one that was such a
    // pocket before, confirmed, and that no change can reach (kept_confirmed).
    std::vector<int> rep(ns, -1);  // per live surface, its component's representative
    for (size_t s : live) rep[s] = sets.find(int(s));
    const std::vector<char> kept = changed && moved ? kept_confirmed(h, live, rep, open, largest, was, *changed, *moved)
                                                    : std::vector<char>(ns, 0);
    std::vector<size_t> confirm;
    for (size_t s : live) {
        const int c = rep[s];
        if (!open[size_t(c)] && c != largest && !kept[size_t(c)]) confirm.push_back(s);
    }
    if (!confirm.empty()) {
        parallel_for(confirm.size(), sight.settings.threads, [&](size_t k) {
            hits[confirm[k]].clear();
            rays(h, sight, int(confirm[k]), kConfirmRays, 0xC0F1A3, hits[confirm[k]]);
        }, 8);
        join(confirm);
        components(open, area);
    }
    std::vector<int> component(ns, -1);
    for (size_t s : live) component[s] = sets.find(int(s));
    label(h, live, component, open, area);
    unconfirmed_ = largest >= 0 && !open[size_t(largest)] ? largest + 1 : -1;
    h.set_pocket_sets();
    h.refresh_surface_geom();  // the samplers' copy of each surface's pocket
}

std::vector<char> Pockets::kept_confirmed(const Hierarchy& h, const std::vector<size_t>& live, const std::vector<int>& rep,
                                          const std::vector<char>& open, int largest, const std::vector<int>& was,
                                          const std::vector<Aabb>& changed, const std::vector<char>& moved) const {
    // A closed component found again with the same surfaces as a pocket the last compute
    // confirmed: its confirmation rays then all hit its own surfaces, so they stayed in the
    // box of those surfaces. If no surface of it moved and no changed box meets that box,
    // each ray meets what it met: the confirmation stands, without a ray cast.
    const size_t ns = h.surfaces.size();
    std::vector<int> members(ns, 0), old_members(ns + 1, 0), old_label(ns, -1);
    std::vector<char> ok(ns, 1);
    std::vector<Aabb> box(ns);
    for (size_t s : live) {
        const int c = rep[s];
        const Node& n = h.nodes[size_t(h.surfaces[s].root)];
        ++members[size_t(c)];
        if (was[s] > 0 && size_t(was[s]) <= ns) ++old_members[size_t(was[s])];
        if (old_label[size_t(c)] < 0) old_label[size_t(c)] = was[s];
        const bool still = n.object >= 0 && size_t(n.object) < moved.size() && !moved[size_t(n.object)];
        ok[size_t(c)] &= char(still && was[s] == old_label[size_t(c)] && was[s] > 0 && was[s] != unconfirmed_);
        box[size_t(c)].grow(n.box);
    }
    std::vector<char> kept(ns, 0);
    for (size_t s : live) {
        if (rep[s] != int(s) || open[s] || int(s) == largest || !ok[s]) continue;
        if (size_t(old_label[s]) > ns || old_members[size_t(old_label[s])] != members[s]) continue;  // not the same set
        const Aabb b = box[s].grown(2e-5 * h.scene_diag);  // (the rays start lifted off their surfaces)
        bool reached = false;
        for (const Aabb& c : changed) reached = reached || c.overlaps(b);
        kept[s] = !reached;
    }
    return kept;
}

void Pockets::label(Hierarchy& h, const std::vector<size_t>& live, const std::vector<int>& component,
                    const std::vector<char>& open, const std::vector<double>& area) {
    // Labels: 0 for open space, else 1 + the component's smallest surface id (the
    // representative): the same set of surfaces gets the same label after an update.
    double open_area = 0, main_area = -1;
    main_pocket_ = 0;
    for (size_t s : live) {
        const int c = component[s];
        const int label = open[size_t(c)] ? 0 : c + 1;
        if (size_t(c) == s) {
            if (open[s]) open_area += area[s];
            else if (area[s] > main_area) main_area = area[s], main_pocket_ = label;
        }
        std::vector<int> stack{h.surfaces[s].root};  // the element tree below the surface too
        while (!stack.empty()) {
            Node& e = h.nodes[size_t(stack.back())];
            stack.pop_back();
            e.pocket = label;
            stack.insert(stack.end(), e.children.begin(), e.children.end());
        }
    }
    if (open_area >= main_area) main_pocket_ = 0;
    closed_pockets_ = pocket_surfaces_ = 0;
    for (size_t s : live) {
        const int c = component[s];
        if (open[size_t(c)] || c + 1 == main_pocket_) continue;
        closed_pockets_ += size_t(c) == s;
        ++pocket_surfaces_;
    }
}

bool Pockets::reseal(Hierarchy& h, const Sight& sight, size_t known, const std::vector<Aabb>* changed,
                     const std::vector<char>* moved) {
    const std::vector<int> was = surface_pockets(h, known);
    compute(h, sight, changed, moved);
    for (size_t s = 0; s < h.surfaces.size(); ++s) {
        if (h.surface_dead(int(s))) continue;
        const int p = h.nodes[size_t(h.surfaces[s].root)].pocket;
        if (s < known && was[s] != p) return false;
        // A new surface in a closed pocket that holds old ones (an object put into a closed
        // crate), unless that is the scene's main space (furniture added to a closed room).
        if (s >= known && p != 0 && p != main_pocket_ && size_t(p - 1) < known) return false;
    }
    return true;
}

}  // namespace radiosity
