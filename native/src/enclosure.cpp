// Enclosure (enclosure.h): the per-node table of enclosure answers and closure factors, and
// the escape rays that decide the answers.
#include "radiosity/enclosure.h"

#include <utility>

#include "radiosity/geometry.h"
#include "radiosity/held_bytes.h"
#include "radiosity/random.h"
#include "radiosity/settings.h"
#include "radiosity/visibility.h"

namespace radiosity {

namespace {

// The escape rays of a node (Enclosure's "Deciding"), as segments. Deterministic per node key.
void escape_rays(const Hierarchy& h, const Settings& settings, const Node& n,
                 std::vector<std::pair<Vec3, Vec3>>& rays) {
    const double far = 4.0 * h.scene_diag;
    const double lift = 1e-5 * h.scene_diag;  // off its own surface; tnear 0 sees neighbours
    Rng rng(Hierarchy::mix(settings.seed, n.key));
    Vec3 u, v;
    frame(n.normal, u, v);
    rays.clear();
    for (int r = 0; r < settings.closure_rays; ++r) {
        double r1 = rng.next(), r2 = rng.next();
        Vec3 d = cosine_direction(u, v, n.normal, r1, r2);
        const double s2 = rng.next(), s1 = rng.next();  // named: the order is every compiler's
        Vec3 o = n.poly.sample(s1, s2) + n.normal * lift;
        rays.emplace_back(o, o + d * far);
    }
}

}  // namespace

void Enclosure::fit(const Hierarchy& h) {
    const size_t from = size(), to = h.nodes.size();
    if (to <= from) return;
    factors_.resize(to);
    enclosed_.resize(to, -1);
    escape_ray_.resize(to, -1);
    decider_.resize(to, -1);
    // Ascending: a parent made in the same stretch has taken its own parent's entry already.
    for (size_t id = from; id < to; ++id) {
        const Node& n = h.nodes[id];
        if (n.is_cluster() || n.parent < 0 || h.nodes[size_t(n.parent)].is_cluster()) continue;
        const size_t p = size_t(n.parent);
        factors_[id] = factors_[p];
        enclosed_[id] = enclosed_[p];
        decider_[id] = decider_[p];
    }
}

void Enclosure::clear() { *this = Enclosure{}; }

double Enclosure::bytes(size_t nodes) const {
    constexpr double kPerNode = sizeof(ClosureFactors) + 2 * sizeof(int8_t) + sizeof(int32_t);
    const double now = held_bytes(factors_) + held_bytes(enclosed_) + held_bytes(escape_ray_) + held_bytes(decider_);
    return nodes > size() ? now + kPerNode * double(nodes - size()) : now;
}

std::vector<int> Enclosure::deciders(const Hierarchy& h) const {
    std::vector<char> is_decider(size(), 0);
    for (size_t i = 0; i < size(); ++i) {
        const Node& n = h.nodes[i];
        if (!n.is_cluster() && !n.dead && enclosed_[i] >= 0 && decider_[i] >= 0) is_decider[size_t(decider_[i])] = 1;
    }
    std::vector<int> out;
    for (size_t i = 0; i < is_decider.size(); ++i)
        if (is_decider[i]) out.push_back(int(i));
    return out;
}

void Enclosure::follow_deciders(const Hierarchy& h) {
    for (size_t i = 0; i < size(); ++i) {
        const Node& n = h.nodes[i];
        if (!n.is_cluster() && !n.dead && decider_[i] >= 0) enclosed_[i] = enclosed_[size_t(decider_[i])];
    }
}

void Enclosure::decide(const Sight& s, int id, const std::vector<Aabb>* moved_boxes) {
    std::vector<std::pair<Vec3, Vec3>> rays;
    escape_rays(s.h, s.settings, s.h.nodes[size_t(id)], rays);
    auto meets = [&](int r) { return meets_any(*moved_boxes, rays[r].first, rays[r].second); };
    if (moved_boxes && enclosed(id) == 1) {
        for (int r = 0; r < int(rays.size()); ++r)
            if (meets(r) && !s.vis.occluded(rays[r].first, rays[r].second, 0.0)) {
                reopen(id, r);
                return;
            }
        return;  // every ray still blocked
    }
    const int witness = escape_ray(id);
    if (moved_boxes && enclosed(id) == 0 && witness >= 0 && !meets(witness)) return;  // witness still clear
    for (int r = 0; r < int(rays.size()); ++r)
        if (!s.vis.occluded(rays[r].first, rays[r].second, 0.0)) {
            record(id, r);
            return;
        }
    record(id, -1);
}

}  // namespace radiosity
