// Per-corner output. By default a final gather at every corner point (final_gather.h), run as
// the last phase of a solve or an update. With gather_rays = 0: the radiance of the leaf
// element at each input corner (corner_values.h); so too for an object whose colours are not
// read (ObjectDesc::output false), which the final gather skips.
#include <algorithm>
#include <limits>

#include "radiosity/corner_values.h"
#include "radiosity/solver.h"

namespace radiosity {

namespace {

// The final gather's settings, from the solver's.
FinalGather::Config gather_config(const Settings& settings) {
    FinalGather::Config c;
    c.rays = settings.gather_rays;
    c.min_rays = settings.gather_min_rays;
    c.share = settings.gather_share;
    c.light_samples = std::max(4, settings.gather_rays / 8);
    c.threads = settings.threads;
    c.seed = settings.seed;
    c.cycles_points = settings.cycles_corner_points;
    c.sealed_solids = settings.gather_sealed_solids;
    return c;
}

// What a trace counted (and the bytes it holds), as the stats report it.
void record_gather(const FinalGather::Counts& k, size_t bytes, Stats& s) {
    s.gather_points = k.points;
    s.gather_corners = k.corners;
    s.gather_covered = k.covered;
    s.gather_sealed = k.sealed;
    s.gather_links = k.links;
    s.gather_rays = k.rays;
    s.gather_bytes = int64_t(bytes);
    s.gather_kept = k.kept;
    s.gather_replayed = k.replayed;
    s.gather_fresh_points = k.fresh_points;
    s.gather_near = k.near;
    s.gather_near_rays = k.near_rays;
    s.gather_lamp_rays = k.lamp_rays;
    s.gather_shared = k.shared;
    s.gather_probe_rays = k.probe_rays;
    s.gather_probes_kept = k.probes_kept;
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
    return gathered_or_leaves({h_, scene_, direct_light_, settings_.crease_angle_deg}, object,
                              settings_.gather_rays > 0 && o.output ? output_.corner_radiance(h_, object) : std::vector<float>{},
                              [this](int id) { return h_.nodes[id].L; });
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
    const FinalGather::Config c = gather_config(settings_);
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
    record_gather(output_.counts(), output_.bytes(), stats_);
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
