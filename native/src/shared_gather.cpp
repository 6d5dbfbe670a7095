// Shared gathers (FinalGather::Config::share): the output's bounced light gathered at some
// points and taken by the points near them, as an irradiance cache does (Ward, Rubinstein
// and Clear, 1988). A gathered point lends within share x R, R its distance to the nearest
// surface it sees: bounced light changes over distances like that one, so a floor point 2 m
// from anything lends to a wide disc and one beside a box's foot to nobody. Normals must
// agree as well (the error term adds sqrt(1 - n.n')). What changes over shorter distances
// still comes to every point itself: its lamps and its emitting senders (a lamp's shadow
// edge crosses a floor wherever the occluder is).
//
// Which points gather is decided level by level, coarse to fine, the same way in a trace and
// in a retrace: at each level every open point first takes what the last level's gathered
// points lend it, then one open point per grid cell (of each object and normal direction)
// gathers; the cells halve each level, and at the last one every open point gathers.
#include <algorithm>
#include <array>
#include <atomic>
#include <limits>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <tbb/enumerable_thread_specific.h>

#include "final_gather_trace.h"
#include "radiosity/parallel.h"
#include "radiosity/random.h"

namespace radiosity {
namespace fg {
namespace {

// A cell of a uniform grid of one object: (object, size level or facing, ix, iy, iz).
struct CellKey {
    int object, level;
    int64_t ix, iy, iz;
    bool operator==(const CellKey& o) const {
        return object == o.object && level == o.level && ix == o.ix && iy == o.iy && iz == o.iz;
    }
};
struct CellHash {
    size_t operator()(const CellKey& k) const {
        uint64_t v = Hierarchy::mix(uint64_t(uint32_t(k.object)), uint64_t(uint32_t(k.level)));
        v = Hierarchy::mix(v, uint64_t(k.ix));
        v = Hierarchy::mix(v, uint64_t(k.iy));
        return size_t(Hierarchy::mix(v, uint64_t(k.iz)));
    }
};

// The cell of a grid of cells `size` wide that holds x.
CellKey cell_of(int object, int level, const Vec3& x, double size) {
    return {object, level, int64_t(std::floor(x.x / size)), int64_t(std::floor(x.y / size)), int64_t(std::floor(x.z / size))};
}

// Ward's error term of a lender at p (normal pn, reach R) for a point at x (normal n).
double error_term(const Vec3& x, const Vec3& n, const Vec3& p, const Vec3& pn, double R) {
    return length(x - p) / R + std::sqrt(std::max(0.0, 1.0 - dot(n, pn)));
}

// The dominant axis and sign of a normal: points of one cell that face different ways (a
// box's corner) are not one another's neighbours.
int facing(const Vec3& n) {
    const double ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
    if (ax >= ay && ax >= az) return n.x >= 0 ? 0 : 1;
    if (ay >= az) return n.y >= 0 ? 2 : 3;
    return n.z >= 0 ? 4 : 5;
}

// probe_reach's rays from x (normal n): from x lifted off its surface, `full` long, along the
// directions of a 4 x 4 grid of cosine strata drawn from `seed` in order (fixed by the seed:
// a retrace draws them again to see which a move can change).
struct ProbeRays {
    ProbeRays(double diag, const Vec3& x, const Vec3& n, uint64_t seed)
        : o(x + n * (1e-6 * diag)), full(2.0 * diag), strata(n, 4), rng(seed) {}
    Vec3 direction(int i) { return strata.direction(i, rng); }
    Vec3 o;
    double full;
    CosineStrata strata;
    Rng rng;
};
static_assert(sizeof(Point::probe_ends) == 16, "a probe end per probe ray");

// Where a probe ray ended (t from its origin, of `full`), as a byte rounded up: 255 a miss (the
// ray's full length), else 2^((code - 254) / 16) of the full length, at most 4.4 % beyond the
// hit and never short of it (a hair beyond, so that a box the hit point lies on counts as met).
uint8_t probe_end(double t, double full) {
    const double c = std::ceil(16.0 * std::log2(t * (1 + 1e-9) / full)) + 254;
    return uint8_t(std::clamp(c, 0.0, 254.0));
}
double probe_length(uint8_t end, double full) { return end >= 254 ? full : full * std::exp2((int(end) - 254) / 16.0); }

// The harmonic mean distance of what a point's own hemisphere sees, by a few cosine rays
// (misses count as infinitely far): a point may lie beside an occluder its would-be lender
// 1 cm away does not see (a chair leg's foot), and then shares with nobody. `ends` gets where
// each ray ended (probe_end).
double probe_reach(const Solution& s, const Vec3& x, const Vec3& n, uint64_t seed, std::array<uint8_t, 16>& ends,
                   int64_t& rays) {
    const double diag = s.h.scene_diag;
    ProbeRays pr(diag, x, n, seed);
    double inv = 0;
    for (int i = 0; i < pr.strata.count(); ++i) {
        const Vec3 d = pr.direction(i);
        Vec3 at;
        ++rays;
        ends[size_t(i)] = 255;
        if (s.vis.hit_object(pr.o, pr.o + d * pr.full, 0.0, &at) < 0) continue;
        ends[size_t(i)] = probe_end(length(at - pr.o), pr.full);
        inv += 1.0 / std::max(length(at - pr.o), 1e-9 * diag);
    }
    return inv > 0 ? pr.strata.count() / inv : std::numeric_limits<double>::infinity();
}

// Whether a retrace may keep a point's probe as its last trace (`old`) made it: the same point
// (unmoved: same place, normal and seed, so the same rays), and no probe ray meets a moved
// object's old or new box between its origin and where it ended. Outside those boxes the
// geometry is as it was, so such a ray meets what it met, at the same distance.
bool probe_holds(const Solution& s, const Job& j, const Point& old, const Moves& moves) {
    if (!(old.probed >= 0) || moves.cast_all || old.seed != j.seed || old.n.x != j.n.x || old.n.y != j.n.y ||
        old.n.z != j.n.z)
        return false;
    Aabb all;
    for (const Aabb& c : moves.clips) all.grow(c);
    ProbeRays pr(s.h.scene_diag, j.x, j.n, Hierarchy::mix(j.seed, 0x9b0eu));
    // Every ray ends within the longest one's reach of the origin: with the boxes farther
    // away, none can meet them, and the directions need not be drawn.
    const uint8_t longest = *std::max_element(old.probe_ends.begin(), old.probe_ends.end());
    if (distance_to_box(all, pr.o) > probe_length(longest, pr.full) * (1 + 1e-9)) return true;
    for (int i = 0; i < pr.strata.count(); ++i) {
        const Vec3 d = pr.direction(i);
        const Vec3 end = pr.o + d * probe_length(old.probe_ends[size_t(i)], pr.full);
        if (all.meets_segment(pr.o, end) && meets_any(moves.clips, pr.o, end)) return false;
    }
    return true;
}

// Per vertex of a mesh, whether it lies on an open edge (an edge of one polygon only). The
// surface ends there and its light changes toward the end faster than the distance to what it
// sees says (a Cornell box's ceiling at its open front, darker than just inside it): such
// points neither lend nor borrow (bench/results/interior_native.md, "Open edges").
std::vector<char> open_edge_vertices(const ObjectDesc& o) {
    std::vector<char> open(o.vertices.size(), 0);
    std::unordered_map<uint64_t, int> uses;
    uses.reserve(o.corner_count());
    auto key = [](int32_t a, int32_t b) { return (uint64_t(uint32_t(std::min(a, b))) << 32) | uint32_t(std::max(a, b)); };
    for (size_t f = 0; f < o.polygon_count(); ++f)
        for (int32_t k = 0; k < o.loop_totals[f]; ++k) {
            const int32_t c0 = o.loop_starts[f] + k, c1 = o.loop_starts[f] + (k + 1) % o.loop_totals[f];
            ++uses[key(o.corner_verts[size_t(c0)], o.corner_verts[size_t(c1)])];
        }
    for (const auto& [e, count] : uses)
        if (count == 1) open[size_t(e >> 32)] = open[size_t(e & 0xffffffffu)] = 1;
    return open;
}

// Per point to trace, whether its corner's vertex lies on an open edge.
std::vector<char> open_edge_points(const Solution& s, const std::vector<Job>& jobs) {
    std::vector<char> open_edge(jobs.size(), 0);
    std::vector<std::vector<char>> open(s.scene.objects().size());
    for (size_t i = 0; i < jobs.size(); ++i) {
        const Job& j = jobs[i];
        const ObjectDesc& o = s.scene.objects()[size_t(j.object)];
        if (open[size_t(j.object)].empty()) open[size_t(j.object)] = open_edge_vertices(o);
        open_edge[i] = open[size_t(j.object)][size_t(o.corner_verts[size_t(s.h.prims[size_t(j.prim)].corner[size_t(j.k)])])];
    }
    return open_edge;
}

// The gathered points that lend, each in the cell of the grid level matching its lending
// radius (share x reach, cells from `base` up); `levels_used` gets a bit per level used. Most
// cells a point asks for hold no lender: a bit per hash of the cells that do (a table that
// stays in cache) answers those without a look into the map.
struct LenderGrid {
    std::unordered_map<CellKey, std::vector<int>, CellHash> cells;
    std::vector<uint64_t> held;  // bit (hash mod held.size() * 64) set: that cell may hold lenders
    const std::vector<int>* find(const CellKey& k) const {
        const size_t b = CellHash{}(k) % (held.size() * 64);
        if (!((held[b >> 6] >> (b & 63)) & 1)) return nullptr;
        const auto it = cells.find(k);
        return it == cells.end() ? nullptr : &it->second;
    }
};
LenderGrid lender_grid(const std::vector<Point>& points, const std::vector<size_t>& lenders,
                       const std::vector<char>& open_edge, double share, double base, uint64_t& levels_used) {
    LenderGrid grid;
    levels_used = 0;
    for (size_t i : lenders) {
        const Point& p = points[i];
        const double r = share * double(p.reach);
        if (!(r > 0) || open_edge[i]) continue;
        const int l = std::clamp(int(std::ceil(std::log2(r / base))), 0, 63);
        const double size = base * std::ldexp(1.0, l);
        grid.cells[cell_of(p.object, l, p.x, size)].push_back(int(i));
        levels_used |= uint64_t(1) << l;
    }
    grid.held.assign(std::max<size_t>(64, (grid.cells.size() * 16 + 63) / 64), 0);  // ~16 bits a cell
    for (const auto& c : grid.cells) {
        const size_t b = CellHash{}(c.first) % (grid.held.size() * 64);
        grid.held[b >> 6] |= uint64_t(1) << (b & 63);
    }
    return grid;
}

// Point pt's own reach (job j's), probed when first asked: kept from its last trace (`old`)
// where probe_holds, else cast (its rays counted in `rays`, a probe kept in `kept`).
double own_reach(const Solution& s, const Job& j, Point& pt, const Point* old, const Moves* moves,
                 std::atomic<int64_t>& rays, std::atomic<int64_t>& kept) {
    if (pt.probed >= 0) return pt.probed;
    if (moves && old && probe_holds(s, j, *old, *moves)) {
        pt.probed = old->probed;
        pt.probe_ends = old->probe_ends;
        ++kept;
    } else {
        int64_t r = 0;
        pt.probed = probe_reach(s, j.x, j.n, Hierarchy::mix(j.seed, 0x9b0eu), pt.probe_ends, r);
        rays += r;
    }
    return pt.probed;
}

// The lenders of the grid whose reach holds point j (within share, on its tangent plane, and
// within j's own reach, `own_reach()`, asked only when some lender is near), the nearest few
// weighted to sum to 1 in `borrow`; false when there is none. `found` is scratch.
template <class OwnReach>
bool find_lenders(const std::vector<Point>& points, const LenderGrid& grid, uint64_t levels_used, double base, double a,
                  const Job& j, const OwnReach& own_reach, std::vector<std::pair<int, double>>& found,
                  std::vector<std::pair<int, float>>& borrow) {
    constexpr size_t kMaxLenders = 8;
    found.clear();
    for (int l = 0; l < 64; ++l) {
        if (!((levels_used >> l) & 1)) continue;
        const CellKey at = cell_of(j.object, l, j.x, base * std::ldexp(1.0, l));
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    const std::vector<int>* cell = grid.find({j.object, l, at.ix + dx, at.iy + dy, at.iz + dz});
                    if (!cell) continue;
                    for (int q : *cell) {
                        const Point& p = points[size_t(q)];
                        const Vec3 d = j.x - p.x;
                        // (Not across a step: both on one tangent plane, within a tenth of
                        // their distance.)
                        if (error_term(j.x, j.n, p.x, p.n, double(p.reach)) < a && std::fabs(dot(d, p.n)) <= 0.1 * length(d))
                            found.push_back({q, 0.0});
                    }
                }
    }
    if (found.empty()) return false;
    const double probed = own_reach();
    // Each lender again, within the point's own reach as well.
    size_t m = 0;
    for (const auto& f : found) {
        const Point& p = points[size_t(f.first)];
        const double e = error_term(j.x, j.n, p.x, p.n, std::min(double(p.reach), probed));
        if (e < a) found[m++] = {f.first, 1.0 / std::max(e, 1e-9) - 1.0 / a};
    }
    found.resize(m);
    if (found.empty()) return false;
    // The nearest few (by weight, ties by index: the same choice in every run).
    std::sort(found.begin(), found.end(), [](const auto& u, const auto& v) {
        return u.second != v.second ? u.second > v.second : u.first < v.first;
    });
    if (found.size() > kMaxLenders) found.resize(kMaxLenders);
    double W = 0;
    for (const auto& f : found) W += f.second;
    if (!(W > 0)) return false;
    borrow.clear();
    for (const auto& f : found) borrow.push_back({f.first, float(f.second / W)});
    return true;
}

}  // namespace

float lend_reach(const Point& pt, double dark) {
    if (pt.covered || pt.sealed) return 0.f;
    double F = 0, inv = 0;
    for (const Record& r : pt.records)
        if (r.inv_dist > 0) F += double(r.F), inv += double(r.inv_dist);
    const double R = std::min(inv > 0 ? F / inv : 0.0, dark);
    return std::isfinite(R) ? float(R) : 0.f;
}

Rgb emitted_part(const Hierarchy& h, const Point& p) {
    Rgb e = p.direct;
    for (const Record& r : p.records) {
        if (r.emits) e += record_light(h, p, r) * (r.own ? p.c_own : p.c_inherited);
    }
    return e;
}

}  // namespace fg

