// Adaptive-mesh output: an object's front-side leaf elements as one mesh, T-vertex free.
//
// Element quadtrees split at edge midpoints, so where a coarse leaf meets finer neighbours
// (same input edge, conforming input mesh) every neighbour vertex on the coarse edge is a
// repeated midpoint of it, computed with the same arithmetic ((a + b) * 0.5, symmetric in a
// and b): looking the midpoint up among all leaf vertices, recursively, finds exactly the
// hanging vertices, which then become corners of the coarse leaf (an n-gon). An input mesh
// that already has T-junctions keeps them.
#include <map>

#include "radiosity/front_leaves.h"
#include "radiosity/leaf_mesh.h"
#include "radiosity/solver.h"

namespace radiosity {

namespace {
// Exact coordinates as the key: shared vertices are bit-identical by construction.
using VKey = std::array<double, 3>;
VKey key_of(const Vec3& p) { return {p.x, p.y, p.z}; }
}  // namespace

LeafMesh Solver::leaf_mesh(int object, bool lighting_only) const {
    settle_preview();
    if (object < 0 || object >= int(scene_.objects().size()))
        throw std::out_of_range("unknown object " + std::to_string(object));
    std::vector<std::pair<int, int>> leaves;  // (node, face), in for_each_front_leaf's order
    for_each_front_leaf(h_, object, [&](int id, const Primitive& p) { leaves.push_back({id, p.face}); });
    LeafMesh m;
    std::map<VKey, int> index;
    auto vertex = [&](const Vec3& p) {
        auto [it, fresh] = index.emplace(key_of(p), int(m.vertices.size()));
        if (fresh) m.vertices.push_back(p * h_.unit + h_.origin);
        return it->second;
    };
    for (const auto& [id, face] : leaves) {
        (void)face;
        const Poly& q = h_.nodes[id].poly;
        for (int k = 0; k < q.n; ++k) vertex(q.v[k]);
    }
    // Hanging vertices strictly inside segment a-b, in order from a to b.
    std::function<void(const Vec3&, const Vec3&, int, std::vector<int32_t>&)> hanging =
        [&](const Vec3& a, const Vec3& b, int depth, std::vector<int32_t>& ring) {
            if (depth > 60) return;  // below double resolution: no further midpoint exists
            const Vec3 mid = (a + b) * 0.5;
            auto it = index.find(key_of(mid));
            if (it == index.end()) return;
            hanging(a, mid, depth + 1, ring);
            ring.push_back(it->second);
            hanging(mid, b, depth + 1, ring);
        };
    for (const auto& [id, face] : leaves) {
        const Node& n = h_.nodes[id];
        const Poly& q = n.poly;
        std::vector<int32_t> ring;
        for (int k = 0; k < q.n; ++k) {
            ring.push_back(index.at(key_of(q.v[k])));
            hanging(q.v[k], q.v[(k + 1) % q.n], 0, ring);
        }
        m.loop_totals.push_back(int32_t(ring.size()));
        m.corner_verts.insert(m.corner_verts.end(), ring.begin(), ring.end());
        m.values.push_back(lighting_only ? leaf_irradiance(id) : n.L);
        m.source_face.push_back(face);
    }
    return m;
}

}  // namespace radiosity
