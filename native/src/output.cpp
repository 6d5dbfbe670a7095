// Per-corner output. By default a final gather at every corner point (final_gather.h), run as
// the last phase of a solve or an update. With gather_rays = 0: the radiance of the leaf
// element at each input corner (the hierarchy evaluated at that point), averaged over the
// faces that share the vertex unless a crease separates them; so too for an object whose
// colours are not read (ObjectDesc::output false), which the final gather skips.
#include <cmath>
#include <limits>

#include "radiosity/solver.h"

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

std::vector<float> Solver::all_corner_radiance() const {
    std::vector<float> out;
    for (size_t o = 0; o < scene_.objects().size(); ++o) {
        const std::vector<float> c = corner_radiance(int(o));
        out.insert(out.end(), c.begin(), c.end());
    }
    return out;
}

std::vector<float> Solver::corner_radiance(int object) const {
    settle_preview();
    if (object < 0 || object >= int(scene_.objects().size()))
        throw std::out_of_range("unknown object " + std::to_string(object));
    const ObjectDesc& o = scene_.objects()[size_t(object)];
    if (o.textured()) {
        // A textured surface: each corner reflects with its own reflectance what arrives there.
        std::vector<float> v = corner_irradiance(object);
        for (size_t f = 0; f < o.polygon_count(); ++f)
            for (int k = 0; k < o.loop_totals[f]; ++k) {
                const size_t c = size_t(o.loop_starts[f]) + size_t(k);
                const Rgb out = o.corner_shading(f, c, {double(v[3 * c]), double(v[3 * c + 1]), double(v[3 * c + 2])});
                for (int ch = 0; ch < 3; ++ch) v[3 * c + size_t(ch)] = float(out[ch]);
            }
        return v;
    }
    // An object without output has no gather points (final_gather.cpp): its leaves.
    return gathered_or_leaves(object,
                              settings_.gather_rays > 0 && o.output ? output_.corner_radiance(h_, object) : std::vector<float>{},
                              [this](int id) { return h_.nodes[id].L; });
}

std::vector<float> Solver::gathered_or_leaves(int object, std::vector<float> gathered,
                                              const std::function<Rgb(int)>& leaf_value) const {
    const ObjectDesc& o = scene_.objects()[size_t(object)];
    if (gathered.size() != o.corner_count() * 3) return corner_values(object, leaf_value);
    if (!o.written_corners.empty()) o.fill_unwritten(gathered, corner_values(object, leaf_value));
    return gathered;
}

void Solver::final_gather(double from, double to, const FinalGather::Moves* moves) {
    if (settings_.gather_rays <= 0 || tolerances_.reference <= 0) {
        output_.clear();
        return;
    }
    if (!moves) {
        memory_.forecast_output(memory_view());
        stats_.gather_forecast_bytes = int64_t(memory_.output_forecast());
    }
    direct_light_.find_contacts(h_, scene_, settings_.threads);
    h_.index_emitters();  // the near field asks per point whether a cluster emits
    gathering_.enclosure().fit(h_);  // a leaf split since the last collect reads its parent's answer
    FinalGather::Config c;
    c.rays = settings_.gather_rays;
    c.min_rays = settings_.gather_min_rays;
    c.share = settings_.gather_share;
    c.light_samples = std::max(4, settings_.gather_rays / 8);
    c.threads = settings_.threads;
    c.seed = settings_.seed;
    c.cycles_points = settings_.cycles_corner_points;
    c.sealed_solids = settings_.gather_sealed_solids;
    const FinalGather::Solution s{scene_, h_, *vis_, links_, gathering_.enclosure(),
                                  [this](int surface, const Vec3& p) { return direct_light_.contact(h_, surface, p); },
                                  &topology_.tri_prim()};
    auto progress = [&](double f) {
        check_cancel();
        set_progress(from + (to - from) * f);
    };
    try {
        if (moves) {
            FinalGather::Moves m = *moves;
            m.cast_all = !settings_.replay_rays;
            output_.retrace(s, c, m, progress);
        }
        else
            output_.trace(s, c, progress);
    } catch (...) {
        output_.clear();  // half a trace is no trace (corners fall back to the leaves)
        throw;
    }
    const FinalGather::Counts& k = output_.counts();
    stats_.gather_points = k.points;
    stats_.gather_corners = k.corners;
    stats_.gather_covered = k.covered;
    stats_.gather_sealed = k.sealed;
    stats_.gather_links = k.links;
    stats_.gather_rays = k.rays;
    stats_.gather_bytes = int64_t(output_.bytes());
    stats_.gather_kept = k.kept;
    stats_.gather_replayed = k.replayed;
    stats_.gather_fresh_points = k.fresh_points;
    stats_.gather_near = k.near;
    stats_.gather_near_rays = k.near_rays;
    stats_.gather_lamp_rays = k.lamp_rays;
    stats_.gather_shared = k.shared;
    stats_.gather_probe_rays = k.probe_rays;
    stats_.gather_probes_kept = k.probes_kept;
}

std::vector<float> Solver::corner_values(int object, const std::function<Rgb(int)>& leaf_value) const {
    if (object < 0 || object >= int(scene_.objects().size()))
        throw std::out_of_range("unknown object " + std::to_string(object));
    const ObjectDesc& o = scene_.objects()[object];
    const size_t nc = o.corner_count();
    std::vector<Rgb> val(nc);
    std::vector<double> wsum(nc, 0.0);
    std::vector<Vec3> face_n(o.polygon_count());
    std::vector<char> touching(nc, 0);
    // Value of each corner on its own face (fan-split faces: angle-weighted over pieces).
    for (const Primitive& p : h_.prims) {
        if (p.object != object || p.front < 0) continue;
        const Node& root = h_.nodes[h_.surfaces[p.front].root];
        face_n[p.face] = root.normal;
        for (int k = 0; k < p.poly.n; ++k) {
            int c = p.corner[k];
            touching[c] = direct_light_.corner_in_contact(h_, p, k);
            double w = std::max(corner_angle(p.poly, k), 1e-6);
            val[c] += leaf_value(corner_leaf(h_, h_.surfaces[p.front].root, k)) * w;
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

    const double cos_crease = std::cos(settings_.crease_angle_deg * kPi / 180.0);
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

Rgb Solver::radiance_at(int object, int face, const Vec3& world_point) const {
    settle_preview();
    if (!finite(world_point)) throw InputError("radiance_at: the point has a NaN or inf coordinate");
    const Vec3 x = h_.to_internal(world_point);
    // The piece of the polygon (n-gons are fanned) that contains x.
    int id = -1;
    double best = std::numeric_limits<double>::infinity();
    for (const Primitive& p : h_.prims) {
        if (p.object != object || p.face != face || p.front < 0) continue;
        int r = h_.surfaces[p.front].root;
        double o = distance_outside(h_.nodes[r].poly, h_.nodes[r].normal, x);
        if (id < 0 || o < best) { best = o; id = r; }
    }
    if (id < 0) throw std::out_of_range("no polygon " + std::to_string(face) + " in object " + std::to_string(object));
    return h_.nodes[h_.leaf_at(id, x)].L;
}

}  // namespace radiosity
