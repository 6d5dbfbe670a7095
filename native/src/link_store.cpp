#include "radiosity/link_store.h"

#include <algorithm>

namespace radiosity {

int LinkStore::add(Hierarchy& h, Link l) {
    const int id = int(links_.size());
    if (l.active) {
        h.nodes[l.rcv].in_links.push_back(id);
        h.nodes[l.src].out_links.push_back(id);
    }
    if (l.parent >= 0) {
        l.next_sibling = links_[size_t(l.parent)].first_child;
        links_[size_t(l.parent)].first_child = id;
    }
    links_.push_back(std::move(l));
    ++live_;
    return id;
}

void LinkStore::activate(Hierarchy& h, int id) {
    Link& l = links_[id];
    if (l.active) return;
    l.active = true;
    l.occluded = false;
    h.nodes[l.rcv].in_links.push_back(id);
    h.nodes[l.src].out_links.push_back(id);
}

void LinkStore::kill(Hierarchy& h, int id) {
    if (links_[id].dead) return;
    if (links_[id].active) deactivate(h, id);
    links_[id].dead = true;
    --live_;
    kill_refined(h, id);
}

void LinkStore::kill_refined(Hierarchy& h, int id) {
    for (int c = links_[id].first_child; c >= 0; c = links_[c].next_sibling) kill(h, c);
    links_[id].first_child = -1;
}

void LinkStore::deactivate(Hierarchy& h, int id) {
    Link& l = links_[id];
    if (!l.active) return;
    l.active = false;
    auto drop = [id](std::vector<int>& v) {
        auto it = std::find(v.begin(), v.end(), id);
        if (it != v.end()) { *it = v.back(); v.pop_back(); }
    };
    drop(h.nodes[l.rcv].in_links);
    drop(h.nodes[l.src].out_links);
}

void LinkStore::clear() {
    links_.clear();
    live_ = 0;
}

}  // namespace radiosity
