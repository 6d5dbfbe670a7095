// Enclosure (enclosure.h): the per-node table of enclosure answers and closure factors.
#include "radiosity/enclosure.h"

#include "radiosity/held_bytes.h"

namespace radiosity {

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

}  // namespace radiosity
