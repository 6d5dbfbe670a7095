// MemoryBudget (memory_budget.h): what a solve holds in memory and the final gather's share of
// it before the gather runs, so refinement stops at the limit with room left for the output.
#include "radiosity/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_set>
#include <utility>
#include <vector>

#include "radiosity/held_bytes.h"

namespace radiosity {

MemoryBudget::MemoryBudget(double max_memory_mb) {
    limit_ = max_memory_mb * 1048576.0;
    if (limit_ <= 0) {
        const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
        limit_ = pages > 0 && page > 0 ? 0.5 * double(pages) * double(page) : 4.0 * 1073741824.0;
    }
}

double MemoryBudget::estimate(const MemoryView& v, size_t more_links, size_t more_nodes) const {
    // Per node its index lists (children, in and out links), per link its visibility samples
    // (cluster senders and subdivided ones), on average.
    const double node_lists = 4.0 * sizeof(int);
    const double link_samples = 2.0 * sizeof(int) + 0.5 * v.settings.rays_per_link * sizeof(std::pair<int, float>);
    double b = v.h.nodes.bytes(more_nodes) +
               double(v.h.nodes.size() + more_nodes) * node_lists +
               v.links.bytes(more_links) +
               double(v.links.size() + more_links) * link_samples;
    if (v.vis) b += double(std::max<int64_t>(0, v.vis->bytes()));
    b += tables_bytes_ + v.gathering.bytes(v.links.size() + more_links, v.h.nodes.size() + more_nodes);
    b += v.direct_light.bytes(v.scene, v.settings.rays_per_link);
    if (v.output.traced()) {
        b += double(v.output.bytes());
    } else if (output_forecast_ > 0) {
        // The forecast grows with the links that reach the output points (before the first
        // links, it holds the points alone).
        const double now = double(v.links.live() + int64_t(more_links));
        const double grown = output_forecast_links_ > 0 ? now / double(output_forecast_links_) : 1.0;
        b += output_forecast_ * std::max(1.0, grown);
    }
    return b;
}

void MemoryBudget::measure_tables(const MemoryView& v) {
    double b = v.h.tables_bytes() + held_bytes(v.tri_prim) + held_bytes(v.pockets.records());
    for (const ObjectDesc& o : v.scene.objects()) b += o.bytes();
    tables_bytes_ = b;
}

namespace {
// The output's forecast is made again once there are this many links, then at each doubling.
constexpr int64_t kForecastLinks = 10000;
}  // namespace

// The forecast follows the links as refinement makes them, and wave by wave near the memory
// cap. Once the output is traced the estimate counts the trace itself: a forecast, which reads
// every link and corner of the scene, would be work for nothing.
void MemoryBudget::follow_forecast(const MemoryView& v) {
    if (!v.output.traced() &&
        (v.links.live() >= std::max<int64_t>(kForecastLinks, 2 * output_forecast_links_) ||
         estimate(v) > 0.5 * limit_))
        forecast_output(v);
}

void MemoryBudget::forecast_output(const MemoryView& v) {
    output_forecast_ = 0;
    output_forecast_links_ = v.links.live();
    if (v.settings.gather_rays <= 0) return;
    // Per node, the links into it a point below reads (final_gather.cpp links_reaching):
    // active ones and fully occluded ones kept for a move.
    std::vector<int32_t> into(v.h.nodes.size(), 0);
    for (const Link& l : v.links)
        if (!l.dead && (l.active || l.occluded) && size_t(l.rcv) < into.size()) ++into[size_t(l.rcv)];
    // ... and per leaf all it reads: at it, at its element ancestors and at the clusters above
    // its surface.
    std::vector<int32_t> reach(v.h.nodes.size(), -1);
    std::vector<int32_t> above(v.h.surfaces.size(), -1);
    std::vector<int> chain;
    auto reach_of = [&](int id) {
        chain.clear();
        int k = id;
        for (; k >= 0 && !v.h.nodes[size_t(k)].is_cluster() && reach[size_t(k)] < 0; k = v.h.nodes[size_t(k)].parent)
            chain.push_back(k);
        int32_t r = 0;
        if (k >= 0 && !v.h.nodes[size_t(k)].is_cluster()) {
            r = reach[size_t(k)];
        } else {
            const int sf = v.h.nodes[size_t(id)].surface;
            if (sf >= 0 && above[size_t(sf)] < 0) {
                int32_t a = 0;
                for (int c : v.h.ancestors_of_surface(sf)) a += into[size_t(c)];
                above[size_t(sf)] = a;
            }
            r = sf >= 0 ? above[size_t(sf)] : 0;
        }
        for (auto it = chain.rbegin(); it != chain.rend(); ++it) reach[size_t(*it)] = r += into[size_t(*it)];
        return reach[size_t(id)];
    };
    // One point per written vertex and normal (the corners of a vertex in one plane share it).
    const auto& objects = v.scene.objects();
    std::unordered_set<uint64_t> made;
    std::vector<std::vector<char>> done(objects.size());  // per corner: an n-gon's is in several pieces
    auto q = [](double c) { return uint64_t(int64_t(std::llround(c * 1e6))); };
    double points = 0, records = 0;
    for (const Primitive& p : v.h.prims) {
        if (p.object < 0 || p.front < 0 || !objects[size_t(p.object)].output) continue;
        const ObjectDesc& o = objects[size_t(p.object)];
        const int root = v.h.surfaces[size_t(p.front)].root;
        const Node& r = v.h.nodes[size_t(root)];
        if (r.dead) continue;
        const uint64_t facing = Hierarchy::mix(Hierarchy::mix(q(r.normal.x), q(r.normal.y)), q(r.normal.z));
        std::vector<char>& first = done[size_t(p.object)];
        if (first.empty()) first.assign(o.corner_count(), 0);
        for (int k = 0; k < p.poly.n; ++k) {
            const int corner = p.corner[size_t(k)];
            if (first[size_t(corner)] || !o.written(size_t(corner))) continue;
            first[size_t(corner)] = 1;
            const int vert = o.corner_verts[size_t(corner)];
            if (!made.insert(Hierarchy::mix(Hierarchy::mix(uint64_t(p.object), uint64_t(vert)), facing)).second) continue;
            const int leaf = v.h.leaf_at(root, p.poly.v[size_t(k)]);
            points += 1;
            records += leaf >= 0 ? reach_of(leaf) : 0;
        }
    }
    output_forecast_ = FinalGather::trace_bytes(points, records);
}

}  // namespace radiosity
