// An object's front-side leaf elements in a fixed order: its primitives in input order, the
// quadtree of each primitive's front depth first, children in order.
#pragma once
#include <vector>

#include "radiosity/hierarchy.h"

namespace radiosity {

// Calls visit(node id, primitive) for each front leaf of `object`, in that order.
template <class Visit>
void for_each_front_leaf(const Hierarchy& h, int object, Visit&& visit) {
    std::vector<int> stack;
    for (const Primitive& p : h.prims) {
        if (p.object != object || p.front < 0) continue;
        stack.assign(1, h.surfaces[size_t(p.front)].root);
        while (!stack.empty()) {
            const int id = stack.back();
            stack.pop_back();
            const Node& n = h.nodes[size_t(id)];
            if (n.is_leaf())
                visit(id, p);
            else
                stack.insert(stack.end(), n.children.rbegin(), n.children.rend());
        }
    }
}

}  // namespace radiosity
