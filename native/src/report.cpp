// What a finished run reports from the solution's parts (report.h).
#include "report.h"

#include <string>
#include <vector>

namespace radiosity {

void count_links(const Hierarchy& h, const LinkStore& links, Stats& s) {
    s.links = s.cluster_links = s.surface_links = s.history_links = s.occluded_links = 0;
    s.obj_env_links = s.env_env_links = s.obj_obj_links = 0;
    for (const Link& l : links) {
        if (l.dead) continue;
        if (l.occluded) { ++s.occluded_links; continue; }
        if (!l.active) { ++s.history_links; continue; }
        ++s.links;
        (l.cluster ? s.cluster_links : s.surface_links)++;
        int os = h.nodes[l.src].object, orc = h.nodes[l.rcv].object;
        // A link end above object level (a collection or the root) counts as object side
        // when it is a collection cluster; environment means polygons directly in the scene.
        bool src_env = os >= 0 ? h.object_of_env[os] != 0 : l.src == h.root;
        bool rcv_env = orc >= 0 ? h.object_of_env[orc] != 0 : l.rcv == h.root;
        if (src_env && rcv_env) ++s.env_env_links;
        else if (src_env != rcv_env) ++s.obj_env_links;
        else ++s.obj_obj_links;
    }
}

int64_t lit_elements(const Hierarchy& h, const LinkStore& links, const DirectLight& direct) {
    int64_t elements = 0;
    for (size_t si = 0; si < h.surfaces.size(); ++si) {
        if (h.surface_dead(int(si))) continue;  // of a removed object
        const Node& sr = h.nodes[h.surfaces[si].root];
        bool r = sr.emission.max() > 0;
        std::vector<int> stack{h.surfaces[si].root};
        int64_t leaves = 0;
        while (!stack.empty()) {
            int id = stack.back();
            stack.pop_back();
            const Node& n = h.nodes[id];
            r = r || !n.in_links.empty() || !n.out_links.empty();
            r = r || (n.children.empty() && direct.direct(id).max() > 0);  // lit by a lamp
            if (n.children.empty()) ++leaves;
            for (int c : n.children) stack.push_back(c);
        }
        // Else reached through a cluster link only if the surface faces its sender (the
        // clusters' lists are long: read only when nothing else says so).
        auto faces_a_sender = [&] {
            for (int a : h.ancestors_of_surface(int(si)))
                for (int li : h.nodes[a].in_links) {
                    const Link& l = links[li];
                    if (l.K > 0 && dot(sr.normal, l.dir) < 0 && h.holds_pocket(l.src, sr.pocket)) return true;
                }
            return false;
        };
        r = r || faces_a_sender();
        if (r) elements += leaves;
    }
    return elements;
}

void add_result_warnings(const Hierarchy& h, const Settings& settings, double held, double limit, Stats& s) {
    if (h.unfanned_polygons > 0)
        s.warnings.push_back(std::to_string(h.unfanned_polygons) +
                             " concave polygon(s) too large (over 4096 corners) or self-intersecting to "
                             "triangulate: some of their pieces face the wrong way; triangulate them in Blender");
    if (held > limit)
        s.warnings.push_back("the bake holds about " + std::to_string(int64_t(held / 1048576.0)) +
                             " MB, over max_memory_mb (" + std::to_string(int64_t(limit / 1048576.0)) +
                             "): allow more memory, or use a coarser preset");
    if (s.memory_capped)
        s.warnings.push_back("refinement stopped at the memory cap (max_memory_mb " +
                             std::to_string(int64_t(limit / 1048576.0)) +
                             "): the result is coarser than the threshold asks");
    else if (s.capped)
        s.warnings.push_back("refinement stopped at the element or link cap (max_elements " +
                             std::to_string(settings.max_elements) + ", max_links " +
                             std::to_string(settings.max_links) + "): the result is coarser than the threshold asks");
}

}  // namespace radiosity
