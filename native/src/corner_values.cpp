// Per-corner read-out of the solution's leaves (corner_values.h).
#include "radiosity/corner_values.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace radiosity {

namespace {
// Leaf below `root` holding quadtree corner k: child k always keeps parent corner k.
int corner_leaf(const Hierarchy& h, int root, int k) {
    int id = root;
    while (!h.nodes[id].children.empty()) id = h.nodes[id].children[k];
    return id;
}
double corner_angle(const Poly& p, int k) {
    Vec3 a = p.v[(k + p.n - 1) % p.n] - p.v[k], b = p.v[(k + 1) % p.n] - p.v[k];
    double la = length(a), lb = length(b);
    if (la <= 0 || lb <= 0) return 0;
    return std::acos(std::clamp(dot(a, b) / (la * lb), -1.0, 1.0));
}
}  // namespace

std::vector<float> leaf_corner_values(const CornerRead& r, int object, const std::function<Rgb(int)>& leaf_value) {
    const Hierarchy& h = r.h;
    const SceneDesc& scene = r.scene;
    if (object < 0 || object >= int(scene.objects().size()))
        throw std::out_of_range("unknown object " + std::to_string(object));
    const ObjectDesc& o = scene.objects()[object];
    const size_t nc = o.corner_count();
    std::vector<Rgb> val(nc);
    std::vector<double> wsum(nc, 0.0);
    std::vector<Vec3> face_n(o.polygon_count());
    std::vector<char> touching(nc, 0);
    // Value of each corner on its own face (fan-split faces: angle-weighted over pieces).
    for (const Primitive& p : h.prims) {
        if (p.object != object || p.front < 0) continue;
        const Node& root = h.nodes[h.surfaces[p.front].root];
        face_n[p.face] = root.normal;
        for (int k = 0; k < p.poly.n; ++k) {
            int c = p.corner[k];
            touching[c] = r.direct.corner_in_contact(h, p, k);
            double w = std::max(corner_angle(p.poly, k), 1e-6);
            val[c] += leaf_value(corner_leaf(h, h.surfaces[p.front].root, k)) * w;
            wsum[c] += w;
        }
    }
    for (size_t c = 0; c < nc; ++c)
        if (wsum[c] > 0) val[c] = val[c] / wsum[c];
    // Corner -> face lookup and vertex -> corners adjacency.
    const std::vector<int> face_of = o.corner_polygons();
    std::vector<int> start(o.vertices.size() + 1, 0), list(nc);
    for (size_t c = 0; c < nc; ++c) ++start[o.corner_verts[c] + 1];
    for (size_t v = 0; v < o.vertices.size(); ++v) start[v + 1] += start[v];
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (size_t c = 0; c < nc; ++c) list[fill[o.corner_verts[c]]++] = int(c);

    const double cos_crease = std::cos(r.crease_angle_deg * kPi / 180.0);
    std::vector<float> out(nc * 3, 0.f);
    for (size_t c = 0; c < nc; ++c) {
        const int v = o.corner_verts[c];
        const Vec3 nf = face_n[face_of[c]];
        Rgb acc;
        double w = 0;
        for (int i = start[v]; i < start[v + 1]; ++i) {
            int c2 = list[i];
            if (wsum[c2] <= 0) continue;
            // Zero-area faces have no normal: they take the value of their neighbours.
            if (length2(nf) > 0 && dot(nf, face_n[face_of[c2]]) < cos_crease) continue;
            if (touching[c] != touching[c2]) continue;  // lights.cpp: a contact line is an edge
            acc += val[c2] * wsum[c2];
            w += wsum[c2];
        }
        Rgb r = w > 0 ? acc / w : (wsum[c] > 0 ? val[c] : Rgb{});
        out[3 * c] = float(r.r);
        out[3 * c + 1] = float(r.g);
        out[3 * c + 2] = float(r.b);
    }
    return out;
}

std::vector<float> gathered_or_leaves(const CornerRead& r, int object, std::vector<float> gathered,
                                      const std::function<Rgb(int)>& leaf_value) {
    const ObjectDesc& o = r.scene.objects()[size_t(object)];
    if (gathered.size() != o.corner_count() * 3) return leaf_corner_values(r, object, leaf_value);
    if (!o.written_corners.empty()) o.fill_unwritten(gathered, leaf_corner_values(r, object, leaf_value));
    return gathered;
}

}  // namespace radiosity
