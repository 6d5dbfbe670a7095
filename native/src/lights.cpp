// Direct light of Blender point, spot and sun lights and of a uniform world at the leaf
// elements (see lights.h). Each leaf keeps the area mean of its four children's estimates as
// its direct term and their spread as the refinement criterion, so a leaf split for its direct
// light already knows what its children will see.
#include "radiosity/lights.h"

#include <algorithm>
#include <cmath>

#include "radiosity/parallel.h"
#include "radiosity/solver.h"

namespace radiosity {

void LightDesc::validate() const {
    auto bad = [this](const std::string& what) { throw InputError("light '" + name + "': " + what); };
    if (int(type) < 0 || int(type) > 3) bad("unknown type");
    if (!finite(position) || !finite(direction)) bad("position or direction is not finite");
    if (!finite(intensity)) bad("intensity is not finite");
    for (int k = 0; k < 3; ++k)
        if (intensity[k] < 0) bad("negative intensity");
    if ((type == Type::Spot || type == Type::Sun) && !(length(direction) > 0)) bad("zero direction");
    if (!(std::isfinite(radius) && radius >= 0)) bad("radius must be >= 0");
    if (!(std::isfinite(angle) && angle >= 0 && angle <= kPi)) bad("sun angle must be in [0, pi]");
    if (!(std::isfinite(spot_size) && spot_size > 0 && spot_size <= kPi)) bad("spot size must be in (0, pi]");
    if (!(std::isfinite(spot_blend) && spot_blend >= 0 && spot_blend <= 1)) bad("spot blend must be in [0, 1]");
    if (env && type != Type::Sky) bad("only the world (sky) takes an environment map");
}

int SceneDesc::add_light(LightDesc l) {
    l.validate();
    l.direction = normalize(l.direction);
    lights_.push_back(std::move(l));
    return int(lights_.size()) - 1;
}

namespace {

// A light in the solver's internal frame (geometry divided by `unit`): intensities of point
// and spot lights are scaled by 1/unit^2 so that I / d_internal^2 is the world irradiance.
struct ILight {
    LightDesc::Type type;
    Vec3 pos, dir;
    double radius = 0, cos_half = -1, smooth = 0, sun_cos = 1;
    bool cos_falloff = false;
    Rgb I;
    const EnvMap* env = nullptr;  // Sky: radiance I x env(d), owned by the scene's LightDesc
    uint64_t salt = 0;
};

std::vector<ILight> internal_lights(const SceneDesc& scene, const Hierarchy& h) {
    std::vector<ILight> out;
    uint64_t k = 0;
    for (const LightDesc& d : scene.lights()) {
        ++k;
        if (d.intensity.max() <= 0 || (d.env && d.env->empty_of_light())) continue;
        ILight l;
        l.env = d.env.get();
        l.type = d.type;
        l.pos = (d.position - h.origin) / h.unit;
        l.dir = normalize(d.direction);
        l.radius = d.radius / h.unit;
        l.I = d.type == LightDesc::Type::Point || d.type == LightDesc::Type::Spot ? d.intensity / (h.unit * h.unit)
                                                                                   : d.intensity;
        l.cos_half = d.type == LightDesc::Type::Spot ? std::cos(0.5 * d.spot_size) : -1.0;
        // Cycles' spot edge: smoothstep over the outer `blend` part of (1 - cos_half).
        l.smooth = (1.0 - l.cos_half) * d.spot_blend;
        l.cos_falloff = d.spot_cos_falloff;
        l.sun_cos = std::cos(0.5 * d.angle);
        l.salt = Hierarchy::mix(0x11947u, k);
        out.push_back(l);
    }
    return out;
}

double spot_mask(const ILight& l, const Vec3& from_light) {
    if (l.type != LightDesc::Type::Spot) return 1.0;
    double z = dot(from_light, l.dir);
    if (z <= l.cos_half) return 0.0;
    double m = 1.0;
    double t = z - l.cos_half;
    if (l.smooth > 0 && t < l.smooth) {
        double x = t / l.smooth;
        m = x * x * (3 - 2 * x);
    }
    return l.cos_falloff ? m * z : m;
}

// What one child's samples say about a light.
struct Sampled {
    Rgb mean;           // irradiance / pi, visibility included
    double var = 0;     // variance of the mean (max channel)
    double unocc = 0;   // mean without visibility (max channel)
    bool partial = false;  // some samples that could see the light did, some did not
};

// The two numbers that pick sample i of m on a light (a direction or a point on it): with
// `strata`, the first k x k samples (k = floor(sqrt(m))) fill a jittered k x k grid of the
// unit square, the rest are uniform. Each sample is still uniform on its own, so the mean
// stays unbiased, and a smooth integrand (the sky seen past a chair, a sun's soft shadow)
// comes out with far less noise than from independent samples.
std::pair<double, double> light_sample_uv(int i, int m, bool strata, Rng& rng) {
    const double a = rng.next(), b = rng.next();
    if (!strata) return {a, b};
    const int k = int(std::sqrt(double(m)));
    if (i >= k * k) return {a, b};
    return {(i % k + a) / k, (i / k + b) / k};
}

// Monte Carlo estimate of irradiance / pi over the points `where(i, rng)` gives (on a plane
// of normal n) from one light, with visibility; m samples. With `strata` (a single point:
// `where` constant) the light's samples are stratified (light_sample_uv); over an element
// the points are stratified instead, and the two must not be paired by index.
// Shadow rays through `vis`: a Visibility, or a LampRayStream (a point's recorded rays).
template <class Where, class Contact, class Rays>
Sampled estimate(const ILight& l, const Where& where, const Vec3& n, int m, Rng& rng, Rays& vis, double lift,
                 double far, const Contact& contact, bool strata = false) {
    Rgb s1;  // sum of the samples' irradiance / pi, visibility included
    double s2 = 0, s_unocc = 0;
    int seen = 0, hidden = 0;
    Vec3 su, sv;  // sun cap frame
    if (l.type == LightDesc::Type::Sun) frame(-l.dir, su, sv);
    Vec3 nu, nv;  // hemisphere frame
    if (l.type == LightDesc::Type::Sky) frame(n, nu, nv);
    // A map: the samples estimate only what occluders take away from the unoccluded
    // irradiance, known in closed form (a control variate: an open floor under a sun gets its
    // exact light, not the noise of a few samples of a bright spot).
    const Rgb open = l.env ? l.I * l.env->irradiance(n) / kPi : Rgb{};
    for (int i = 0; i < m; ++i) {
        const Vec3 p = where(i, rng);
        const Vec3 o = p + n * lift;
        // (A map's two halves, cosine-weighted and by the map, are stratified apart.)
        const bool halves = l.type == LightDesc::Type::Sky && l.env;
        const auto [a, b] = halves ? light_sample_uv(i / 2, i % 2 ? m / 2 : (m + 1) / 2, strata, rng)
                                   : light_sample_uv(i, m, strata, rng);
        const bool touching = contact(p);
        double f = 0, u = 0;  // scalar factor of `col`, with and without visibility
        Rgb col = l.I;
        switch (l.type) {
            case LightDesc::Type::Sky: {
                if (l.env) {
                    // Half the samples cosine-weighted, half by the map's luminance x solid
                    // angle (a sun in the map), each weighted by the mixture of both densities
                    // (the balance heuristic): neither a bright spot nor a uniform map is missed.
                    double pm = 0;
                    Vec3 d;
                    if (i % 2) {
                        d = l.env->sample(a, b, pm);
                    } else {
                        d = cosine_direction(nu, nv, n, a, b);
                        pm = l.env->pdf(d);
                    }
                    const double c = dot(n, d);
                    if (c <= 0) break;
                    const double mix = 0.5 * (c / kPi + pm);
                    if (!(mix > 0)) break;
                    col = l.I * l.env->radiance(d);
                    u = c / kPi / mix;
                    if (!touching && !vis.occluded(o, o + d * far, 0.0)) f = u;
                    if (u > 0) (f > 0 ? seen : hidden)++;
                    // What this sample says is missing from `open` (col x (f - u) <= 0).
                    const double g = (u - f) * col.max();
                    s1 += col * (f - u);
                    s2 += g * g;
                    continue;
                }
                // Cosine-weighted direction: the estimator of E/pi is L_sky x visibility.
                Vec3 d = cosine_direction(nu, nv, n, a, b);
                u = 1.0;
                if (!touching && !vis.occluded(o, o + d * far, 0.0)) f = 1.0;
                break;
            }
            case LightDesc::Type::Sun: {
                // Uniform on the sun's cap of directions (toward the sun).
                double ct = 1 - a * (1 - l.sun_cos), st = std::sqrt(std::max(0.0, 1 - ct * ct)), phi = 2 * kPi * b;
                Vec3 d = su * (std::cos(phi) * st) + sv * (std::sin(phi) * st) + (-l.dir) * ct;
                double c = dot(n, d);
                if (c <= 0) break;
                u = c / kPi;
                if (!touching && !vis.occluded(o, o + d * far, 0.0)) f = u;
                break;
            }
            default: {
                // A disk of the light's radius facing the receiving point (Cycles' model of a
                // point light with a radius), radiance I / (pi r^2): uniform samples on it.
                Vec3 q = l.pos;
                Vec3 w = normalize(p - l.pos);
                if (l.radius > 0) {
                    Vec3 u, v;
                    frame(w, u, v);
                    double r = l.radius * std::sqrt(a), phi = 2 * kPi * b;
                    q = l.pos + u * (r * std::cos(phi)) + v * (r * std::sin(phi));
                }
                Vec3 d = q - p;
                double d2 = length2(d);
                if (d2 <= 0) break;
                Vec3 dn = d / std::sqrt(d2);
                double cp = dot(n, dn), cq = l.radius > 0 ? -dot(w, dn) : 1.0;
                if (cp <= 0 || cq <= 0) break;
                double mask = spot_mask(l, w);
                if (mask <= 0) break;
                u = cp * cq * mask / (d2 * kPi);
                if (!touching && !vis.occluded(o, q)) f = u;
                break;
            }
        }
        const double g = f * col.max();
        s1 += col * f;
        s2 += g * g;
        s_unocc += u * col.max();
        if (u > 0) (f > 0 ? seen : hidden)++;
    }
    Sampled r;
    r.mean = s1 / m;
    const double mean = l.env ? -r.mean.max() : r.mean.max();
    r.var = m > 1 ? std::max(0.0, s2 / m - mean * mean) / (m - 1) : mean * mean;
    r.unocc = s_unocc / m;
    if (l.env) {
        r.mean = cmax(open + r.mean, Rgb{});
        r.unocc = open.max();
        if (hidden > 0 && seen == 0) r.mean = Rgb{};  // a point in contact, or wholly covered
    }
    r.partial = seen > 0 && hidden > 0;
    return r;
}

// A point's shadow rays, cast through `vis` or, with `old` (the same point's record, same
// seed and lights) and `changed` (boxes where geometry moved since), a ray that meets none of
// the boxes takes its recorded outcome.
struct LampRayStream {
    LampRayStream(const Visibility& v, const LampRays* o, const std::vector<Aabb>* c)
        : vis(v), old(o), changed(o ? c : nullptr) {}
    const Visibility& vis;
    const LampRays* old = nullptr;
    MovedBoxes changed;
    LampRays out;
    int cast = 0;
    bool occluded(const Vec3& a, const Vec3& b) { return take(a, b, -1); }
    bool occluded(const Vec3& a, const Vec3& b, double near) { return take(a, b, near); }
    bool take(const Vec3& a, const Vec3& b, double near) {
        const int k = out.count++;
        bool blocked;
        if (old && k < old->count && !changed.meets(a, b)) {
            blocked = (old->blocked[size_t(k) >> 6] >> (k & 63)) & 1;
        } else {
            blocked = near < 0 ? vis.occluded(a, b) : vis.occluded(a, b, near);
            ++cast;
        }
        if ((size_t(k) >> 6) >= out.blocked.size()) out.blocked.push_back(0);
        if (blocked) out.blocked[size_t(k) >> 6] |= uint64_t(1) << (k & 63);
        return blocked;
    }
};

template <class Rays>
PointLight direct_light_with(const SceneDesc& scene, const Hierarchy& h, Rays& vis, const Vec3& x, const Vec3& n,
                             bool covered, int m, uint64_t seed) {
    PointLight out;
    const double far = 4.0 * h.scene_diag, lift = 1e-5 * h.scene_diag;
    for (const ILight& l : internal_lights(scene, h)) {
        Rng rng(Hierarchy::mix(seed ^ l.salt, 0x70u));
        const bool sky = l.type == LightDesc::Type::Sky;
        // A point light without a radius casts a hard shadow: one ray says all there is.
        const bool hard = (l.type == LightDesc::Type::Point || l.type == LightDesc::Type::Spot) && l.radius <= 0;
        const int mm = sky ? 4 * m : hard ? 1 : m;
        const Sampled r = estimate(l, [&x](int, Rng&) { return x; }, n, mm, rng, vis, lift, far,
                                   [covered](const Vec3&) { return covered; }, true);
        out.E += r.mean;
        out.partial |= r.partial;
        out.rays += mm;
    }
    return out;
}

}  // namespace

PointLight direct_light_at(const SceneDesc& scene, const Hierarchy& h, const Visibility& vis, const Vec3& x,
                           const Vec3& n, bool covered, int m, uint64_t seed) {
    return direct_light_with(scene, h, vis, x, n, covered, m, seed);
}

PointLight direct_light_replay(const SceneDesc& scene, const Hierarchy& h, const Visibility& vis, const Vec3& x,
                               const Vec3& n, int m, uint64_t seed, const LampRays* old,
                               const std::vector<Aabb>* changed, LampRays& out) {
    LampRayStream rs(vis, old, changed);
    PointLight r = direct_light_with(scene, h, rs, x, n, false, m, seed);
    r.rays = rs.cast;
    out = std::move(rs.out);
    return r;
}

int element_shadow_rays(int rays_per_link, LightDesc::Type type) {
    // Half the link rays (an element costs two links), four times that for the sky, whose
    // hemisphere integral is noisier than a small light's. Fewer hid real shadow edges behind
    // the noise allowance of light_compute.
    const int m = std::max(4, rays_per_link / 2);
    return type == LightDesc::Type::Sky ? 4 * m : m;
}

void Solver::set_light(int index, const LightDesc& l) {
    if (index < 0 || index >= int(scene_.lights().size()))
        throw InputError("set_light: unknown light " + std::to_string(index));
    l.validate();
    LightDesc d = l;
    d.direction = normalize(d.direction);
    scene_.lights_mut()[index] = d;
    std::fill(lights_.have.begin(), lights_.have.end(), 0);
    lights_.recheck = true;
    edits_.record_materials();  // the update path re-derives the reference radiance and re-solves
}

double Solver::light_power(double total_area) const {
    // Flux the lights bring into the scene, in radiance x internal area (the units of the
    // emitters' sum in compute_reference): a Lambertian emitter of radiance L and area A
    // radiates pi L A, so each light counts as power / pi.
    double p = 0;
    for (const ILight& l : internal_lights(scene_, h_)) {
        switch (l.type) {
            case LightDesc::Type::Point: p += 4 * l.I.max(); break;
            case LightDesc::Type::Spot: p += 2 * (1 - l.cos_half) * l.I.max(); break;
            case LightDesc::Type::Sun: p += 0.25 * total_area * l.I.max() / kPi; break;  // a convex scene's mean projection
            case LightDesc::Type::Sky:  // half the sky, unoccluded
                p += 0.5 * total_area * (l.env ? (l.I * l.env->mean()).max() : l.I.max());
                break;
        }
    }
    return p;
}

Rgb Solver::light_direct(int id) const {
    return size_t(id) < lights_.have.size() && lights_.have[id] == LightState::kLit ? lights_.direct[id] : Rgb{};
}

double Solver::light_spread(int id) const {
    return size_t(id) < lights_.have.size() && lights_.have[id] == LightState::kLit ? double(lights_.spread[id]) : 0.0;
}

void Solver::light_invalidate() {
    // Placements changed since the cache was made (an update moved objects): every shadow may
    // have changed. A move that replays rays (moves only) leaves each node's shadow rays to be
    // replayed: those that meet no moved box keep their outcome. A node whose box meets a
    // moved one is lit afresh (what touches it, and so which of its rays are cast, may differ).
    if (edits_.poses() != lights_.poses) {
        const bool replay = update_run_ && update_run_->replaying && !lights_.poses.empty();
        bool stale_left = false;
        for (uint8_t v : lights_.have) stale_left |= v == LightState::kStale;
        if (!stale_left) lights_.clips.clear();
        if (replay) {
            const std::vector<Aabb>& clips = update_run_->replay_clips;
            lights_.clips.insert(lights_.clips.end(), clips.begin(), clips.end());
            for (size_t id = 0; id < lights_.have.size(); ++id) {
                if (lights_.have[id] == LightState::kNone) continue;
                const Node& n = h_.nodes[id];
                bool near = n.dead;
                for (const Aabb& c : clips) near = near || c.overlaps(n.box);
                lights_.have[id] = near || id >= lights_.rays.size() ? LightState::kNone : LightState::kStale;
            }
        } else {
            std::fill(lights_.have.begin(), lights_.have.end(), LightState::kNone);
        }
        lights_.recheck = !lights_.poses.empty();
        lights_.contacts.clear();
        lights_.poses = edits_.poses();
    }
    light_resize();
}

void Solver::light_prepare() {
    if (scene_.lights().empty()) return;
    light_invalidate();
    std::vector<int> todo;
    for (int id : leaves_)
        if (lights_.have[id] != LightState::kLit) todo.push_back(id);
    light_compute(todo);
}

void Solver::light_update() {
    // An update's first step for the lights (adjust.cpp): lights or placements changed, so
    // the splits the new direct light does not need go before the remaining leaves are lit
    // again (the old leaves there would cost rays for nothing), and the new light splits
    // where it needs, as light_initial does before a full solve's first linking: the oracle
    // then judges links by the radiances the new light's elements give. (Split only in the
    // first refinement round, after the first gather, links were judged on the old, coarser
    // light elements and refined for good: 0.09-0.14 % NRMSE more on two of eight moves.)
    if (scene_.lights().empty()) return;
    light_invalidate();
    if (!lights_.recheck) return;
    lights_.recheck = false;
    light_coarsen();
    collect_receivers();
    if (light_refine()) collect_receivers();
}

void Solver::light_contacts() {
    // Surfaces of other objects lying in the same plane and facing the other way: where they
    // overlap, the two touch (a box standing on a floor). Rays from there start between the
    // two and would escape through the other one; Cycles finds such points unlit, and so
    // does a real contact. Found by walking the cluster tree by boxes.
    lights_.contacts.assign(h_.surfaces.size(), {});
    const double tol = 1e-7 * h_.scene_diag;
    parallel_for(h_.surfaces.size(), settings_.threads, [&](size_t si) {
        const Node& n = h_.nodes[h_.surfaces[si].root];
        if (n.dead) return;  // of a removed object
        Aabb b = n.box;
        b.lo -= Vec3{tol, tol, tol};
        b.hi += Vec3{tol, tol, tol};
        auto overlaps = [&b](const Aabb& o) {
            for (int a = 0; a < 3; ++a)
                if (o.lo[a] > b.hi[a] || o.hi[a] < b.lo[a]) return false;
            return true;
        };
        const bool own_back = h_.surfaces[si].back;
        // Polygons of its own object looked at, at most: the pieces of a fanned n-gon all share
        // its apex, so every piece's box meets every other's (100k pieces: 10^10 tests). Real
        // meshes meet a few neighbours.
        int same_left = 4096;
        std::vector<int> stack{h_.root};
        while (!stack.empty()) {
            const int id = stack.back();
            stack.pop_back();
            const Node& m = h_.nodes[id];
            if (!overlaps(m.box)) continue;
            // Within one object only front sides touch (below): a back surface skips its own
            // object's clusters (a 100k-piece fanned disc: every piece's box meets every other's).
            if (m.is_cluster()) {
                if (m.object == n.object && (own_back || same_left <= 0)) continue;
                for (int c : m.children) stack.push_back(c);
                continue;
            }
            // Another object's polygon, or a front side of another polygon of the same object (a
            // chair's back resting on its seat: Cycles finds that contact unlit too). Not the
            // back of a neighbouring piece of the same plane (a two-sided fanned n-gon).
            if (m.object == n.object && (own_back || --same_left < 0 || h_.surfaces[size_t(m.surface)].back)) continue;
            if (h_.surfaces[size_t(m.surface)].prim == h_.surfaces[si].prim || dot(m.normal, n.normal) > -1 + 1e-9) continue;
            if (std::fabs(dot(m.poly.v[0] - n.poly.v[0], n.normal)) > tol) continue;
            if (!scene_.objects()[m.object].occluder) continue;
            lights_.contacts[si].push_back(m.surface);
        }
    }, 32);
}

bool Solver::light_in_contact(int surface, const Vec3& p) const { return light_contact(surface, p) >= 0; }

int Solver::light_contact(int surface, const Vec3& p) const {
    if (size_t(surface) >= lights_.contacts.size()) return -1;
    const double tol = 1e-9 * h_.scene_diag;
    for (int t : lights_.contacts[surface]) {
        const Node& m = h_.nodes[h_.surfaces[t].root];
        if (within_edges(m.poly, m.normal, p, tol)) return t;
    }
    return -1;
}

bool Solver::light_corner_in_contact(const Primitive& p, int k) const {
    // Cycles shades each corner inside its own face: at the foot of a box standing on the
    // floor, the floor corners under the box are unlit and those beside it lit. Corners in
    // contact are therefore not averaged with the others (output.cpp).
    if (lights_.contacts.empty() || p.front < 0) return false;
    const Vec3 inside = p.poly.v[k] + (p.poly.centroid() - p.poly.v[k]) * 1e-4;
    return light_in_contact(p.front, inside);
}

void Solver::light_compute(const std::vector<int>& ids) {
    if (ids.empty()) return;
    if (lights_.contacts.size() != h_.surfaces.size()) light_contacts();
    const std::vector<ILight> ls = internal_lights(scene_, h_);
    const double far = 4.0 * h_.scene_diag, lift = 1e-5 * h_.scene_diag;
    if (lights_.rays.size() < h_.nodes.size()) lights_.rays.resize(h_.nodes.size());
    parallel_for(ids.size(), settings_.threads, [&](size_t i) {
        const int id = ids[i];
        const Node& n = h_.nodes[id];
        // Its shadow rays, replayed where a move left the node stale (light_invalidate).
        const bool stale = lights_.have[id] == LightState::kStale;
        LampRayStream rs(*vis_, stale ? &lights_.rays[id] : nullptr, stale ? &lights_.clips : nullptr);
        Rgb sum, lo = Rgb::all(1e300), hi = Rgb::all(-1e300);
        double area = 0, var_max = 0, edge = 0;
        for (int k = 0; k < 4; ++k) {
            const Poly c = n.poly.child(k);
            const double a = c.area();
            Rgb e;
            double var = 0;
            for (const ILight& l : ls) {
                Rng rng(Hierarchy::mix(Hierarchy::mix(settings_.seed ^ l.salt, n.key), uint64_t(k)));
                const bool sky = l.type == LightDesc::Type::Sky;
                const int mm = element_shadow_rays(settings_.rays_per_link, l.type);
                // Stratified over the child along its first coordinate.
                auto where = [&c, mm](int s, Rng& g) { return c.sample((s + g.next()) / mm, g.next()); };
                const Sampled r = estimate(l, where, n.normal, mm, rng, rs, lift, far,
                                           [&](const Vec3& p) { return light_in_contact(n.surface, p); });
                e += r.mean;
                if (sky) var += r.var;
                // A shadow edge of a small light crosses this child (the HR visibility error):
                // its light may be anywhere between none and all of the unoccluded value.
                else if (r.partial) edge = std::max(edge, r.unocc);
            }
            sum += e * a;
            area += a;
            lo = cmin(lo, e);
            hi = cmax(hi, e);
            var_max = std::max(var_max, var);
        }
        lights_.direct[id] = area > 0 ? sum / area : Rgb{};
        // Spread of the children beyond what the sky's noise explains (one sigma of a
        // difference: the sky's occlusion is smooth, noise alone must not refine it to the
        // resolution limit), or a small light's shadow edge inside a child.
        lights_.spread[id] = float(std::max({0.0, (hi - lo).max() - std::sqrt(2.0 * var_max), edge}));
        lights_.have[id] = LightState::kLit;
        lights_.rays[id] = std::move(rs.out);
    }, 8);
}

void Solver::light_initial() {
    // The initial linking judges links by their senders' radiance: without this, surfaces lit
    // only by lamps would look dark to it (their light arrives only with the first sweep) and
    // the first links would be too coarse, leaving the refinement rounds to catch up.
    if (scene_.lights().empty()) return;
    collect_receivers();
    light_refine();
    collect_receivers();
    sweep(false, nullptr);
}

void Solver::light_resize() {
    const size_t nn = h_.nodes.size();
    lights_.direct.resize(nn);
    lights_.spread.resize(nn, 0.f);
    lights_.have.resize(nn, LightState::kNone);
    lights_.split.resize(nn, 0);
}

void Solver::light_walk(const std::vector<char>& link_below, std::vector<int>& lit, std::vector<int>& drop) {
    // Top-down, level by level, as a full solve splits for the light: a node's children are
    // there for the light only if it was split for it and its direct light still varies by
    // more than the threshold. Below a node whose children neither the light nor a link
    // needs nothing is visited, so the splits down there are never evaluated. (Judged
    // bottom-up, a light right above a node's centre kept its children: they agree with each
    // other by symmetry, so a full solve never splits it, but their own children differ.)
    light_resize();
    std::vector<int> level;
    for (const Surface& s : h_.surfaces)
        if (!h_.nodes[s.root].dead) level.push_back(s.root);
    while (!level.empty()) {
        std::vector<int> todo, next;
        for (int id : level)
            if (lights_.split[id] && !h_.nodes[id].children.empty() && lights_.have[id] != LightState::kLit) todo.push_back(id);
        light_compute(todo);
        for (int id : level) {
            const Node& n = h_.nodes[id];
            if (n.children.empty()) continue;
            if (lights_.split[id] && n.rho.max() * lights_.spread[id] > threshold_) {
                lit.push_back(id);
            } else {
                lights_.split[id] = 0;
                if (!link_below[id]) {
                    drop.push_back(id);
                    continue;
                }
            }
            for (int c : n.children) next.push_back(c);
        }
        level.swap(next);
    }
}

std::vector<char> Solver::link_below(const std::vector<char>& referenced) const {
    // Per element: a node strictly below it is referenced. Children have larger ids than
    // their parents (subdivide appends), so one pass from the back sees every child first.
    std::vector<char> below(h_.nodes.size(), 0);
    for (size_t i = h_.nodes.size(); i-- > 0;) {
        const Node& n = h_.nodes[i];
        if (n.dead || n.is_cluster() || n.parent < 0) continue;
        if (referenced[i] || below[i]) below[n.parent] = 1;
    }
    return below;
}

bool Solver::light_coarsen() {
    // After a light moved or changed (or objects moved), elements split only for the old
    // direct light merge back where the new light does not need them, so an incremental
    // update ends with the elements a full solve would make (3.4's un-refinement, for
    // lights). Done before the direct light of the old leaves is recomputed: the merged ones
    // cost no rays.
    std::vector<char> referenced(h_.nodes.size(), 0);
    for (const Link& l : links_)
        if (!l.dead) referenced[l.src] = referenced[l.rcv] = 1;
    std::vector<int> lit, drop;
    light_walk(link_below(referenced), lit, drop);
    for (int id : drop) {
        std::vector<int> stack(h_.nodes[id].children.begin(), h_.nodes[id].children.end());
        while (!stack.empty()) {
            Node& c = h_.nodes[stack.back()];
            lights_.split[stack.back()] = 0;
            stack.pop_back();
            for (int k : c.children) stack.push_back(k);
            c.children.clear();
            c.dead = true;
            std::vector<int>().swap(c.in_links);
            std::vector<int>().swap(c.out_links);
            --stats_.element_nodes;
        }
        h_.nodes[id].children.clear();
    }
    if (!drop.empty()) collect_receivers();
    return !drop.empty();
}

bool Solver::light_refine() {
    if (scene_.lights().empty()) return false;
    if (lights_.recheck) {
        lights_.recheck = false;
        light_coarsen();
    }
    // Leaves whose direct light varies across them more than the threshold split; their
    // children are evaluated at once and split again if needed, so a shadow edge reaches
    // the resolution limit in one round.
    std::vector<int> wave;
    for (int id : leaves_)
        if (size_t(id) < lights_.have.size() && lights_.have[id] == LightState::kLit) wave.push_back(id);
    bool changed = false;
    while (!wave.empty()) {
        std::vector<int> kids;
        for (int id : wave) {
            const Node& n = h_.nodes[id];
            if (n.dead || !n.children.empty()) continue;
            // A shadow's edge splits below the area floor too (may_split_below_floor): a floor
            // leaf across it sends its half-lit average under the object that casts it.
            if (n.rho.max() * lights_.spread[id] <= threshold_ || !(can_split(id) || may_split_below_floor(id))) continue;
            h_.subdivide(id);
            stats_.element_nodes += 4;
            for (int c : h_.nodes[id].children) kids.push_back(c);
            changed = true;
        }
        light_resize();
        for (int c : kids) lights_.split[h_.nodes[c].parent] = 1;
        light_compute(kids);
        wave.swap(kids);
    }
    return changed;
}

void Solver::light_keep(std::vector<int>& refs) {
    // Children made for the direct light are referenced by it (pruning must keep them) while
    // the light still varies across their parent and the parent itself stays; otherwise the
    // split is forgotten and the children go like any unreferenced element.
    std::vector<char> referenced(h_.nodes.size(), 0);
    for (size_t i = 0; i < refs.size() && i < referenced.size(); ++i) referenced[i] = refs[i] > 0;
    std::vector<int> lit, drop;
    light_walk(link_below(referenced), lit, drop);
    for (int id : lit)
        for (int c : h_.nodes[id].children) ++refs[c];
}

std::vector<float> Solver::first_bounce() const {
    // Per element node: emission + rho x the direct light of the lamps, the area mean over its
    // leaves (largest channel). This is the radiance a full solve's first linking judges links
    // by (light_initial's sweep, before any link exists), so the settlements (3.5) it makes
    // then hold for it. The cached direct terms are used as they are: before an update
    // recomputes them they are the old lights'.
    const size_t nn = h_.nodes.size();
    std::vector<Rgb> sum(nn);
    std::vector<double> area(nn, 0.0);
    std::vector<float> out(nn, 0.f);
    for (size_t i = nn; i-- > 0;) {  // children (larger ids) before their parents
        const Node& n = h_.nodes[i];
        if (n.dead || n.is_cluster()) continue;
        if (n.children.empty()) {
            const Rgb d = i < lights_.direct.size() ? lights_.direct[i] : Rgb{};
            sum[i] = (n.emission + n.rho * d) * n.area;
            area[i] = n.area;
        }
        if (area[i] > 0) out[i] = float((sum[i] / area[i]).max());
        if (n.parent >= 0 && !h_.nodes[n.parent].is_cluster()) {
            sum[n.parent] += sum[i];
            area[n.parent] += area[i];
        }
    }
    return out;
}

void Solver::at_first_bounce(const std::function<void()>& judge_links, const std::vector<char>* only) {
    // A full solve of a lit scene makes its first linking on the radiance light_initial's
    // sweep leaves (emission + rho x lamp light, no interreflection yet), and most of its
    // oracle decisions then stand: a settlement (3.5) is never judged again. An update's
    // first judgement of links whose senders' light changed is made on that same radiance,
    // swapped in for it and back; judged on converged radiance instead, links beside a box's
    // foot that a full solve settles were split (0.64 % NRMSE after one light move).
    // `only`: the leaves to swap (per node); the others keep their radiance, and their element
    // ancestors and clusters are averaged again over both.
    const size_t nn = h_.nodes.size();
    // The solved radiance comes back however judge_links ends (a cancel throws).
    struct Saved {
        Hierarchy& h;
        size_t nn;
        std::vector<Rgb> L, lo, hi;
        std::vector<std::array<Rgb, kBins>> S;
        ~Saved() {
            for (size_t i = 0; i < nn; ++i) {
                Node& n = h.nodes[i];
                n.L = L[i], n.Lmin = lo[i], n.Lmax = hi[i], n.S = S[i];
            }
            // Elements split meanwhile inherit their parent's radiance, as subdivide does.
            for (size_t i = nn; i < h.nodes.size(); ++i) {
                Node& n = h.nodes[i];
                if (n.is_cluster() || n.parent < 0) continue;
                n.L = n.Lmin = n.Lmax = h.nodes[n.parent].L;
            }
        }
    } saved{h_, nn, std::vector<Rgb>(nn), std::vector<Rgb>(nn), std::vector<Rgb>(nn),
            std::vector<std::array<Rgb, kBins>>(nn)};
    for (size_t i = 0; i < nn; ++i) {
        const Node& n = h_.nodes[i];
        saved.L[i] = n.L, saved.lo[i] = n.Lmin, saved.hi[i] = n.Lmax, saved.S[i] = n.S;
    }
    for (size_t i = nn; i-- > 0;) {  // children (larger ids) before their parents
        Node& n = h_.nodes[i];
        if (n.dead || n.is_cluster()) continue;
        if (n.children.empty()) {
            if (!only || (i < only->size() && (*only)[i])) n.L = n.Lmin = n.Lmax = n.emission + n.rho * light_direct(int(i));
            continue;
        }
        Rgb sum, mn = Rgb::all(1e300), mx = Rgb::all(-1e300);
        double area = 0;
        for (int c : n.children) {
            const Node& k = h_.nodes[c];
            sum += k.L * k.area;
            area += k.area;
            mn = cmin(mn, k.Lmin);
            mx = cmax(mx, k.Lmax);
        }
        n.L = area > 0 ? sum / area : n.emission;
        n.Lmin = mn;
        n.Lmax = mx;
    }
    pull_up_clusters();
    judge_links();
}

Rgb Solver::leaf_irradiance(int id) const {
    // What push_down gathers for this leaf (gather.cpp), without the reflectance: light
    // arriving through element links on the leaf and its ancestors, and through cluster links
    // above its surface times its own cosine; closure-corrected; plus the direct term.
    const Node& n = h_.nodes[id];
    Rgb acc;
    for (int a = id; a >= 0 && !h_.nodes[a].is_cluster(); a = h_.nodes[a].parent)
        if (!h_.nodes[a].in_links.empty()) acc += h_.nodes[a].G;
    for (int a : h_.ancestors_of_surface(n.surface))
        for (int li : h_.nodes[a].in_links) {
            const Link& l = links_[li];
            double c = -dot(n.normal, l.dir);
            if (c > 0 && h_.holds_pocket(l.src, n.pocket)) acc += l.value * c;  // gather_plan.cpp's rule
        }
    const Rgb own = n.in_links.empty() ? Rgb{} : n.G;
    return closure_gathered(own, acc, n.closure_own, n.closure, n.closure_fill, n.L) + light_direct(id);
}

std::vector<float> Solver::corner_irradiance(int object) const {
    if (object < 0 || object >= int(scene_.objects().size()))
        throw std::out_of_range("unknown object " + std::to_string(object));
    if (settings_.gather_rays > 0) {  // output.cpp: the final gather's points
        std::vector<float> v = output_.corner_irradiance(h_, object);
        if (v.size() == scene_.objects()[size_t(object)].corner_count() * 3) return v;
    }
    return corner_values(object, [this](int id) { return leaf_irradiance(id); });
}

}  // namespace radiosity
