// Per-object cost of a solution (Solver::object_costs): what an update that moves an object
// must compute again, measured on what a solve computed.
#include "radiosity/solver.h"

namespace radiosity {

std::vector<Solver::ObjectCost> Solver::object_costs() const {
    settle_preview();
    std::vector<ObjectCost> c(scene_.objects().size());
    const std::vector<int64_t>& pr = output_.counts().object_rays;
    for (size_t o = 0; o < c.size() && o < pr.size(); ++o) c[o].point_rays = pr[o];
    if (h_.root < 0 || h_.nodes.empty()) return c;  // no hierarchy yet (no solve, or it failed early)
    // Per node: the one object everything below it belongs to (a collection holding one
    // object counts as that object), -1 for clusters of several (or none).
    std::vector<int> sole(h_.nodes.size(), -1);
    std::vector<int> order{h_.root};
    for (size_t i = 0; i < order.size(); ++i)
        for (int ch : h_.nodes[size_t(order[i])].children) order.push_back(ch);
    for (size_t i = order.size(); i-- > 0;) {
        const Node& n = h_.nodes[size_t(order[i])];
        if (n.object >= 0 || n.children.empty()) {
            sole[size_t(order[i])] = n.object;
            continue;
        }
        int o = sole[size_t(n.children[0])];
        for (int ch : n.children)
            if (sole[size_t(ch)] != o) o = -1;
        sole[size_t(order[i])] = o;
    }
    for (const Link& l : links_) {
        if (l.dead) continue;
        const int a = sole[size_t(l.src)], b = sole[size_t(l.rcv)];
        if (a == b) continue;  // inside one object, or between clusters of several
        // The rays of its last evaluation, replayed ones included (the record holds up to 64;
        // without a record -- beyond 64, stale, or dropped after an addition or removal -- the
        // budget).
        const int64_t rays = l.ray_count >= 0 ? l.ray_count : settings_.rays_per_link;
        for (int o : {a, b}) {
            if (o < 0 || size_t(o) >= c.size()) continue;
            if (l.active || l.occluded) {
                ++c[size_t(o)].links;
                c[size_t(o)].link_rays += rays;
            } else {
                ++c[size_t(o)].history_links;
                c[size_t(o)].history_link_rays += rays;
            }
        }
    }
    return c;
}

}  // namespace radiosity