void FinalGather::Impl::share_gathers(const Solution& s, const Config& c, const std::vector<fg::Job>& jobs,
                                      const std::vector<fg::Point*>& old, const Moves* moves, Counts& counts,
                                      const std::function<void(size_t, bool)>& trace,
                                      const std::function<void(double)>& progress) {
    const Hierarchy& h = s.h;
    const size_t n = jobs.size();
    enum : char { kOpen = 0, kGathered = 1, kShared = 2 };
    std::vector<char> state(n, kOpen);
    const std::vector<char> open_edge = fg::open_edge_points(s, jobs);
    std::atomic<int64_t> probe_rays{0}, probes_kept{0};
    auto own_reach = [&](size_t i) { return fg::own_reach(s, jobs[i], points[i], old[i], moves, probe_rays, probes_kept); };
    size_t done = 0;
    auto trace_all = [&](const std::vector<size_t>& batch, bool emitters_only) {
        const size_t block = 512;
        for (size_t b = 0; b < batch.size(); b += block) {
            if (progress) progress(double(done) / double(std::max<size_t>(n, 1)));
            const size_t e = std::min(batch.size(), b + block);
            parallel_for(e - b, c.threads, [&](size_t i) { trace(batch[b + i], emitters_only); }, 4);
            done += e - b;
        }
    };
    // Covered points read what lies beyond their contact, no links: gathered, lending nothing.
    std::vector<size_t> batch;
    for (size_t i = 0; i < n; ++i)
        if (jobs[i].covered) batch.push_back(i), state[i] = kGathered;
    trace_all(batch, false);

    const double a = c.share;
    const double diag = h.scene_diag > 0 ? h.scene_diag : 1.0;
    const double base = 1e-6 * diag;  // the finest lending grid's cell
    constexpr int kLevels = 12;       // cells from 1/16 of the scene down to 1/65536
    tbb::enumerable_thread_specific<std::vector<std::pair<int, double>>> found;  // find_lenders' scratch
    std::vector<size_t> lenders;
    double cell = diag / 16.0;
    for (int level = 0; level <= kLevels; ++level) {
        // 1. Open points take what the last level's gathered points lend them.
        if (!lenders.empty()) {
            uint64_t levels_used = 0;
            const fg::LenderGrid grid = fg::lender_grid(points, lenders, open_edge, a, base, levels_used);
            batch.clear();
            for (size_t i = 0; i < n; ++i)
                if (state[i] == kOpen && !open_edge[i]) batch.push_back(i);
            parallel_for(batch.size(), c.threads, [&](size_t k) {
                const size_t i = batch[k];
                if (fg::find_lenders(points, grid, levels_used, base, a, jobs[i], [&] { return own_reach(i); },
                                     found.local(), points[i].borrow))
                    state[i] = kShared;
            }, 64);
        }
        // 2. One open point per cell gathers (all of them at the last level).
        batch.clear();
        if (level == kLevels) {
            for (size_t i = 0; i < n; ++i)
                if (state[i] == kOpen) batch.push_back(i);
        } else {
            std::unordered_map<fg::CellKey, size_t, fg::CellHash> first;
            for (size_t i = 0; i < n; ++i) {
                if (state[i] != kOpen) continue;
                const fg::Job& j = jobs[i];
                first.emplace(fg::cell_of(j.object, fg::facing(j.n), j.x, cell), i);
            }
            for (const auto& f : first) batch.push_back(f.second);
            std::sort(batch.begin(), batch.end());
        }
        for (size_t i : batch) state[i] = kGathered;
        trace_all(batch, false);
        lenders = batch;
        cell *= 0.5;
    }
    // The shared points' own lamps and emitting senders.
    batch.clear();
    for (size_t i = 0; i < n; ++i)
        if (state[i] == kShared) batch.push_back(i);
    trace_all(batch, true);
    counts.probe_rays += probe_rays;
    counts.probes_kept += probes_kept;
}

Rgb FinalGather::Impl::bounced_part(const Hierarchy& h, const fg::Point& p) const {
    return point_value(h, p, true) - fg::emitted_part(h, p);
}

}  // namespace radiosity
